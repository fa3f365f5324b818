"""Ctrl-C stops a make target whole (issue 19): every run it started is killed, the queued runs do
not start, it prints one line and exits 130, and it leaves no summary that looks current beside
killed, partial runs (postprocess/jobs.py). Before, `make svk` ran its queued runs for 42 s after
the interrupt, ended in a Python traceback, and left the previous summary.md and figures."""
import os
import signal
import subprocess
import sys
import time

import pytest

from conftest import ROOT

PYTHON = sys.executable
TARGETS = {
    "make svk": (["postprocess/svk_compare.py"], "summary.md"),
    "make methods": (["postprocess/methods.py"], "summary.md"),
    "make csm3": (["postprocess/csm3.py"], "summary.md"),
    "make stress": (["postprocess/stress.py", "--fast"], "summary.md"),
    "make bench": (["postprocess/bench.py"], "bench.md"),
    "make accuracy": (["postprocess/accuracy.py", "--methods-only"], "methods.md"),
}


def processes_of(out):
    """pids of the processes working in out (their directory, or out on their command line)."""
    pids = []
    for pid in os.listdir("/proc"):
        if not pid.isdigit() or int(pid) == os.getpid():
            continue
        try:
            cwd = os.readlink(f"/proc/{pid}/cwd")
            cmdline = open(f"/proc/{pid}/cmdline", "rb").read().replace(b"\0", b" ").decode(errors="replace")
        except OSError:
            continue
        if cwd.startswith(str(out)) or str(out) in cmdline:
            pids.append(int(pid))
    return pids


def freefem_running(out):
    for pid in processes_of(out):
        try:
            if open(f"/proc/{pid}/comm").read().startswith("FreeFem"):
                return True
        except OSError:
            pass
    return False


@pytest.mark.parametrize("target", list(TARGETS))
def test_ctrl_c_stops_the_target_whole(tmp_path, target):
    args, summary = TARGETS[target]
    out = tmp_path / "out"
    out.mkdir()
    (out / summary).write_text("an earlier run's summary\n")
    p = subprocess.Popen([PYTHON] + args + ["--out", str(out)], cwd=ROOT, stdout=subprocess.DEVNULL,
                         stderr=subprocess.PIPE, text=True, start_new_session=True)
    deadline = time.time() + 60
    while not freefem_running(out) and time.time() < deadline and p.poll() is None:
        time.sleep(0.05)
    assert freefem_running(out), f"{target}: no run started"
    time.sleep(0.3)
    os.killpg(p.pid, signal.SIGINT)                        # what a terminal's Ctrl-C does
    try:
        _, err = p.communicate(timeout=15)
    except subprocess.TimeoutExpired:
        os.killpg(p.pid, signal.SIGKILL)
        raise AssertionError(f"{target} still running 15 s after Ctrl-C")
    lines = [line for line in err.splitlines() if line.strip()]
    assert p.returncode == 130 and len(lines) == 1 and lines[0].startswith(f"interrupted: {target} stopped"), err
    time.sleep(0.5)
    assert not processes_of(out), f"{target}: processes left after Ctrl-C: {processes_of(out)}"
    assert not (out / summary).exists(), f"{target}: a stale {summary} is left"
