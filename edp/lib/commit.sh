#!/bin/sh
# commit.sh -- the one place where a run's files reach its output directory OUT.
# edp/contact.edp calls it from OUT/.staging, its working directory, once every
# check has passed; edp/run.sh holds OUT's lock.
#   commit.sh prepare STEP T   restart from $CONTACT_RESTART: copy into the staging
#       directory its history.csv up to the checkpoint's STEP (checked: the columns
#       of expected_header.txt, rows 0..STEP complete and in order), its checkpoint,
#       and its snapshots up to time T
#   commit.sh commit NV NT NBE  check mesh.msh (1 + NV + NT + NBE lines), remove the
#       earlier run's files that the new run does not replace, move the staged files into OUT
# One line "error: ..." on failure: exit 3 if the restart cannot continue, 7 if a
# copy or a move fails (disk full?). Before the moves, OUT is untouched.
set -u
out=..
fail() { echo "error: $2"; exit "$1"; }
run_files="history.csv parameters.txt scene.idp ipopt.opt ipopt.out mesh.msh foundation.csv summary.txt checkpoint.txt"

case "${1:-}" in
prepare)
  step=$2 t=$3 dir=$CONTACT_RESTART
  awk -F, -v s="$step" -v header_file=expected_header.txt -v dir="$dir" '
    BEGIN { getline want < header_file }
    NR == 1 { if ($0 != want) { bad = "its history.csv has other columns than this run writes (another version, or other -probes)"; exit }
              n = NF; print; next }
    NR - 2 > s { exit }
    NF != n || $1 != NR - 2 { bad = "its history.csv row " NR - 1 " is incomplete or out of order"; exit }
    { print; last = $1 }
    END { if (bad == "" && last != s) bad = "its history.csv stops at step " (NR > 1 ? last : "none") ", before the checkpoint (step " s ")"
          if (bad != "") { printf "error: -restart %s: %s\n", dir, bad; exit 3 } }' "$dir/history.csv" > history.csv
  status=$?
  [ $status -eq 3 ] && exit 3
  [ $status -eq 0 ] || fail 7 "cannot copy $dir/history.csv into the output directory (disk full?); the output directory is unchanged"
  rm -f expected_header.txt
  cp "$dir/checkpoint.txt" . || fail 7 "cannot copy $dir/checkpoint.txt (disk full?); the output directory is unchanged"
  for f in "$dir"/snapshot_t*.csv "$dir"/vonmises_t*.vtu; do
    [ -e "$f" ] || continue
    ft=${f##*_t}; ft=${ft%.*}
    awk -v a="$ft" -v b="$t" 'BEGIN { exit !(a + 0 <= b + 1e-9 * (b > 1 ? b : 1)) }' || continue
    cp "$f" . || fail 7 "cannot copy $f (disk full?); the output directory is unchanged"
  done
  ;;
commit)
  lines=$(wc -l < mesh.msh 2>/dev/null)
  [ "$lines" = $((1 + $2 + $3 + $4)) ] || fail 7 "cannot write mesh.msh in the output directory (disk full?); the output directory is unchanged"
  for f in $run_files "$out"/snapshot_t*.csv "$out"/vonmises_t*.vtu "$out"/*.part "$out"/*.part.vtu; do
    f=${f##*/}
    [ -e "$out/$f" ] && [ ! -e "$f" ] && { rm -f "$out/$f" || fail 7 "cannot remove the earlier run's $f"; }
  done
  for f in *; do
    [ -e "$f" ] || continue
    mv -f "$f" "$out/" || fail 7 "cannot move $f into the output directory"
  done
  : > .committed
  ;;
*) fail 1 "usage: commit.sh prepare STEP T | commit NV NT NBE" ;;
esac
