"""No run loses data: flushed history, checkpoints and -restart, the IPOPT retry, a clean stop."""
import os
import signal
import subprocess
import time

import numpy as np

from conftest import RUN, run_scene
from history import read_run


def test_killed_run_restarts_to_the_same_history(tmp_path, histories):
    out = tmp_path / "killed"
    proc = subprocess.Popen([RUN, "test1", str(out), "-T", "20", "-checkpoint_every", "50", "-progress", "0",
                             "-vtk", "0"], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                            start_new_session=True, env=dict(os.environ, FORCE="1"))
    history = out / "history.csv"
    deadline = time.time() + 120
    while time.time() < deadline:             # kill it on purpose, past a checkpoint, mid-run
        if history.exists() and sum(1 for _ in open(history)) > 260:
            break
        time.sleep(0.05)
    os.killpg(proc.pid, signal.SIGKILL)
    proc.wait()
    rows_at_kill = sum(1 for _ in open(history)) - 1
    step = int(open(out / "checkpoint.txt").readline().split()[0])
    assert 200 <= step <= rows_at_kill < 400, (step, rows_at_kill)

    run_scene("test1", str(out), ["-restart", str(out)])
    restarted, whole = read_run(str(out)), histories["test1"]
    n = len(restarted["t"])
    assert n == 401 and (restarted["step"] == np.arange(n)).all()
    for column in restarted:
        diff = np.abs(restarted[column] - whole[column][:n]).max()
        assert diff <= 1e-12, f"column {column} differs by {diff:.3g} after the restart"


def test_restart_without_checkpoint_is_a_clear_error(tmp_path):
    p = run_scene("test1", str(tmp_path / "out"), ["-restart", str(tmp_path)], check=False)
    assert p.returncode == 3 and "no checkpoint.txt there" in p.stderr


def test_ipopt_failure_is_retried_from_u_n(tmp_path, histories):
    # max_iter 1 makes every first IPOPT attempt fail; the retry must give the same step
    out = tmp_path / "retry"
    run_scene("test1", str(out), ["-T", "12", "-ipopt_max_iter", "1", "-progress", "0", "-vtk", "0"])
    h = read_run(str(out))
    n = len(h["t"])
    assert np.abs(h["u2_low"] - histories["test1"]["u2_low"][:n]).max() < 1e-6
    summary = dict(line.split() for line in open(out / "summary.txt"))
    assert int(summary["ipopt_retries"]) == int(h["qp_solved"].sum()) > 0


def test_failed_step_stops_cleanly_and_keeps_the_history(tmp_path):
    out = tmp_path / "fail"
    p = run_scene("test1", str(out), ["-T", "12", "-ipopt_max_iter", "1", "-ipopt_retry", "0", "-progress", "0"],
                  check=False)
    assert p.returncode == 4
    errors = [line for line in p.stderr.splitlines() if line.strip()]
    assert len(errors) == 1 and "ipopt failed at step" in errors[0] and "t = " in errors[0] and "status -1" in errors[0]
    h = read_run(str(out))
    failed_step = int(errors[0].split("step ")[1].split(",")[0])
    assert (h["step"] == np.arange(failed_step)).all()     # every step before the failure is there
