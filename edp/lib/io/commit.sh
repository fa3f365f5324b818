#!/bin/sh
# io/commit.sh -- the one place where a run's files reach its output directory OUT. edp/contact.edp calls it
# from OUT/.staging, its working directory, once every check has passed; edp/run.sh holds OUT's lock.
#   io/commit.sh prepare STEP   restart from $CONTACT_RESTART (DIR): stage DIR's history.csv up to the checkpoint's
#       STEP (checked: the columns of expected_header.txt, rows 0..STEP complete and in order), the checkpoint
#       run.sh copied (restart_checkpoint.txt), and the snapshots up to it that restart_files.txt lists (each must be there)
#   io/commit.sh commit NV NT NBE [3]   check mesh.msh (1 + NV + NT + NBE lines; 3D: mesh.mesh's closing line),
#       remove the earlier run's files that the new run does not replace, move the staged files into OUT
#   io/commit.sh restore   put back the run's files that a restart into OUT itself kept aside (OUT/.restart_kept)
# One line "error: ..." on failure: exit 3 if the restart cannot continue, 7 if a copy or a move fails
# (disk full?). Before the moves, OUT is untouched.
set -u
trap '' INT TERM HUP     # never cut in half: a signal stops the run (edp/run.sh) once the files are moved
out=..
unchanged="the output directory is unchanged"
fail() { echo "error: $2"; exit "$1"; }
run_files="history.csv parameters.txt scene.idp ipopt.opt ipopt.out mesh.msh mesh.mesh foundation.csv summary.txt checkpoint.txt run.pvd"
# the run's files in OUT, a name a line: run_files and the snapshots (-np N's pieces, vonmises_t*_<rank>.vtu, among
# vonmises_t*.vtu); "partial": also what a stopped write leaves (*.part). The one list of commit's and restore's loops.
out_run_files() {
  for f in $run_files "$out"/snapshot_t*.csv "$out"/vonmises_t*.vtu "$out"/vonmises_t*.pvtu "$out"/foundation_t*.vtu; do
    [ ! -e "$out/${f##*/}" ] || echo "${f##*/}"
  done
  [ "${1:-}" != partial ] || for f in "$out"/*.part "$out"/*.part.vtu; do [ ! -e "$f" ] || echo "${f##*/}"; done
}

case "${1:-}" in
prepare)
  step=$2 dir=$CONTACT_RESTART
  awk -F, -v s="$step" -v header_file=expected_header.txt '
    BEGIN { getline want < header_file }
    NR == 1 { if ($0 != want) { bad = "its history.csv has other columns than this run writes (another version, or other -probes)"; exit }
              n = NF; print > "history.csv"; next }
    NR - 2 > s { exit }
    NF != n || $1 != NR - 2 { bad = "its history.csv is incomplete or out of order at line " NR " (step " NR - 2 ")"; exit }
    { print > "history.csv"; last = $1 }
    END { if (bad == "" && last != s) bad = "its history.csv stops at step " (NR > 1 ? last : "none") ", before the checkpoint (step " s ")"
          if (bad != "") { printf "error: -restart %s: %s\n", ENVIRON["CONTACT_RESTART"], bad; exit 3 }
          if (close("history.csv") != 0) exit 7 }' "$dir/history.csv" 2>/dev/null
  status=$?
  [ $status -eq 3 ] && exit 3
  [ $status -eq 0 ] || fail 7 "cannot copy $dir/history.csv into the output directory (disk full?); $unchanged"
  mv -f restart_checkpoint.txt checkpoint.txt || fail 7 "cannot keep the checkpoint of $dir; $unchanged"
  while IFS= read -r f; do
    [ -n "$f" ] || continue
    [ -f "$dir/$f" ] || fail 3 "-restart $dir: its $f is missing (the run wrote it before its checkpoint); $unchanged"
    cp "$dir/$f" . 2>/dev/null || fail 7 "cannot copy $dir/$f (disk full?); $unchanged"
    case $f in *.pvtu)     # -np N's snapshot: its pieces too (io/snapshot_pieces.idp)
      for p in $(sed -n 's/.*<Piece Source="\([^"]*\)".*/\1/p' "$f"); do
        [ -f "$dir/$p" ] || fail 3 "-restart $dir: its $p is missing (a piece of $f, which the run wrote before its checkpoint); $unchanged"
        cp "$dir/$p" . 2>/dev/null || fail 7 "cannot copy $dir/$p (disk full?); $unchanged"
      done ;;
    esac
  done < restart_files.txt
  rm -f expected_header.txt restart_files.txt
  ;;
commit)
  if [ "${5:-2}" = 3 ]; then      # a 3D body's mesh.mesh (medit): complete when its last line is "End"
    [ "$(grep -v '^[[:space:]]*$' mesh.mesh 2>/dev/null | tail -n 1)" = End ] ||
      fail 7 "cannot write mesh.mesh in the output directory (disk full?); $unchanged"
  else
    lines=$(wc -l < mesh.msh 2>/dev/null)
    [ "$lines" = $((1 + $2 + $3 + $4)) ] || fail 7 "cannot write mesh.msh in the output directory (disk full?); $unchanged"
  fi
  # from here on OUT changes: run.sh counts the run as started (history.csv is its own from now)
  : > .committed || fail 7 "cannot write into the staging directory (disk full?); $unchanged"
  # a restart into its own directory: the run's files are kept aside in OUT/.restart_kept until the restart
  # has gone past the run's last row or ends well; edp/run.sh puts them back if it stops before (outputs.md)
  if [ -n "${CONTACT_RESTART:-}" ] && [ "$(cd "$out" && pwd -P)" = "$CONTACT_RESTART" ]; then
    rm -rf "$out/.restart_kept" && mkdir "$out/.restart_kept" || fail 7 "cannot write into the output directory (disk full?)"
    for f in $(out_run_files); do
      mv -f "$out/$f" "$out/.restart_kept/" 2>/dev/null || fail 7 "cannot keep the run's $f aside"
    done
  fi
  for f in $(out_run_files partial); do
    if [ ! -e "$f" ]; then
      rm -f "$out/$f" 2>/dev/null || fail 7 "cannot remove the earlier run's $f from the output directory"
    fi
  done
  for f in *; do
    [ -e "$f" ] || continue
    mv -f "$f" "$out/" 2>/dev/null || fail 7 "cannot move $f into the output directory"
  done
  ;;
restore)      # edp/run.sh, when a restart into OUT itself stopped before it passed the run's last row: OUT's run
              # files are the restart's; remove them and put the kept ones back
  for f in $(out_run_files partial); do rm -f "$out/$f"; done
  for f in "$out/.restart_kept"/* "$out/.restart_kept"/.[!.]*; do
    [ ! -e "$f" ] || mv -f "$f" "$out/" || fail 7 "cannot put the run's ${f##*/} back from $out/.restart_kept"
  done
  ;;
*) fail 1 "usage: io/commit.sh prepare STEP | commit NV NT NBE | restore" ;;
esac
