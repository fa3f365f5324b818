#!/usr/bin/env bash
# run.sh SCENE OUT [-key value ...] -- launches one simulation of edp/contact.edp into OUT: the lock, the
#   staging, compiled.idp, the paths, FreeFem++ (or mpirun), the exit status. SCENE is a name in edp/scenes/
#   or the path of a scene file (.idp); -restart DIR continues the run in DIR from its last checkpoint
#   (only -T and output options may change); -np N runs on N processes, its solves with A on ffddm (docs/parallel.md).
# OUT changes only once the new run is under way (docs/outputs.md): a lock on OUT/.lock; an earlier run is
#   replaced only with FORCE=1 (or by its own restart); FreeFEM checks everything in OUT/.staging, then
#   edp/lib/io/commit.sh moves its first files into OUT.
# Exit statuses (docs/errors.md): 0 done, 1 unexpected FreeFEM error (a bug), 2 usage, 3 refused before the
#   first step, 4 a step failed, 5 factorisation, 6 the run fails its own audit (a bug), 7 a write failed, 8 out of memory; 128 + N after signal N (SIGTERM, SIGINT,
#   SIGHUP: run.sh stops FreeFEM first, then dies of the signal; one sent to FreeFEM itself is named).
set -uo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(dirname "$here")
err() { echo "error: $1" >&2; exit "${2:-3}"; }

