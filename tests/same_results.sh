#!/usr/bin/env bash
# tests/same_results.sh [REV] [--added-columns A,B] [--added-parameters K,L] -- does the working tree give the same results as REV (default HEAD) on 23
# representative runs: P1/P2, 2D/3D, every material, contact method, solver, scheme and mass, -np 2, a restart?
# Each tree is copied to the same temporary path and run there (parameters.txt records the mesh's path, and
# the checkpoints its checksum), then every file of every run is compared byte for byte, except summary.txt's
# cpu_seconds, IPOPT's ipopt.out (timings) and scene.idp (the scene's text, comments included).
# For a change that must not move a number (a refactor). A change that adds history.csv columns or parameters
# and moves no number names them: history.csv is compared without those columns, parameters.txt without those
# keys' lines, and checkpoint.txt without its header's checksum of parameters.txt (field 18); every other byte the same.
# Exit 0: identical; 1: a difference (each file named); 2: usage. About 5 minutes on 2 cores.
set -uo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
rev=HEAD added_columns="" added_parameters=""
while [ $# -gt 0 ]; do
  case "$1" in
    --added-columns|--added-parameters)
      [ $# -ge 2 ] || { echo "error: $1 needs a comma-separated list" >&2; exit 2; }
      if [ "$1" = --added-columns ]; then added_columns=$2; else added_parameters=$2; fi
      shift 2 ;;
    -*) echo "error: unknown option $1" >&2; exit 2 ;;
    *) rev=$1; shift ;;
  esac
done
git -C "$root" rev-parse --verify -q "$rev^{commit}" > /dev/null || { echo "error: $rev is not a commit of $root" >&2; exit 2; }
work=$(mktemp -d) || exit 2
trap 'rm -rf "$work"' EXIT
runs() {   # TREE OUT: the 23 runs of TREE, made at $work/tree
  rm -rf "$work/tree"
  cp -a "$1" "$work/tree" && rm -rf "$work/tree/results" "$work/tree/.git"
  cd "$work/tree" || exit 2
  # a tree whose serial solves need the plugin (solve/cholmod_columns.cpp) builds it (the working tree's copy has
  # it up to date, a worktree of REV has no build/)
  if [ -f edp/lib/solve/cholmod_columns.cpp ]; then make -s plugins > /dev/null || { echo "error: cannot build the plugin of $1" >&2; exit 2; }; fi
  local o=$2 t=$2/rs
  mkdir -p "$o"
  run() { local name=$1 scene=$2; shift 2
          FORCE=1 edp/run.sh "$scene" "$o/$name" -progress 0 "$@" > "$o/$name.log" 2>&1; echo "$name $?" >> "$o/status.txt"; }
  run t1 test1 -T 12 -snapshots 11.4
  run t2 test2 -T 12 -snapshots 11.4
  run t1p2 test1 -T 12 -order 2 -snapshots 11.4
  run t1svk test1 -T 12 -material svk -snapshots 11.4
  run t1nh test1 -T 12 -material neohookean -snapshots 11.4
  run t1svkp2 test1 -T 11 -material svk -order 2
  run t1pen test1 -T 12 -contact penalty -snapshots 11.4
  run t1nit test1 -T 12 -contact nitsche -snapshots 11.4
  run t1gauss test1 -T 12 -contact penalty -contact_quadrature gauss
  run t1as test1 -T 12 -solver activeset
  run t1lump test1 -T 12 -mass lumped
  run t1sing test1 -T 12 -mass singular
  run t1nm test1 -T 12 -scheme newmark -newmark_gamma 0.6
  run t1vv test1 -T 10 -dt 0.01 -scheme verlet -contact penalty -snapshots none
  run wave wave -T 10
  run cant cantilever -T 6 -material svk -snapshots 5
  run ball ball -T 10 -snapshots 10
  run ballnh ball -T 10 -material neohookean -snapshots none
  run ballpen ball -T 10 -contact penalty -snapshots none
  run ballnp2 ball -T 10 -np 2 -solver activeset -snapshots 10
  run t1np2 test1 -T 12 -np 2 -solver activeset -snapshots 11.4
  run ballmov ball_moving -T 10 -snapshots none
  run rs test1 -T 6 -snapshots 5 -checkpoint_every 50
  run rs test1 -restart "$t" -T 12 -snapshots 5,11.4
  cd "$root" || exit 2
}
echo "same_results: the runs of $rev"
git -C "$root" worktree add -q --detach "$work/before_tree" "$rev" || exit 2
for m in "$root"/meshes/*.msh; do [ -e "$work/before_tree/meshes/${m##*/}" ] || cp "$m" "$work/before_tree/meshes/"; done
runs "$work/before_tree" "$work/before"
git -C "$root" worktree remove --force "$work/before_tree"
echo "same_results: the runs of the working tree"
runs "$root" "$work/after"
# a file as compared: without the added columns (history.csv), the added keys (parameters.txt), the header's
# checksum of parameters.txt (checkpoint.txt)
shown() {
  case "${1##*/}" in
    history.csv) awk -F, -v drop=",$added_columns," 'BEGIN { OFS = "," }
        NR == 1 { for (i = 1; i <= NF; i++) keep[i] = (index(drop, "," $i ",") == 0) }
        { line = ""; n = 0; for (i = 1; i <= NF; i++) if (keep[i]) line = line (n++ ? "," : "") $i; print line }' "$1" ;;
    parameters.txt) awk -v drop=",$added_parameters," '{ k = $1; sub(/^-/, "", k) } index(drop, "," k ",") == 0' "$1" ;;
    checkpoint.txt) if [ -n "$added_parameters" ]; then awk 'NR == 1 { $18 = "-" } { print }' "$1"; else cat "$1"; fi ;;
    *) cat "$1" ;;
  esac
}
bad=0
cmp -s "$work/before/status.txt" "$work/after/status.txt" || { echo "exit statuses differ:"; diff "$work/before/status.txt" "$work/after/status.txt"; bad=1; }
for d in "$work"/before/*/; do
  n=$(basename "$d")
  [ "$(cd "$d" && ls -A)" = "$(cd "$work/after/$n" 2>/dev/null && ls -A)" ] || { echo "$n: the files differ"; bad=1; continue; }
  for f in "$d"*; do
    g=${f##*/}
    case "$g" in
      ipopt.out | scene.idp) ;;
      summary.txt) cmp -s <(grep -v '^cpu_seconds' "$f") <(grep -v '^cpu_seconds' "$work/after/$n/$g") || { echo "$n/$g differs"; bad=1; } ;;
      *) cmp -s <(shown "$f") <(shown "$work/after/$n/$g") || { echo "$n/$g differs"; bad=1; } ;;
    esac
  done
done
if [ $bad = 0 ]; then echo "same_results: $(ls -d "$work"/before/*/ | wc -l) runs byte-identical to $rev"; else echo "same_results: NOT the same as $rev"; fi
exit $bad
