"""-np N (issue 26, docs/parallel.md): the driver on N processes of FreeFem++-mpi, its solves with A on
ffddm (RAS-preconditioned GMRES to a relative residual of 1e-12), against the same runs on one process:
the same history to the Krylov tolerance, the same steps with a QP and the same active sets, the same files
(written by process 0 only), a restart with another N, and every refusal and failure path (one line, the
documented status, no process left waiting)."""
import os
import signal
import subprocess
import time

import numpy as np
import pytest

from conftest import RUN, error_lines, files_of, refused_into_copy, run_scene, run_scenes
from history import read_run, read_summary

QUIET = ["-progress", "0"]
BALL = ["-T", "14", "-solver", "activeset", "-snapshots", "0,10", "-checkpoint_every", "100"] + QUIET
# name: (scene, args); each "<name> np<N>" beside its serial run "<name>"
CASES = {
    "ball": ("ball", BALL),                    # Test 1 in 3D: the fall, the first impact, resting (t = 8.95 on)
    "ball_moving": ("ball_moving", ["-T", "12", "-solver", "activeset", "-snapshots", "none"] + QUIET),  # (10) on a moving surface
    "ball_neohookean": ("ball", ["-T", "10", "-material", "neohookean", "-snapshots", "none"] + QUIET),  # Newton, GMRES on A
    "ball_penalty": ("ball", ["-T", "10", "-contact", "penalty", "-snapshots", "none"] + QUIET),
    "test1": ("test1", ["-T", "14", "-solver", "activeset", "-snapshots", "none"] + QUIET),            # a plane body too
}
PROCESSES = {"ball": [1, 2], "ball_moving": [2], "ball_neohookean": [2], "ball_penalty": [2], "test1": [2]}
# Tolerances of the parallel runs against the serial ones: the displacement relative to the largest displacement
# component of the run, the energies and alpha relative to their own largest magnitude. GMRES stops at a relative
# residual of 1e-12, and A, dominated by its mass term, is well conditioned, so a solve is within about 1e-12 of
# the direct one; the impacts amplify that, as they amplify round-off. Measured on these runs: the displacement
# 1.8e-10 (ball_moving; 2.3e-11 ball), the energies 1.9e-11, alpha 3.3e-8 (ball_moving; 2.0e-9 ball); -np 1
# (one subdomain, its own numbering) 1.7e-11, 2.0e-12, 3.6e-9. The tolerances are 30-55 times those.
TOL = {"u": 1e-8, "energy": 1e-9, "pressure": 1e-6}


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    base = tmp_path_factory.mktemp("parallel")
    todo = {}
    for name, (scene, args) in CASES.items():
        todo[name] = (scene, args)
        for n in PROCESSES[name]:
            todo[f"{name} np{n}"] = (scene, args + ["-np", str(n)])
    return run_scenes(base, {k.replace(" ", "_"): v for k, v in todo.items()})


def columns(name):
    u = ["u1_low", "u2_low", "u3_low"] if name.startswith("ball") else ["u1_low", "u2_low"]
    return u, ["energy", "modified_energy"], ["contact_pressure_low"]


@pytest.mark.parametrize("name,n", [(name, n) for name in CASES for n in PROCESSES[name]],
                         ids=[f"{name} np{n}" for name in CASES for n in PROCESSES[name]])
