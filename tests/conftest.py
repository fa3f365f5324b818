"""Shared runs for the tests: every simulation the tests need is started once
per session, two at a time (the machines have 2 cores), in a temporary directory."""
import os
import shutil
import subprocess
import sys
import time

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "postprocess"))

from history import read_run  # noqa: E402
from stress import FAST, case_args  # noqa: E402

RUN = os.path.join(ROOT, "edp", "run.sh")

# name: (scene, options). Horizons cover the first bounce and the rebound after it.
RUNS = {
    "test1": ("test1", ["-T", "45"]),
    "test1_qp_every_step": ("test1", ["-T", "30", "-skip_free", "0"]),
    "test2_t1_18": ("test2", ["-T", "45", "-t1", "18"]),
    "test2_t1_22": ("test2", ["-T", "45", "-t1", "22"]),
    "test2_t1_26": ("test2", ["-T", "45", "-t1", "26"]),
    # the exact active-set solver against IPOPT converged further (tol 1e-10)
    "test1_activeset": ("test1", ["-T", "30", "-solver", "activeset"]),
    "test1_ipopt_tight": ("test1", ["-T", "30", "-tol", "1e-10"]),
    "test2_activeset": ("test2", ["-T", "30", "-solver", "activeset"]),
    "test2_ipopt_tight": ("test2", ["-T", "30", "-tol", "1e-10"]),
    # the LU factorisation of A (UMFPACK) against the default Cholesky (CHOLMOD)
    "test2_activeset_lu": ("test2", ["-T", "30", "-solver", "activeset", "-factorization", "lu"]),
    # scenes beyond the paper, on short horizons
    "freeflight": ("freeflight", []),
    "incline": ("incline", ["-T", "10"]),
    "oblique": ("oblique", ["-T", "15"]),
    "rising": ("rising", ["-T", "20"]),
    "wave": ("wave", ["-T", "25"]),
    "bump": ("bump", ["-T", "30"]),
}
# the fast subset of make stress (postprocess/stress.py)
RUNS.update({f"stress: {name}": case_args(name, horizon) for name, horizon in FAST.items()})


def run_scene(scene, out, args, check=True, env=None, **kwargs):
    """edp/run.sh SCENE OUT ARGS (with FORCE=1); returns the CompletedProcess."""
    p = subprocess.run([RUN, scene, str(out)] + list(args), capture_output=True, text=True,
                       env=dict(os.environ, FORCE="1", **(env or {})), **kwargs)
    if check and p.returncode != 0:
        raise AssertionError(f"{scene} {' '.join(args)} failed ({p.returncode}):\n{p.stdout}\n{p.stderr}")
    return p


def error_lines(p):
    """The "error:" lines a run wrote on stderr."""
    return [line for line in p.stderr.splitlines() if line.startswith("error:")]


def files_of(directory):
    """Every file of a run directory (not the hidden lock and staging), with its bytes."""
    return {f: open(os.path.join(directory, f), "rb").read()
            for f in sorted(os.listdir(directory)) if not f.startswith(".")}


@pytest.fixture(scope="session")
def earlier_run(tmp_path_factory):
    """A finished run with a file of every kind (history, parameters, mesh, foundation,
    snapshots as CSV and VTU, checkpoint, summary): each failure test runs into a copy
    of it with FORCE=1 and checks that every file is byte-identical afterwards."""
    out = tmp_path_factory.mktemp("earlier") / "run"
    run_scene("test1", out, ["-T", "0.5", "-snapshots", "0,0.25", "-checkpoint_every", "5", "-progress", "0"])
    return str(out)


def refused_into_copy(tmp_path, earlier, scene, args, env=None, **kwargs):
    """Run SCENE ARGS with FORCE=1 into a copy of the earlier run; returns the process
    and whether any file of the earlier run changed."""
    out = tmp_path / "copy"
    shutil.copytree(earlier, out)
    before = files_of(out)
    p = run_scene(scene, out, args, check=False, env=env, **kwargs)
    return p, files_of(out) != before


@pytest.fixture(scope="session")
def runs(tmp_path_factory):
    base = tmp_path_factory.mktemp("runs")
    pending = list(RUNS.items())
    active = []
    while pending or active:
        while pending and len(active) < 2:
            name, (scene, args) = pending.pop(0)
            out = str(base / name)
            proc = subprocess.Popen([RUN, scene, out, "-progress", "0", "-vtk", "0"] + args,
                                    stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                                    env=dict(os.environ, FORCE="1"))
            active.append((name, out, proc))
        time.sleep(0.2)
        for item in list(active):
            name, out, proc = item
            if proc.poll() is not None:
                log = proc.stdout.read()
                assert proc.returncode == 0, f"run {name} failed ({proc.returncode}):\n{log}"
                active.remove(item)
    return {name: str(base / name) for name in RUNS}


@pytest.fixture(scope="session")
def histories(runs):
    return {name: read_run(d) for name, d in runs.items()}
