"""The runs of the make targets (svk, methods, csm3, stress, bench, accuracy): started one by one
or in parallel, and stopped whole by Ctrl-C.

- `run(cmd)` is subprocess.run(cmd, capture_output=True, text=True) with the run in its own
  process group, registered while it lasts; `start(cmd)` and `finished(p)` do the same around
  a Popen (bench.py, which reads the run's resource usage).
- `stop_on_interrupt(target, out, stale)`, called first by a target's main: it removes the files
  that summarise an earlier run of the target (`stale`, globs in `out`), so that a target stopped
  half-way never leaves a summary or figure that looks current beside new, partial runs. On
  Ctrl-C (SIGINT) or SIGTERM it interrupts every registered run's process group (SIGINT, as a
  terminal would, then SIGKILL after 5 s), drops the queued runs, prints one line and exits 130.
- `run_parallel(fn, items, jobs)`: fn(item) for each item, `jobs` at a time, results in the order
  they finish (a generator); an exception of fn stops the queue and is raised.
- `ArgumentParser` and `positive_int`, for the targets' --jobs, and `add_processes_option` for their
  --np: a bad argument is one line on stderr (`error: methods.py: argument --jobs: must be a positive
  integer (runs at a time), got '0'`) and exit 2, before the target removes anything.
  `path`: an argument that names a file or directory, not empty.
"""
import argparse
import concurrent.futures
import faulthandler
import glob
import os
import re
import shutil
import signal
import subprocess
import sys
import threading
import time

_running = set()
# re-entrant: the signal handler runs in the main thread, which may hold it (review: a plain Lock
# deadlocked a Ctrl-C that landed while the main thread registered a run)
_lock = threading.RLock()
_stopping = threading.Event()


class Interrupted(Exception):
    pass


class ArgumentParser(argparse.ArgumentParser):
    """argparse.ArgumentParser whose errors are one line, `error: PROG: MESSAGE`, and exit 2
    (argparse's own print the usage first; -h still prints it)."""

    def error(self, message):
        self.exit(2, f"error: {self.prog}: {message}\n")


def positive_int(text):
    """argparse type of --jobs (runs at a time): an integer >= 1, written in decimal digits."""
    if not re.fullmatch(r"[0-9]+", text.strip()) or int(text) < 1:
        raise argparse.ArgumentTypeError(f"must be a positive integer (runs at a time), got '{text}'")
    return int(text)


def path(text):
    """argparse type of a path: not empty (an empty one would name the current directory)."""
    if not text.strip():
        raise argparse.ArgumentTypeError("must be a path, got an empty one")
    return text


def start(cmd, **kwargs):
    """subprocess.Popen(cmd, **kwargs) in its own process group, registered until finished(p).
    Started and registered under the lock, which the handler takes too: a run is either killed by the
    handler or never started, never left running outside its reach. From the main thread, where the
    handler runs, a short-lived thread starts it while the main thread waits: holding SIGINT and SIGTERM
    back in the main thread instead (as before 2026-11-27) passed them on blocked to the run (Popen's child
    keeps its parent's signal mask, and neither bash nor FreeFEM clears it), so Ctrl-C reached a run only as
    the SIGKILL 5 s later."""
    if threading.current_thread() is not threading.main_thread():
        return _start_registered(cmd, **kwargs)
    started = []
    t = threading.Thread(target=lambda: started.append(_start_or_error(cmd, **kwargs)))
    t.start()
    t.join()
    p, error = started[0]
    if error is not None:
        raise error
    return p


def _start_or_error(cmd, **kwargs):
    try:
        return _start_registered(cmd, **kwargs), None
    except BaseException as e:      # (raised again in the calling thread)
        return None, e


def _start_registered(cmd, **kwargs):
    with _lock:
        if _stopping.is_set():
            raise Interrupted()
        p = subprocess.Popen(cmd, start_new_session=True, **kwargs)
        _running.add(p)
    return p


def finished(p):
    with _lock:
        _running.discard(p)
    if _stopping.is_set():
        raise Interrupted()


def _run(cmd, **kwargs):
    p = start(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, **kwargs)
    try:
        out, err = p.communicate()
    finally:
        finished(p)
    return subprocess.CompletedProcess(cmd, p.returncode, out, err)


# ---- --np N (issue 26, docs/parallel.md): a target's runs on N processes each (edp/run.sh -np N), JOBS of them
# at a time. A run that -np refuses (IPOPT, Nitsche, Newmark, Verlet: their own factorisations) runs on one
# process instead, with a note; its one error line says why.
processes = 0


