# io/check_reached.awk -- a restart into its own directory must not undo what the run already wrote
# (io/restart.idp): it never shortens the run, nor drops a snapshot the run wrote after its checkpoint.
# usage: CONTACT_RESTART=DIR awk -F, -v steps=N -v T=T -v snapshot=K -v snapshot_t=T -v vtu=K -v vtu_t=T \
#            -f io/check_reached.awk DIR/history.csv
#   steps, T: the restart's last step and its time; snapshot (vtu): the first step after the checkpoint where
#   the run's -snapshots (-vtk 1) wrote a file that the restart would not write again, or -1; _t: its time.
# The run reached the last complete row of its history.csv (step R); it finished if it wrote summary.txt.
# Prints one line "error: -restart DIR: ..." and exits 3 if the restart would drop any of it.
BEGIN { name = ENVIRON["CONTACT_RESTART"] }     # (DIR from the environment: -v would read a '\' in it as an escape)
function fail(msg) { printf "error: -restart %s: %s\n", name, msg; exit 3 }
NR == 1 { n = NF; next }
NF == n && $1 ~ /^[0-9]+$/ { reached = $1 + 0; t = sprintf("%.9f", $2); sub(/0+$/, "", t); sub(/\.$/, "", t) }
END {
  finished = (getline line < (name "/summary.txt")) > 0
  if (finished && steps <= reached)
    fail("the run already reached step " reached " (t = " t "); give a -T larger than " t " to extend it")
  if (steps < reached)
    fail("its history.csv holds steps up to " reached " (t = " t "), beyond -T " T "; a restart never "\
         "shortens its run: give a -T of at least " t " (or restart into another directory)")
  if (snapshot >= 0 && snapshot <= reached)
    fail("-snapshots leaves out t = " snapshot_t ", which the run wrote (snapshot_t" snapshot_t ".csv); a restart never "\
         "removes its run's files: list it too (a restart without -snapshots keeps the run's list)")
  if (vtu >= 0 && vtu <= reached)
    fail("-vtk 0 would remove the .vtu files the run wrote from t = " vtu_t " on; a restart never removes its run's files: "\
         "leave out -vtk 0")
}
