#!/usr/bin/env bash
# run.sh SCENE OUT [-key value ...] -- run one simulation of edp/contact.edp.
# Copies edp/scenes/SCENE.idp to OUT/scene.idp (a record of what ran), writes
# OUT/ipopt.opt, and runs FreeFEM in OUT with the plugin and include paths
# Debian's FreeFEM needs. Refuses to overwrite an earlier run unless FORCE=1.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(dirname "$here")
if [ $# -lt 2 ]; then
  echo "usage: $0 SCENE OUT [-key value ...]   (scenes: $(cd "$here/scenes" && ls *.idp | sed 's/\.idp$//' | tr '\n' ' '))" >&2
  exit 2
fi
scene=$1 out=$2
shift 2
scene_file="$here/scenes/$scene.idp"
[ -f "$scene_file" ] || { echo "error: no scene '$scene' (edp/scenes/$scene.idp); see make scenes" >&2; exit 3; }

# Relative -mesh paths are relative to the repository root, as in the Makefile.
args=()
while [ $# -gt 0 ]; do
  if [ "$1" = "-mesh" ] && [ $# -ge 2 ]; then
    m=$2
    case "$m" in /*) ;; *) m="$root/$m" ;; esac
    [ -r "$m" ] || { echo "error: -mesh $2: file missing or unreadable" >&2; exit 3; }
    args+=(-mesh "$m"); shift 2
  else
    args+=("$1"); shift
  fi
done
# the default mesh
if ! printf '%s\n' "${args[@]:-}" | grep -qx -- -mesh; then
  [ -r "$root/meshes/disk.msh" ] || { echo "error: meshes/disk.msh is missing; run make meshes" >&2; exit 3; }
  args+=(-mesh "$root/meshes/disk.msh")
fi

if [ -e "$out/history.csv" ] && [ "${FORCE:-0}" != 1 ]; then
  echo "error: $out already holds a run (history.csv); use FORCE=1 to overwrite it" >&2
  exit 3
fi
mkdir -p "$out" 2>/dev/null && [ -w "$out" ] || { echo "error: output directory $out cannot be written" >&2; exit 3; }
cp "$scene_file" "$out/scene.idp"
# IPOPT reads ipopt.opt from the working directory; its options override the script's.
cat > "$out/ipopt.opt" <<'OPT'
# no banner
sb yes
# keep C x <= g exactly (the default 1e-8 relaxation lets the body sink ~3e-8 into the foundation)
bound_relax_factor 0
OPT

export FF_LOADPATH=/usr/lib/freefem++
export FF_INCLUDEPATH="$(cd "$out" && pwd);/usr/include/freefem++/idp"
cd "$out"
# FreeFEM writes everything to stdout: keep its "error:" lines (to stderr) and
# our own output, drop IPOPT's blank lines and FreeFEM's exit trace; on a
# terminal the progress line is rewritten in place.
tty=0; [ -t 1 ] && tty=1
FreeFem++-nw -nw -ns -v 0 "$here/contact.edp" "${args[@]}" | awk -v tty=$tty '
  /^error: / { print > "/dev/stderr"; fflush("/dev/stderr"); next }
  /^$/ || /^  current line = / || /^ call .* at  line / || /^exit\(/ || /^ err code / { next }
  /^progress / { sub(/^progress /, "");
                 if (tty) { printf "\r%s   ", $0; pending = 1 } else if (++np % 10 == 0) print;
                 fflush(); next }
  { if (pending) { printf "\n"; pending = 0 } print; fflush() }
  END { if (pending) printf "\n" }'