NP_MOST = 1024          # edp/run.sh's -np: 1 to 1024
# what edp/run.sh -np needs, and how it names it
NP_TOOLS = "(FreeFEM's MPI build with Open MPI; Debian: apt-get install freefem++ openmpi-bin)"
FFDDM = "/usr/include/freefem++/idp/ffddm.idp"


def process_count(text):
    """argparse type of --np (processes of each run): what edp/run.sh -np takes (1 to 1024, in at most 4 decimal
    digits) and needs (mpirun, FreeFem++-mpi, ffddm), checked before the target removes anything."""
    if not re.fullmatch(r"[0-9]{1,4}", text) or not 1 <= int(text) <= NP_MOST:
        raise argparse.ArgumentTypeError(f"must be a whole number of processes per run from 1 to {NP_MOST} "
                                         f"(edp/run.sh -np), got '{text}'")
    for tool in ("mpirun", "FreeFem++-mpi"):
        if shutil.which(tool) is None:
            raise argparse.ArgumentTypeError(f"{text} processes per run need {tool} {NP_TOOLS}")
    if not os.access(FFDDM, os.R_OK):
        raise argparse.ArgumentTypeError(f"{text} processes per run need FreeFEM's ffddm ({FFDDM}; Debian: apt-get "
                                         "install libfreefem++-dev)")
    return int(text)


def add_processes_option(parser):
    """The targets' --np N (make TARGET NP=N)."""
    parser.add_argument("--np", type=process_count, default=0, metavar="N",
                        help="processes of each run (edp/run.sh -np N; runs that -np refuses run on one process)")


def use_processes(n):
    global processes
    processes = n or 0


def is_driver_run(cmd):
    return len(cmd) >= 3 and os.path.basename(str(cmd[0])) == "run.sh"


def on_processes(cmd):
    """cmd with -np N after edp/run.sh's SCENE and OUT, when --np N was given."""
    return list(cmd[:3]) + ["-np", str(processes)] + list(cmd[3:]) if processes and is_driver_run(cmd) else list(cmd)


def refused_by_np(p):
    return p.returncode == 3 and "does not run on -np" in (p.stderr or "")


def run_processes(cmd, launch):
    """launch(cmd) on --np N processes; a run that -np refuses again on one process, with a note."""
    p = launch(on_processes(cmd))
    if processes and is_driver_run(cmd) and refused_by_np(p):
        reason = [line for line in p.stderr.splitlines() if "does not run on -np" in line][0]
        print(f"note: {cmd[1]} {' '.join(map(str, cmd[3:]))} runs on one process ({reason[len('error: '):]})", flush=True)
        p = launch(list(cmd))
    return p


def run(cmd, **kwargs):
    """subprocess.run(cmd, capture_output=True, text=True) in a process group of its own (see the top), with
    --np N for a run of edp/run.sh."""
    return run_processes(cmd, lambda c: _run(c, **kwargs))


def _signal_groups(sig):
    with _lock:
        procs = list(_running)
    for p in procs:
        try:
            os.killpg(p.pid, sig)
        except (ProcessLookupError, PermissionError):
            pass
    return procs


def stop_on_interrupt(target, out, stale):
    # SIGUSR1 prints every thread's stack on stderr (test_interrupt.py asks for it when a target starts no run)
    faulthandler.register(signal.SIGUSR1, all_threads=True)
    for pattern in stale:
        for path in glob.glob(os.path.join(out, pattern)):
            os.remove(path)

    def handler(signum, frame):
        if _stopping.is_set():
            return
        _stopping.set()
        procs = _signal_groups(signal.SIGINT)
        deadline = time.monotonic() + 5
        while time.monotonic() < deadline and any(p.poll() is None for p in procs):
            time.sleep(0.05)
        _signal_groups(signal.SIGKILL)
        print(f"interrupted: {target} stopped, its runs killed; {out} holds no summary of this run "
              f"(run {target} again)", file=sys.stderr, flush=True)
        os._exit(130)

    signal.signal(signal.SIGINT, handler)
    signal.signal(signal.SIGTERM, handler)


def run_parallel(fn, items, jobs):
    ex = concurrent.futures.ThreadPoolExecutor(jobs)
    futs = [ex.submit(fn, item) for item in items]
    try:
        for fut in concurrent.futures.as_completed(futs):
            yield fut.result()
    finally:
        ex.shutdown(wait=True, cancel_futures=True)


def write_files(out, texts):
    """Each text into out/name (a study's tables: summary.md and its CSV), then the first printed."""
    for name, text in texts.items():
        with open(os.path.join(out, name), "w") as f:
            f.write(text)
    print(next(iter(texts.values())))