def test_parallel_runs_equal_the_serial_ones(runs, name, n):
    """The same scheme (1)-(2) with (10), each step's QP (4) solved exactly, whatever N: the steps that solved
    a QP and the active nodes are the same at every step, and the displacement at the reference point, the
    energies and the contact pressure alpha of (6) agree with the serial direct solver's to the Krylov
    tolerance at every step."""
    serial, parallel = read_run(runs[name]), read_run(runs[f"{name}_np{n}"])
    assert len(serial["t"]) == len(parallel["t"])
    assert np.array_equal(serial["qp_solved"], parallel["qp_solved"])
    assert np.array_equal(serial["active_nodes"], parallel["active_nodes"])
    u, energies, pressure = columns(name)
    displacement = max(np.abs(serial[c]).max() for c in u)
    for group, tol in ((u, TOL["u"]), (energies, TOL["energy"]), (pressure, TOL["pressure"])):
        for c in group:
            scale = displacement if group is u else max(np.abs(serial[c]).max(), 1e-300)
            gap = np.abs(serial[c] - parallel[c]).max()
            assert gap <= tol * scale, f"{c}: {gap:.3g} > {tol:g} x {scale:.6g}"
    summary = read_summary(runs[f"{name}_np{n}"])
    assert int(summary["processes"]) == n and int(summary["krylov_solves"]) > 0
    assert int(read_summary(runs[name])["krylov_solves"]) == 0
    # the constraint (10) holds at every contact node to round-off (max_penetration: its largest violation;
    # the penalty lets the body in by design, as much as serially)
    if "penalty" not in name:
        assert parallel["max_penetration"].max() <= 1e-9 * 20
    else:
        assert abs(parallel["max_penetration"].max() - serial["max_penetration"].max()) <= 1e-6 * displacement


def test_only_process_0_writes_and_the_files_are_the_serial_ones(runs):
    """OUT holds the files of a serial run, and nothing else: the same names, the same parameters.txt
    (the number of processes is not a parameter of the run) and mesh, snapshots of the same size."""
    serial, parallel = files_of(runs["ball"]), files_of(runs["ball_np2"])
    assert sorted(serial) == sorted(parallel)
    for f in ("parameters.txt", "mesh.mesh", "scene.idp", "foundation.csv"):
        assert serial[f] == parallel[f], f
    for f in serial:
        if f.endswith(".csv") and f.startswith("snapshot"):
            assert serial[f].count(b"\n") == parallel[f].count(b"\n")


def test_a_parallel_run_prints_as_a_serial_one(tmp_path):
    """Only process 0's lines reach the terminal: the mesh line once, the last line once, no error line."""
    p = run_scene("ball", tmp_path / "out", ["-T", "0.5", "-solver", "activeset", "-np", "2"] + QUIET)
    lines = p.stdout.splitlines()
    assert sum(line.startswith("mesh ") for line in lines) == 1, p.stdout
    assert sum(" steps, " in line for line in lines) == 1, p.stdout
    assert p.stderr == "", p.stderr


def test_a_restart_with_another_number_of_processes_continues_the_run(runs, tmp_path):
    """A run on 2 processes, restarted from its checkpoint (t = 5, step 100) on 1 process and serially, gives
    the uninterrupted history to the Krylov tolerance."""
    straight = read_run(runs["ball_np2"])
    for extra in (["-np", "1"], []):
        out = tmp_path / f"restart{len(extra)}"
        run_scene("ball", out, ["-restart", runs["ball_np2"], "-T", "14"] + extra + QUIET)
        h = read_run(str(out))
        assert np.array_equal(h["qp_solved"], straight["qp_solved"])
        assert np.abs(h["u3_low"] - straight["u3_low"]).max() <= TOL["u"] * 4


@pytest.fixture(scope="module")
def earlier_ball(tmp_path_factory):
    out = tmp_path_factory.mktemp("earlier_np") / "run"
    run_scene("ball", out, ["-T", "0.5", "-snapshots", "0,0.25", "-checkpoint_every", "5"] + QUIET)
    return str(out)


REFUSED = [
    (["-np", "2"], 3, "-solver ipopt does not run on -np 2 processes"),
    (["-np", "2", "-solver", "activeset", "-scheme", "newmark"], 3, "-scheme newmark does not run on -np 2 processes"),
    (["-np", "2", "-material", "neohookean", "-newton_precond", "step"], 3, "-newton_precond step is not supported on a 3D"),
    (["-np", "0"], 3, "-np must be a whole number of processes from 1 to 1024; got '0'"),
    (["-np", "two"], 3, "-np must be a whole number of processes from 1 to 1024; got 'two'"),
    (["-np", "2", "-np", "2"], 3, "-np is given twice"),
    (["-np"], 3, "-np needs the number of processes"),
    (["-np", "2", "-solver", "activeset", "-u0z", "-1"], 3, "the initial state penetrates the foundation"),
]