if [ $# -lt 2 ]; then
  echo "usage: $0 SCENE OUT [-key value ...]   (scenes: $(cd "$here/scenes" && ls *.idp | sed 's/\.idp$//' | tr '\n' ' '))" >&2
  exit 2
fi
scene=$1 out=$2 out_arg=$2
shift 2
case "$scene" in
  */* | *.idp)
    [ -f "$scene" ] || err "scene file $scene not found"
    scene_file=$(cd "$(dirname "$scene")" && pwd)/$(basename "$scene") scene_name=$(basename "$scene" .idp) ;;
  *)
    scene_file=$here/scenes/$scene.idp scene_name=$scene
    [ -f "$scene_file" ] || err "no scene '$scene' (edp/scenes/$scene.idp); see make scenes" ;;
esac
[[ "$scene_name" =~ ^[A-Za-z0-9_.-]+$ ]] || err "the scene name '$scene_name' must be letters, digits, '_', '.' or '-'"
[ -n "$out" ] || err "OUT is empty"

args=()
restart_dir=""
np=""
while [ $# -gt 0 ]; do
  if [ "$1" = "-restart" ]; then
    [ $# -ge 2 ] && [ -n "$2" ] || err "-restart needs the directory of the run to continue"
    [ -z "$restart_dir" ] || err "-restart is given twice"
    restart_dir=$2
    shift 2
  elif [ "$1" = "-np" ]; then
    [ $# -ge 2 ] || err "-np needs the number of processes"
    [ -z "$np" ] || err "-np is given twice"
    [[ "$2" =~ ^[0-9]+$ ]] && [ "${#2}" -le 4 ] && [ "$2" -ge 1 ] && [ "$2" -le 1024 ] ||
      err "-np must be a whole number of processes from 1 to 1024; got '$2'"
    np=$((10#$2))
    shift 2
  else
    args+=("$1")
    shift
  fi
done
# -np N: FreeFEM's MPI build, Open MPI's mpirun and FreeFEM's ffddm (Debian's freefem++ and libfreefem++-dev)
if [ -n "$np" ]; then
  for tool in mpirun FreeFem++-mpi; do
    command -v $tool >/dev/null || err "-np needs $tool (FreeFEM's MPI build with Open MPI; Debian: apt-get install freefem++ openmpi-bin)"
  done
  [ -r /usr/include/freefem++/idp/ffddm.idp ] ||
    err "-np needs FreeFEM's ffddm (/usr/include/freefem++/idp/ffddm.idp; Debian: apt-get install libfreefem++-dev)"
fi
if [ -n "$restart_dir" ]; then
  [ -d "$restart_dir" ] || err "-restart $restart_dir: no such directory"
  for f in checkpoint.txt parameters.txt history.csv scene.idp; do
    [ -r "$restart_dir/$f" ] || err "-restart $restart_dir: no $f there (checkpoints are written every -checkpoint_every steps)"
  done
  restart_dir=$(cd "$restart_dir" && pwd -P)
  scene_file=$restart_dir/scene.idp     # the scene that ran, even if edp/scenes has changed since
fi

# ---- OUT: created if need be (and removed again if the run never starts), locked, staged
created=0
if [ ! -d "$out" ]; then
  mkdir -p "$out" 2>/dev/null || err "output directory $out cannot be created"
  created=1
fi
[ -w "$out" ] || err "output directory $out cannot be written"
out=$(cd "$out" && pwd -P)
stage=$out/.staging
lock_holder() { head -c 200 "$1/.lock" 2>/dev/null | tr -d '\n'; }
{ exec 9>>"$out/.lock"; } 2>/dev/null || err "output directory $out cannot be written"
if ! flock -n 9; then
  holder=$(lock_holder "$out")
  [ -n "$holder" ] || err "$out is in use by another run that is starting or ending (it has not named itself); try again in a moment"
  err "$out is in use by another run ($holder); wait for it to end or stop it"
fi
# the lock must be the file that is there now (a refused run may just have removed a directory it created)
[ "$(stat -L -c %d:%i /dev/fd/9)" = "$(stat -c %d:%i "$out/.lock" 2>/dev/null)" ] ||
  err "$out is being created or removed by another run; try again"
stale=$(lock_holder "$out")
errfile=$(mktemp 2>/dev/null) || err "cannot create a temporary file (is /tmp full?)" 7
cleanup() {
  local committed=0
  [ -e "$stage/.committed" ] && committed=1
  [ -z "${choices_pid:-}" ] || { kill -TERM "$choices_pid" 2>/dev/null; wait "$choices_pid" 2>/dev/null; }
  rm -f "$errfile" "$errfile.stop" "$errfile.pid" "$errfile.status"
  rm -rf "$stage"
  if [ $committed = 1 ] || [ "$created" = 0 ]; then
    : > "$out/.lock"
  else                               # created here and never started: leave no trace
    rm -f "$out/.lock"
    rmdir "$out" 2>/dev/null
  fi
}
trap cleanup EXIT
# SIGTERM, SIGINT or SIGHUP: before FreeFEM starts, run.sh cleans up and dies of the signal (128 + its number);
# once it runs, FreeFEM is stopped first (below)
die_of() { cleanup; trap - EXIT "$1"; kill -s "$1" $$; }
for sig in TERM INT HUP; do trap "die_of $sig" $sig; done
printf 'pid %s, started %s: run.sh %s %s' "$$" "$(date '+%Y-%m-%d %H:%M:%S')" "$scene" "$out_arg" > "$out/.lock" ||
  err "cannot write into $out (disk full?)" 7
[ -z "$stale" ] || echo "note: $out was left by a run that was killed ($stale); taking it over"

same_dir=0
[ "$restart_dir" = "$out" ] && same_dir=1
if [ -e "$out/history.csv" ] && [ "${FORCE:-0}" != 1 ] && [ $same_dir = 0 ]; then
  err "$out already holds a run (history.csv); use FORCE=1 to replace it, or another OUT"
fi
# a run restarted into another OUT must not be running: its lock too
if [ -n "$restart_dir" ] && [ $same_dir = 0 ] && { exec 8>>"$restart_dir/.lock"; } 2>/dev/null; then
  flock -n 8 || err "-restart $restart_dir: that run is still going ($(lock_holder "$restart_dir")); wait for it to end or stop it"
fi
rm -rf "$stage"
{ mkdir "$stage" && cp "$scene_file" "$stage/scene.idp"; } 2>/dev/null || err "cannot write into $out (disk full?)" 7
if [ -n "$restart_dir" ]; then   # one copy of the checkpoint is checked, read and kept
  cp "$restart_dir/checkpoint.txt" "$stage/restart_checkpoint.txt" 2>/dev/null || err "cannot write into $out (disk full?)" 7
fi
# FreeFEM's environment. FreeFEM splits FF_INCLUDEPATH at ';' and misreads a '\' in it, so its entries hold no
# path of the user's: they are relative to the staging directory, FreeFEM's working directory, where .edp is a link
# to edp/ (the staged compiled.idp includes lib/...)
# .plugins is a link to build/plugins, where make builds the serial solves' plugin (solve/cholmod_columns.cpp).
export FF_LOADPATH="/usr/lib/freefem++;.plugins"
{ ln -s "$here" "$stage/.edp" && ln -s "$root/build/plugins" "$stage/.plugins"; } 2>/dev/null ||
  err "cannot create a symbolic link in $out (disk full, or a file system without links?)" 7
export FF_INCLUDEPATH=".;.edp;/usr/include/freefem++/idp"
export CONTACT_ROOT=$root CONTACT_CWD=$PWD CONTACT_SCENE=$scene_name CONTACT_RESTART=$restart_dir
# -np N: a process's status line carries this run's own tag, so that a line a scene prints is never taken for one
export CONTACT_STATUS_TAG=$(od -An -N6 -tx1 /dev/urandom 2>/dev/null | tr -d ' \n')
[ -n "$CONTACT_STATUS_TAG" ] || CONTACT_STATUS_TAG=$$$RANDOM$RANDOM
# compiled.idp: the one place of what FreeFEM compiles. contact.edp includes it three times: first the order,
# the processes' file and the dimension's; then (once it defines compiledSectionSolves) the solves with A for
# those processes and the dimension's kinematics; then (compiledSectionMaterial) the material's file for that
# dimension.
write_compiled() {   # ORDER MATERIAL MATERIAL_FILE DIMENSION PROCESSES
  local fe=P1 solves=direct
  [ "$1" = 2 ] && fe=P2
  [ "$5" = mpi ] && solves=ffddm_solve
  printf '%s\n' "// written by edp/run.sh: what the driver is compiled for (-order, -material, the mesh's dimension, -np)" \
    "IFMACRO(!compiledSectionSolves)" "int compiledOrder = $1;" "func Pk = $fe;" "string compiledMaterial = \"$2\";" \
    "include \"lib/run/processes_$5.idp\"" "include \"lib/dimension/$4d.idp\"" "ENDIFMACRO" \
    "IFMACRO(compiledSectionSolves)" "IFMACRO(!compiledSectionMaterial)" "include \"lib/solve/$solves.idp\"" \
    "include \"lib/dimension/kinematics_$4d.idp\"" "ENDIFMACRO" "ENDIFMACRO" \
    "IFMACRO(compiledSectionMaterial)" "include \"lib/$3\"" "ENDIFMACRO" \
    > "$stage/compiled.idp" 2>/dev/null || err "cannot write into $out (disk full?)" 7
}
write_compiled 1 linear material/linear.idp 2 serial
# (in the background, so that a signal to run.sh stops it at once: cleanup stops it)
(cd "$stage" && exec FreeFem++-nw -nw -ns -v 0 "$here/lib/run/choices.edp" "${args[@]}") > "$stage/.choices" 2>/dev/null &
choices_pid=$!
wait $choices_pid
chosen=$(cat "$stage/.choices" 2>/dev/null)
rm -f "$stage/.choices"
choices_pid=""
order=1 material=linear mesh_file=$root/meshes/disk.msh
if grep -q '^choice-mesh ' <<< "$chosen"; then
  order=$(sed -n 's/^choice-order //p' <<< "$chosen" | tail -n 1)
  material=$(sed -n 's/^choice-material //p' <<< "$chosen" | tail -n 1)
  mesh_file=$(sed -n 's/^choice-mesh //p' <<< "$chosen" | tail -n 1)
fi
[[ "$order" =~ ^[0-9]{1,9}$ ]] || order=0     # (the driver refuses it)
# the dimension is the mesh's: a gmsh mesh with tetrahedra is a 3D body (one that is not there: 2D here, and
# the driver names what is wrong with it)
dimension=2
[ -r "$mesh_file" ] && awk -f "$here/lib/body/mesh_volumes.awk" "$mesh_file" 2>/dev/null && dimension=3
# a restart continues the run's body: a -mesh of another dimension is refused here, by its name, before the driver
# (compiled for that dimension) could trip over what the run's parameters.txt records
if [ -n "$restart_dir" ]; then
  run_dimension=2
  [ -e "$restart_dir/mesh.mesh" ] && run_dimension=3
  if [ "$dimension" != "$run_dimension" ]; then
    run_mesh=$(sed -n 's/^-mesh //p' "$restart_dir/parameters.txt" | head -n 1)
    err "-restart: -mesh $mesh_file (a ${dimension}D body) differs from the run's -mesh $run_mesh (a ${run_dimension}D body); a restart continues the same discrete problem and may change only -T and the output options"
  fi
fi
# -np N: ffddm needs at least 50 mesh vertices a process (body/partition.idp says why, and checks it again on the mesh it
# loads); checked here on the file's nodes, before mpirun starts any process
if [ -n "$np" ] && [ "$np" -gt 1 ] && [ -r "$mesh_file" ]; then
  mesh_nodes=$(awk '{ sub(/\r$/, "") } /^\$Nodes$/ { getline; sub(/\r$/, ""); print (NF >= 2 ? $2 : $1); exit }' "$mesh_file" 2>/dev/null)
  if [[ "$mesh_nodes" =~ ^[0-9]{1,12}$ ]] && (( mesh_nodes < 50 * np )); then
    advice="run it without -np"
    (( mesh_nodes >= 100 )) && advice="use -np $((mesh_nodes / 50)) or fewer"
    err "-np $np needs at least 50 mesh vertices per process (ffddm's subdomains and their overlap), and the mesh $mesh_file has $mesh_nodes: $advice"
  fi
fi
# the materials: edp/lib/material/materials.txt, one line each (NAME, then how this error names it);
# -material NAME is edp/lib/material/NAME.idp
materials=$here/lib/material/materials.txt
if ! MATERIAL=$material awk '!/^#/ && NF && $1 == ENVIRON["MATERIAL"] { found = 1 } END { exit !found }' "$materials"; then
  choices=$(awk '!/^#/ && NF { e = $1; if (NF > 1) { t = $0; sub(/^[ \t]*[^ \t]+[ \t]+/, "", t); e = e " (" t ")" } a[n++] = e }
                 END { s = a[0]; for (i = 1; i < n; i++) s = s (i == n - 1 ? " or " : ", ") a[i]; print s }' "$materials")
  err "-material must be $choices; got '$material'"
fi
# 3D: a material's 3D kinematics live in material/NAME_3d.idp (the linear one's in the dimension files)
material_file=material/$material.idp
if [ "$dimension" = 3 ] && [ "$material" != linear ]; then
  material_file=material/${material}_3d.idp
  [ -f "$here/lib/$material_file" ] ||
    err "-material $material is not supported on a 3D body yet (the mesh $mesh_file has tetrahedra): use -material linear or neohookean"
fi
[ -f "$here/lib/material/$material.idp" ] || err "edp/lib/material/materials.txt lists -material $material, but edp/lib/material/$material.idp is missing" 1
processes=serial
[ -n "$np" ] && processes=mpi
# the solves with A go through CHOLMOD's factor in the plugin make builds (solve/direct.idp; -np: the subdomains'
# factors, solve/ffddm_solve.idp)
for plugin in cholmod_columns body_contact; do
  [ -f "$root/build/plugins/$plugin.so" ] ||
    err "$root/build/plugins/$plugin.so is missing: build it with 'make plugins' (it needs g++ and libsuitesparse-dev; 'make deps' installs them)" 1
done
write_compiled "$order" "$material" "$material_file" "$dimension" "$processes"
# IPOPT reads ipopt.opt from its working directory (the driver removes it when the run's -solver is not ipopt)
cp "$here/lib/contact/ipopt.opt" "$stage/ipopt.opt" 2>/dev/null || err "cannot write into $out (disk full?)" 7

# ---- FreeFEM, in the staging directory (io/commit.sh moves it on into OUT)
if [ -n "$np" ]; then
  # -np N: FreeFem++-mpi's plugins, and ffddm's files as Debian can load them
  export FF_LOADPATH="/usr/lib/freefem++/mpi;.plugins"
  sh "$here/lib/solve/ffddm_without_mumps.sh" "$stage/.ffddm" 2>/dev/null || err "cannot write into $out (disk full?)" 7
  export FF_INCLUDEPATH=".;.ffddm;.edp;/usr/include/freefem++/idp"
  # Open MPI refuses to start as root without these (CI runs as root)
  export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
fi
# FreeFEM's output goes through edp/lib/run/output_filter.awk (the driver's lines; one error line).
tty=0
[ -t 1 ] && tty=1
# CONTACT_DEBUG=1 also shows FreeFEM's raw output on stderr (for developers).
raw=/dev/null
[ -n "${CONTACT_DEBUG:-}" ] && raw=/dev/stderr
# -np N: a process that stops alone leaves the others waiting in MPI for ever (FreeFEM's exit waits in
# MPI_Finalize): once the filter has seen its status line or a crash (it writes $errfile.stop), the others get
# 5 s to end too, then mpirun is stopped, and the status is the one the process gave (docs/parallel.md).
# The pid of FreeFEM (or mpirun) goes into $errfile.pid, for run.sh to pass a signal on.
run_freefem() {
  if [ -z "$np" ]; then
    (cd "$stage" && exec FreeFem++-nw -nw -ns -v 0 "$here/contact.edp" "${args[@]}") &
  else
    (cd "$stage" && exec mpirun --oversubscribe --tag-output -np "$np" FreeFem++-mpi -nw -ns -v 0 "$here/contact.edp" "${args[@]}") &
  fi
  local job=$! since=""
  echo $job > "$errfile.pid"
  while [ -n "$np" ] && kill -0 $job 2>/dev/null; do
    if [ -e "$errfile.stop" ]; then
      [ -n "$since" ] || since=$SECONDS
      if [ $((SECONDS - since)) -ge 5 ]; then
        kill -TERM $job 2>/dev/null
        for _ in 1 2 3 4 5 6 7 8 9 10; do kill -0 $job 2>/dev/null || break; sleep 0.2; done
        pkill -KILL -P $job 2>/dev/null
        kill -KILL $job 2>/dev/null
        break
      fi
    fi
    sleep 0.2
  done
  wait $job
}
# (mawk, Debian's awk, reads a pipe in blocks unless told to read it line by line: the watchdog and the
# progress line need each line as it comes)
awk_lines=()
awk -W version 2>/dev/null | grep -q mawk && awk_lines=(-W interactive)
# (run_freefem's shell reports a crash of FreeFEM, such as a segmentation fault, into the pipe.)
# The pipeline runs in the background, so that a signal to run.sh is handled at once (a shell runs its traps only
# between commands): FreeFEM (or mpirun, which stops every process) is sent SIGTERM, and run.sh waits for it to
# end (SIGKILL after 10 s), then dies of the signal it was sent, after the clean-up below.
caught="" stopped_at=""
stop_freefem() {
  local pid
  caught=${caught:-$1}
  [ -z "$stopped_at" ] && pid=$(cat "$errfile.pid" 2>/dev/null) && [ -n "$pid" ] || return 0
  kill -TERM "$pid" 2>/dev/null
  # (-np N: its processes too; mpirun takes about a second to stop them, in which they make a hundred steps)
  [ -z "$np" ] || pkill -TERM -P "$pid" 2>/dev/null
  stopped_at=$SECONDS
}
for sig in TERM INT HUP; do trap "stop_freefem $sig" $sig; done
# (awk -v reads a '\' as the start of an escape: the scene's path has each doubled)
{ run_freefem 2>&1 | tee "$raw" | awk "${awk_lines[@]}" -v tty=$tty -v tagged=$([ -n "$np" ] && echo 1 || echo 0) -v statustag="$CONTACT_STATUS_TAG" \
    -v scene="${scene_file//\\/\\\\}" -v errfile="$errfile" -f "$here/lib/run/output_filter.awk"
  echo "${PIPESTATUS[@]}" > "$errfile.status"; } &
pipeline=$!
while kill -0 $pipeline 2>/dev/null; do
  if [ -z "$caught" ]; then wait $pipeline; continue; fi     # (a trapped signal ends the wait)
  stop_freefem "$caught"
  if [ -n "$stopped_at" ] && [ $((SECONDS - stopped_at)) -ge 10 ] && pid=$(cat "$errfile.pid"); then
    pkill -KILL -P "$pid" 2>/dev/null
    kill -KILL "$pid" 2>/dev/null
  fi
  sleep 0.2
done
wait $pipeline 2>/dev/null
{ read -r -a status < "$errfile.status"; } 2>/dev/null     # (missing when a signal to the process group ended the pipeline's shell too)
rc=${status[0]:-143} filter=${status[2]:-143}
# A run stopped mid-row (a failed write, a signal) leaves part of a row: history.csv keeps the complete ones.
keep_complete_rows() {
  if [ -e "$stage/.committed" ] && [ -s "$out/history.csv" ] && [ -n "$(tail -c 1 "$out/history.csv")" ]; then
    partial=$(tail -n 1 "$out/history.csv" | wc -c)
    truncate -s $(($(stat -c %s "$out/history.csv") - partial)) "$out/history.csv"
  fi
}
# A restart into its own directory kept the run's files aside (io/commit.sh): if it stopped before it went past the
# run's last row, they are put back whole (the restart's own files removed); otherwise its history supersedes them.
settle_kept() {
  local kept=$out/.restart_kept
  [ -d "$kept" ] || return 0
  if [ "$1" != 0 ] && [ "$(wc -l < "$out/history.csv" 2>/dev/null || echo 0)" -le "$(wc -l < "$kept/history.csv" 2>/dev/null || echo 0)" ]; then
    (cd "$stage" && sh "$here/lib/io/commit.sh" restore) >&2 || return 0     # (its error line; the kept files stay)
    echo "note: the restart stopped before it passed the run's last row: $out_arg holds the run as it was before it"
  fi
  rm -rf "$kept"
}
# run.sh was sent a signal, and FreeFEM has ended: no line of its own (the caller sent it)
# (... unless the run had reached T: then it is complete, as below)
if [ -n "$caught" ] && [ "$rc" = 0 ] && [ -e "$stage/.committed" ] && [ -s "$out/summary.txt" ]; then
  echo "note: edp/run.sh was sent SIG$caught after the run reached T; the run is complete (its closing warning: lines, if any, may be missing)"
  settle_kept 0
  exit 0
fi
[ -z "$caught" ] || { keep_complete_rows; settle_kept 1; die_of "$caught"; }
# -np N: the status a process gave when it stopped (the others may have been stopped for it)
given=""
if [ -s "$errfile.stop" ]; then
  given=$(head -n 1 "$errfile.stop")
  case "$given" in
    3 | 4 | 5 | 7 | 8) rc=$given ;;
    crash) [ "$rc" = 0 ] && rc=1 ;;
  esac
fi
rm -f "$errfile.stop"
# a signal sent to FreeFEM itself (or to mpirun), not to run.sh
signal_name=""
if [ -z "$given" ] && [ "$filter" = 0 ]; then
  case "$rc" in
    129) signal_name="SIGHUP from outside edp/run.sh" ;; 130) signal_name="SIGINT from outside edp/run.sh" ;;
    137) signal_name="SIGKILL from outside edp/run.sh (by hand, or by the kernel when memory ran out)" ;;
    143) signal_name="SIGTERM from outside edp/run.sh" ;;
  esac
  # (mpirun itself, sent SIGTERM or SIGINT, stops every process and exits 1 without a word)
  [ -n "$np" ] && [ "$rc" = 1 ] && [ ! -s "$errfile" ] &&
    signal_name="a signal to mpirun from outside edp/run.sh (mpirun stopped with status 1 and no process reported an error)"
fi
# ... after the run reached T: it is complete (mpirun, sent a signal, stops its processes a second later)
if [ -n "$signal_name" ] && [ -e "$stage/.committed" ] && [ -s "$out/summary.txt" ]; then
  echo "note: FreeFEM was killed by $signal_name after the run reached T; the run is complete (its closing warning: lines, if any, may be missing)"
  rc=0
fi
# a per-process memory limit (ulimit -d or -v, prlimit --data or --as), for the out-of-memory line below
memory_limit=""
for flag in d v; do
  kib=$(ulimit -$flag 2>/dev/null)
  case "$kib" in '' | unlimited) ;; *) memory_limit="${memory_limit:+$memory_limit, }$((kib / 1024)) MiB (ulimit -$flag)" ;; esac
done
memory_said=""      # (FreeFEM's or CHOLMOD's own words)
grep -qiE "out of memory|bad_alloc|cannot allocate memory" "$errfile" 2>/dev/null && memory_said=$(head -c 160 "$errfile")
case "$rc" in
  0 | 3 | 4 | 5 | 7) exit_status=$rc ;;
  *) if [ -n "$signal_name" ]; then
       where="before the run started; $out_arg is unchanged"
       [ -e "$stage/.committed" ] && where="history.csv keeps every complete step and checkpoint.txt the last checkpoint: edp/run.sh"
       [ -e "$stage/.committed" ] && where+=" $scene $out_arg -restart $out_arg continues the run"
       echo "error: FreeFEM was killed by $signal_name; $where" >&2
       exit_status=$rc
       [ "$rc" = 1 ] && exit_status=143
     elif [ "$filter" = 3 ] || [ "$filter" = 7 ]; then
       exit_status=$filter
     elif [ "$rc" = 8 ] && { [ ! -s "$errfile" ] || [ "$given" = 8 ]; }; then
       # (the driver's own: A's Cholesky factor refused under the limit, solve/direct.idp, or on -np a subdomain's,
       # solve/ffddm_solve.idp, whose other processes' exits FreeFEM reports as an error; its line is said)
       exit_status=8
     elif [ -n "$memory_said" ] ||
          { [ -n "$memory_limit" ] && { [ "$rc" = 139 ] || [ "$rc" = 134 ] || [ "$given" = crash ]; }; }; then
       # out of memory: CHOLMOD or FreeFEM said so, or FreeFEM crashed (SIGSEGV, SIGABRT: a failed allocation it did not
       # check; its buffered output is lost) under a per-process memory limit
       if [ -n "$memory_said" ]; then why="FreeFEM ran out of memory ($memory_said)"
       else why="FreeFEM crashed (exit $rc) under a per-process memory limit of $memory_limit: it most likely ran out of memory"; fi
       where="before the run started; $out_arg is unchanged"
       [ -e "$stage/.committed" ] && where="history.csv keeps every complete step and checkpoint.txt the last checkpoint"
       echo "error: $why; the body needs more memory a process than the limit or the machine gives: -np N holds only" \
            "each process's part of its matrices (docs/parallel.md); $where" >&2
       exit_status=8
     else
       detail=$(head -c 300 "$errfile")
       echo "error: FreeFEM stopped with an unexpected error (exit $rc${detail:+: $detail}); if the scene is your own, check it," \
            "otherwise this is a bug in the suite: please report it (CONTACT_DEBUG=1 shows FreeFEM's output)" >&2
       exit_status=1
     fi ;;
esac
# Success is a run that reached T: committed into OUT, with the summary it writes last. A scene
# that calls exit(0) stops FreeFEM with status 0 before that.
if [ "$exit_status" = 0 ] && { [ ! -e "$stage/.committed" ] || [ ! -s "$out/summary.txt" ]; }; then
  if [ -e "$stage/.committed" ]; then where="after the run started; history.csv keeps the steps it made"
  else where="before the run started; $out_arg is unchanged"; fi
  echo "error: FreeFEM stopped without an error but before the run reached T (no summary.txt), $where; if the scene is" \
       "your own, check that it does not call exit()" >&2
  exit_status=1
fi
# A run that reached T is audited by its own physics (postprocess/audit.py, pure Python, tens of milliseconds: the
# documented columns, the time grid against parameters.txt and summary.txt, the momentum balance of (1) against the
# contact force columns, Prop. 2 where it applies, friction's law in totals, the snapshots against the history).
# A failure is a bug in the suite: exit 6, every file kept (CONTACT_AUDIT=0 skips the audit).
if [ "$exit_status" = 0 ] && [ "${CONTACT_AUDIT:-1}" != 0 ]; then
  audit_python=/usr/bin/python3
  [ -x "$audit_python" ] || audit_python=$(command -v python3 || true)
  if [ -n "$audit_python" ]; then
    audit_lines=$("$audit_python" -S -E "$root/postprocess/audit.py" "$out" 2>&1)     # (-S: no site-packages, 10 ms less)
    audit_rc=$?
    if [ "$audit_rc" = 1 ]; then
      printf '%s\n' "$audit_lines" | sed -n '1,20p' >&2
      echo "error: the run reached T, but its files fail their own audit (postprocess/audit.py, the lines above:" \
           "$(printf '%s\n' "$audit_lines" | grep -c '^audit:') of them): a bug in the suite, please report it;" \
           "every file of $out_arg is kept" >&2
      exit_status=6
    elif [ "$audit_rc" != 0 ]; then
      echo "error: the run reached T, but postprocess/audit.py could not audit it ($(printf '%s' "$audit_lines" | head -c 200)):" \
           "a bug in the suite, please report it; every file of $out_arg is kept" >&2
      exit_status=6
    fi
  fi
fi
case "$exit_status" in 7 | 8 | 129 | 130 | 137 | 143) keep_complete_rows ;; esac
settle_kept "$exit_status"
exit "$exit_status"
