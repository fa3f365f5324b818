"""Running the driver from a study: the repository's root, edp/run.sh's path, and run_case (one run of
run.sh with FORCE=1, timed, its output and exit status kept); case_row, a run's cost and step counts.
Runs start through jobs.py: in a process group of their own, on --np N processes."""
import os
import subprocess
import sys
import tempfile
import threading
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import jobs  # noqa: E402
from history import error_lines, guard_stop, read_run, read_summary  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
RUN = os.path.join(ROOT, "edp", "run.sh")
PLUGINS = os.path.join(ROOT, "build", "plugins")
PEAK_RSS = os.path.join(ROOT, "build", "peak_rss")      # postprocess/peak_rss.cpp, built by `make deps`


def freefem_env(**extra):
    """The environment of a FreeFEM script run outside edp/run.sh (edp/limit.edp, the tests' unit scripts): Debian's
    plugins and the suite's (build/plugins, `make plugins`), FreeFEM's .idp files; extra: more variables."""
    return dict(os.environ, FF_LOADPATH="/usr/lib/freefem++;" + PLUGINS, FF_INCLUDEPATH="/usr/include/freefem++/idp",
                **extra)


class Run:
    """A finished process: cmd, returncode, stdout, stderr ("" when merged into stdout), wall seconds, usage
    (os.wait4's: its own CPU time, FreeFEM included) and peak_KiB (build/peak_rss's: the largest resident size
    of any of its processes, from its own start, not from this Python process's size)."""

    def __init__(self, cmd, returncode, stdout, stderr, wall, usage, peak_KiB):
        self.cmd, self.returncode, self.stdout, self.stderr, self.wall, self.usage = cmd, returncode, stdout, stderr, wall, usage
        self.peak_KiB = peak_KiB

    @property
    def cpu_s(self):
        return self.usage.ru_utime + self.usage.ru_stime

    @property
    def peak_MiB(self):
        return self.peak_KiB / 1024

    @property
    def last_line(self):
        """The last line of stderr (a failed run's one error line), or "no message"."""
        return (self.stderr.strip().splitlines() or ["no message"])[-1]


def timed_process(cmd, merge=False, **kwargs):
    """cmd run to its end (jobs.start: its own process group, stopped by Ctrl-C) through build/peak_rss: a Run.
    merge: stderr into stdout, in the order written."""
    if not os.access(PEAK_RSS, os.X_OK):
        sys.exit(f"{PEAK_RSS} is missing (it measures a run's peak memory): run make deps")
    fd, peak_file = tempfile.mkstemp(prefix="peak_rss.")
    os.close(fd)
    t0 = time.perf_counter()
    try:
        p = jobs.start([PEAK_RSS, peak_file] + list(cmd), stdout=subprocess.PIPE,
                       stderr=subprocess.STDOUT if merge else subprocess.PIPE, text=True, **kwargs)
    except BaseException:
        os.unlink(peak_file)
        raise
    try:
        err = []
        reader = None if merge else threading.Thread(target=lambda: err.append(p.stderr.read()))
        if reader:
            reader.start()
        out = p.stdout.read()
        if reader:
            reader.join()
        # wait4, not wait: this run's own CPU time (Linux counts reaped descendants)
        _, status, usage = os.wait4(p.pid, 0)
        p.returncode = os.waitstatus_to_exitcode(status)
        with open(peak_file) as f:
            peak = f.read().strip()
    finally:
        for f in (p.stdout, p.stderr):
            if f:
                f.close()
        os.unlink(peak_file)
        jobs.finished(p)
    if not peak.isdigit() and p.returncode == 0:
        sys.exit(f"{PEAK_RSS} did not report the peak memory of: {' '.join(cmd)}")
    # (a run killed with its launcher has no peak: None, and a failed run's peak is never tabled)
    return Run(cmd, p.returncode, out, "".join(err), time.perf_counter() - t0, usage, int(peak) if peak.isdigit() else None)


def run_case(scene, out, args, log=None, merge=False, cwd=None):
    """edp/run.sh SCENE OUT ARGS to its end, with FORCE=1 (an earlier OUT is replaced) and, under --np N, on
    N processes (a run that -np refuses runs again on one: jobs.run_processes): its Run, timed. log: a file
    given the command, the run's output and its exit status."""
    cmd = [RUN, scene, out] + list(args)
    env = dict(os.environ, FORCE="1")
    runs = []

    def launch(c):
        r = timed_process(c, merge=merge, env=env, cwd=cwd)
        runs.append(r)
        return subprocess.CompletedProcess(c, r.returncode, r.stdout, r.stdout if merge else r.stderr)

    jobs.run_processes(cmd, launch)
    r = runs[-1]
    if log:
        with open(log, "w") as f:
            f.write("$ " + " ".join(cmd) + "\n" + r.stdout + r.stderr + f"exit status {r.returncode}\n")
    return r


def case_row(out_base, name, scene, args, allow_stop=False):
    """One run into out_base/name (-progress 0 -snapshots none), timed: its row of cost and step counts
    (make bench's and make accuracy's tables). A failed run ends the study with its output. allow_stop: a
    run that the energy guard stops (exit 4, its one line; docs/errors.md) is returned with that line as
    "stopped", not taken as a failure."""
    out = os.path.join(out_base, name)
    r = run_case(scene, out, ["-progress", "0", "-snapshots", "none"] + list(args), merge=True)
    log = r.stdout
    stopped = allow_stop and r.returncode == 4 and guard_stop(log) is not None
    if r.returncode != 0 and not stopped:
        sys.exit(f"bench case {name} failed:\n{log}")
    h = read_run(out)
    summary = read_summary(out) if not stopped else {}     # (a stopped run has no summary.txt)
    steps = len(h["t"]) - 1
    return {"case": name, "scene": scene, "args": " ".join(args), "wall_s": r.wall, "stopped": error_lines(log)[0] if stopped else "",
            "cpu_s": r.cpu_s, "peak_MiB": r.peak_MiB, "steps": steps, "qp_steps": int(h["qp_solved"].sum()),
            "ms_per_step": 1000 * r.wall / steps, "history": h, "log": log,
            **{k: int(summary.get(k, 0)) for k in ("newton_iterations", "newton_retries", "gmres_iterations")}}
