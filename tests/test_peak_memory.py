"""The studies' peak memory is the run's own (postprocess/peak_rss.cpp, docs/bench.md "Peak memory"): Linux starts
a forked child's peak (wait4's ru_maxrss) from the forking process's resident size, so before this launcher every
run that make bench timed read at least the bench's own 60 to 91 MiB (the ball's rows, and their memory ratios, were
that floor). Checked here: a run started from a Python process of 300 MiB reads its own size, not 300 MiB; a run
that touches 200 MiB reads that; and the launcher passes the run's exit status and signal on unchanged."""
import os
import signal
import sys

import pytest

from driver import PEAK_RSS, timed_process

PYTHON = sys.executable
MiB = 2 ** 20


@pytest.fixture(scope="module")
def large_parent():
    """This process made 300 MiB larger (touched, so resident), as make bench is after its first cases."""
    block = bytearray(300 * MiB)
    block[::4096] = b"\1" * len(block[::4096])
    yield block
    del block


def test_a_run_does_not_inherit_the_forking_process_s_peak(large_parent):
    # the old way, os.wait4 on a process forked straight from here: at least our 300 MiB
    pid = os.fork()
    if pid == 0:
        os.execv("/bin/true", ["/bin/true"])
    _, _, usage = os.wait4(pid, 0)
    assert usage.ru_maxrss / 1024 >= 300, usage.ru_maxrss
    # through the launcher: /bin/true's own (about 1 MiB)
    r = timed_process(["/bin/true"])
    assert r.returncode == 0 and r.peak_MiB < 10, (r.returncode, r.peak_MiB)


def test_a_run_s_own_memory_is_measured(large_parent):
    r = timed_process([PYTHON, "-c", f"b = bytearray({200 * MiB}); b[::4096] = b'\\1' * len(b[::4096])"])
    assert r.returncode == 0 and 200 <= r.peak_MiB < 240, (r.returncode, r.peak_MiB, r.stderr)


@pytest.mark.parametrize("script,status", [("exit 7", 7), ("kill -TERM $$", -signal.SIGTERM), ("kill -INT $$", -signal.SIGINT)])
def test_the_launcher_passes_the_run_s_ending_on(script, status):
    # a shell's status and its signal, as if run directly (jobs.py's Popen: the negative number of the signal)
    r = timed_process(["sh", "-c", script])
    assert r.returncode == status and r.peak_MiB < 10, (r.returncode, r.peak_MiB)
    assert os.access(PEAK_RSS, os.X_OK)


def test_a_missing_or_silent_launcher_is_one_clear_line(tmp_path, monkeypatch):
    # without build/peak_rss no run starts (no peak that looks measured): one line naming it and make deps; a
    # launcher that reports nothing for a run that exits 0 is one line naming the run, never a peak of 0
    import driver
    monkeypatch.setattr(driver, "PEAK_RSS", str(tmp_path / "peak_rss"))
    with pytest.raises(SystemExit) as e:
        timed_process(["/bin/true"])
    assert str(e.value) == f"{tmp_path / 'peak_rss'} is missing (it measures a run's peak memory): run make deps"
    silent = tmp_path / "peak_rss"
    silent.write_text('#!/bin/sh\nshift\nexec "$@"\n')
    silent.chmod(0o755)
    with pytest.raises(SystemExit) as e:
        timed_process(["/bin/true"])
    assert str(e.value) == f"{silent} did not report the peak memory of: /bin/true"