@pytest.mark.parametrize("args,status,message", REFUSED, ids=[" ".join(a) for a, _, _ in REFUSED])
def test_parallel_refusals_are_one_line_and_change_nothing(tmp_path, earlier_ball, args, status, message):
    """What -np N does not run, and a bad -np, is one error line with exit 3, and the earlier run in the
    directory stays byte-identical."""
    p, changed = refused_into_copy(tmp_path, earlier_ball, "ball", ["-T", "1"] + QUIET + args, timeout=120)
    assert p.returncode == status, p.stderr
    assert len(error_lines(p)) == 1 and message in error_lines(p)[0], p.stderr
    assert not changed


def test_a_plane_refusal_names_the_method(tmp_path):
    p = run_scene("test1", tmp_path / "out", ["-T", "1", "-contact", "nitsche", "-np", "2"] + QUIET, check=False,
                  timeout=120)
    assert p.returncode == 3 and error_lines(p) == [
        "error: -contact nitsche does not run on -np 2 processes: its step factorises a matrix of its own; use -contact "
        "constraint or penalty with -contact_quadrature vertex"], p.stderr
    assert not (tmp_path / "out").exists()


def run_group(scene, out, args, env, limit=120):
    """edp/run.sh in a process group of its own, killed whole if it outlives `limit` seconds (a run left waiting
    in MPI must not outlive its test): (CompletedProcess-like result, seconds taken)."""
    start = time.monotonic()
    p = subprocess.Popen([RUN, scene, str(out)] + args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                         env=dict(os.environ, FORCE="1", **env), start_new_session=True)
    try:
        stdout, stderr = p.communicate(timeout=limit)
    except subprocess.TimeoutExpired:
        os.killpg(p.pid, signal.SIGKILL)
        p.communicate()
        raise AssertionError(f"{scene} {' '.join(args)} was still running after {limit} s")
    return subprocess.CompletedProcess(p.args, p.returncode, stdout, stderr), time.monotonic() - start


def test_a_write_that_fails_on_process_0_stops_every_process(tmp_path):
    """history.csv's write failing on process 0 (the only writer; a test hook at step 30, as a full disk would,
    which the serial tests make real with RLIMIT_FSIZE: under mpirun that limit also hits Open MPI's own files)
    while the others compute: exit 7 with its one line within seconds (the others are stopped, not left waiting
    in MPI), history.csv ends with a complete row, and no summary."""
    out = tmp_path / "full"
    p, seconds = run_group("ball", out, ["-T", "5", "-solver", "activeset", "-snapshots", "none", "-np", "2"] + QUIET,
                           {"CONTACT_TEST_WRITE_FAIL_STEP": "30"})
    assert p.returncode == 7 and len(error_lines(p)) == 1, p.stderr
    assert "cannot write history.csv in the output directory (disk full?)" in error_lines(p)[0]
    assert seconds < 60
    assert open(out / "history.csv").read().endswith("\n")
    assert not (out / "summary.txt").exists()


def test_a_process_that_crashes_alone_stops_the_run(tmp_path):
    """FreeFEM stopping with an error on one process only (here the last, by a test hook at step 3) ends the
    run with the unexpected-error line naming that process and exit 1, instead of a job that never ends."""
    p, seconds = run_group("ball", tmp_path / "out", ["-T", "1", "-solver", "activeset", "-np", "2"] + QUIET,
                           {"CONTACT_TEST_CRASH_STEP": "3"})
    assert p.returncode == 1 and len(error_lines(p)) == 1, p.stderr
    assert "FreeFEM stopped with an unexpected error" in p.stderr and "process 1" in p.stderr
    assert seconds < 60
