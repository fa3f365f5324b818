# run/output_filter.awk -- edp/run.sh's filter of FreeFEM's output: FreeFEM writes everything to stdout;
# this keeps the driver's own lines ("error:" and "warning:" ones to stderr) and drops FreeFEM's traces,
# keeping the first message of one for the error line.
# A compile error in the scene becomes one line naming the scene file and the line (exit 3); a file of
# the run that cannot be opened for writing is a write failure (exit 7). On a terminal (tty=1) the
# progress line is rewritten in place; in a log every 10th is kept, and one a minute at least.
# -np N (tagged=1): of the lines mpirun tags "[1,r]<stdout>:", process 0's are kept (every process runs the
# same checks), and from any process its "exit-status TAG N" line (run/options.idp; TAG the run's own, statustag, so
# that no line a scene prints is taken for one) and FreeFEM's error traces,
# the first written to ERRFILE.stop for edp/run.sh to stop the other processes.
# Variables: tty, tagged, statustag, scene (the scene file's path, for the error line), errfile (the detail of an
# unexpected error is written there).

# trace: FreeFEM's error traces, and mpirun's report of a process that died (any process's stops a -np run)
BEGIN { trace = "Exec error|Assertion fail|Segmentation fault|Aborted|Killed|Out of bound|Error line number|err code|out of memory|bad_alloc" }
function newline() { if (pending) { printf "\n"; pending = 0 } }
function stop(why) { if (!stopped) { print why > (errfile ".stop"); close(errfile ".stop"); stopped = 1 } }
tagged { rank = -1
         if (match($0, /^\[[0-9]+,[0-9]+\]<std(out|err)>:/)) { tag = substr($0, 1, RLENGTH); sub(/^\[[0-9]+,/, "", tag)
                                                                rank = tag + 0; $0 = substr($0, RLENGTH + 1) } }
tagged && NF == 3 && $1 == "exit-status" && $2 == statustag && $3 ~ /^[0-9]+$/ { stop($3); next }
tagged && rank != 0 {     # (rank -1: a line of mpirun itself; a process's own error line, shown if process 0 has none:
                          # a failure of that process alone, such as writing its piece of a snapshot)
  if (/^error: / && other_error == "") other_error = $0
  if ($0 ~ trace && $0 !~ /^(error|warning): /) {
    if (detail == "") { detail = (rank < 0 ? "mpirun" : "process " rank) ": " $0; gsub(/^[ \t]+|[ \t]+$/, "", detail) }
    stop("crash")
  }
  next }
/^error: |^warning: / { newline(); print > "/dev/stderr"; fflush("/dev/stderr"); if (/^error: /) printed_error = 1; next }
/^(note: |mesh |reference point: |initial state: |probe [0-9]+: |restart from step |[0-9]+ steps, )/ { newline(); print; fflush(); next }
/^progress / { sub(/^progress /, "")
               if (tty) { printf "\r%s   ", $0; pending = 1 }
               else { el = $0; sub(/.*elapsed /, "", el); sub(/ .*/, "", el)
                      if (++np % 10 == 0 || el + 0 >= shown + 60) { print; shown = el + 0 } }
               fflush(); next }
/Error line number [0-9]+, in file / {
  line = $0; sub(/.*Error line number /, "", line); sub(/,.*/, "", line)
  token = $0; sub(/.*before  *token */, "", token)
  file = $0; sub(/.*, in file /, "", file); sub(/, before.*/, "", file)
  if (reason == "") reason = "syntax error"
  if (file ~ /scene\.idp$/) {
    newline()
    printf "error: scene %s, line %s: %s (before \"%s\")\n", scene, line, reason, token > "/dev/stderr"
    compile = 3
  } else if (detail == "") detail = "compile error in " file ", line " line ": " reason
  next
}
/^ *The Identifier .* does not exist|^ *No operator|^ Error opening file .* in: / {
  if (reason == "") { reason = $0; gsub(/^ +| +$/, "", reason) } next }
/^ Error opening file / { if (opened == "") { opened = $0; sub(/^ Error opening file /, "", opened) } next }
/Exec error|Assertion fail|Error|error|Segmentation fault|Aborted|Killed|Out of bound|bug/ {
  if (detail == "") { detail = $0; gsub(/^[ \t]+|[ \t]+$/, "", detail) }
  if (tagged && $0 ~ trace) stop("crash")
  next }
{ next }
END { newline()
      if (other_error != "" && !printed_error) print other_error > "/dev/stderr"
      if (compile) exit 3
      # the files the run writes (edp/lib/io/, contact.edp): a failed open is a failed write
      if (opened ~ /(history\.csv|parameters\.txt|foundation\.csv|\.part|\.part\.vtu|expected_header\.txt|restart_files\.txt)$/) {
        print "error: cannot open " opened " for writing (disk full, or the directory is not writable)" > "/dev/stderr"; exit 7 }
      if (opened != "" && detail == "") detail = "cannot open " opened
      if (detail != "") print detail > errfile }
