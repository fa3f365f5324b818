#!/usr/bin/env bash
# run.sh SCENE OUT [-key value ...] -- run one simulation of edp/contact.edp.
# Copies edp/scenes/SCENE.idp to OUT/scene.idp (a record of what ran), writes
# OUT/ipopt.opt, and runs FreeFEM in OUT with the plugin and include paths
# Debian's FreeFEM needs. Refuses to overwrite an earlier run unless FORCE=1.
# run.sh SCENE OUT -restart DIR [-key value ...] continues the killed run in
# DIR from DIR/checkpoint.txt with DIR's parameters (options given here win),
# writing into OUT (which may be DIR itself).
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
restart_dir=""
while [ $# -gt 0 ]; do
  if [ "$1" = "-restart" ] && [ $# -ge 2 ]; then
    restart_dir=$2; shift 2
  elif [ "$1" = "-mesh" ] && [ $# -ge 2 ]; then
    m=$2
    case "$m" in /*) ;; *) m="$root/$m" ;; esac
    [ -r "$m" ] || { echo "error: -mesh $2: file missing or unreadable" >&2; exit 3; }
    [ "$(sed -n '1p;2s/ .*//p' "$m" | tr -d '\r' | tr '\n' ' ')" = '$MeshFormat 2.2 ' ] ||
      { echo "error: -mesh $2: not a gmsh MSH 2.2 file (write it with gmsh -2 -format msh22)" >&2; exit 3; }
    args+=(-mesh "$m"); shift 2
  else
    args+=("$1"); shift
  fi
done
if [ -n "$restart_dir" ]; then
  for f in checkpoint.txt parameters.txt history.csv; do
    [ -r "$restart_dir/$f" ] || { echo "error: -restart $restart_dir: no $f there (checkpoints are written every -checkpoint_every steps)" >&2; exit 3; }
  done
  # the killed run's parameters, after the ones given here (the first -key wins)
  while read -r key value; do args+=("$key" "$value"); done < "$restart_dir/parameters.txt"
fi
# the default mesh
if ! printf '%s\n' "${args[@]:-}" | grep -qx -- -mesh; then
  [ -r "$root/meshes/disk.msh" ] || { echo "error: meshes/disk.msh is missing; run make meshes" >&2; exit 3; }
  args+=(-mesh "$root/meshes/disk.msh")
fi

if [ -z "$restart_dir" ] && [ -e "$out/history.csv" ] && [ "${FORCE:-0}" != 1 ]; then
  echo "error: $out already holds a run (history.csv); use FORCE=1 to overwrite it" >&2
  exit 3
fi
mkdir -p "$out" 2>/dev/null && [ -w "$out" ] || { echo "error: output directory $out cannot be written" >&2; exit 3; }
if [ -n "$restart_dir" ]; then
  if [ "$(cd "$restart_dir" && pwd)" != "$(cd "$out" && pwd)" ]; then
    cp "$restart_dir/checkpoint.txt" "$restart_dir/history.csv" "$out/"
  fi
  # keep the header and the complete rows up to the checkpoint's step
  step=$(awk 'NR == 1 { print $1 }' "$out/checkpoint.txt")
  awk -F, -v s="$step" 'NR == 1 { n = NF; print; next } NF == n && $1 <= s' "$out/history.csv" > "$out/history.csv.tmp"
  mv -f "$out/history.csv.tmp" "$out/history.csv"
  args+=(-restart checkpoint.txt)
fi
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
