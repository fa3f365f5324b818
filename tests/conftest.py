"""Shared runs for the tests: every simulation the tests need is started once
per session, two at a time (the machines have 2 cores; under make check's pytest-xdist, one on each worker),
in a temporary directory."""
import os
import shutil
import subprocess
import sys
import time

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "postprocess"))
sys.path.insert(0, os.path.join(ROOT, "tests", "reference"))     # scipy_midpoint

from history import read_run  # noqa: E402
from stress_cases import FAST, case_args, may_break  # noqa: E402

RUN = os.path.join(ROOT, "edp", "run.sh")

# One BLAS thread a simulation (unless the caller chose): the suite runs two at a time on 2 cores, and Debian's
# pthreads OpenBLAS (the BLAS once python3-numpy is installed) starts a thread per core in each, so 4 threads spun on
# 2 cores. The oblique Hertz ball of `make friction` took 8.0 s of CPU and 4.6 s alone with them, 3.1 s and 3.5 s with
# one (2026-11-28); its history moves only by round-off (docs/tests.md).
for _blas_threads in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS"):
    os.environ.setdefault(_blas_threads, "1")

# Every run that make check makes is audited by its own physics (postprocess/audit.py, which edp/run.sh calls after
# a run that reached T: exit 6 where its files fail it), whatever the caller's environment says (CONTACT_AUDIT=0 is a
# user's way to skip it, never the tests').
os.environ["CONTACT_AUDIT"] = "1"

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
    # St Venant-Kirchhoff (Section 3); with the paper's lambda = mu = 30 the body
    # collapses at t = 16.8 in Test 1 (test_svk.py), so these stop before that
    "svk_test1": ("test1", ["-material", "svk", "-T", "16.5"]),
    "svk_test1_every_step": ("test1", ["-material", "svk", "-T", "12", "-skip_free", "0"]),
    "svk_test2_t1_18": ("test2", ["-material", "svk", "-T", "19", "-t1", "18"]),
    "svk_stiff_test1": ("test1", ["-material", "svk", "-lambda", "300", "-mu", "300", "-T", "45"]),
    "svk_incline": ("incline", ["-material", "svk", "-T", "10"]),
    "svk_oblique": ("oblique", ["-material", "svk", "-T", "15"]),
    "svk_spin": ("spin", ["-material", "svk"]),
    "svk_spin_rho2": ("spin", ["-material", "svk", "-rho", "2", "-T", "10", "-snapshots", "none"]),
    "linear_spin": ("spin", []),
    # f = 0 (Prop. 2): a fixed and a decreasing foundation
    "svk_f0_fixed": ("test1", ["-material", "svk", "-fy", "0", "-v0y", "-0.5", "-u0y", "1", "-T", "20"]),
    "svk_f0_falling": ("test2", ["-material", "svk", "-fy", "0", "-v0y", "-0.5", "-u0y", "1", "-t0", "2", "-t1", "8",
                                 "-T", "20"]),
}
# any body, any mesh: Gamma_D, the new scenes, P2, CSM3 (tests/test_geometry.py)
COARSE = os.path.join(ROOT, "meshes", "disk_coarse.msh")
RUNS.update({
    "cantilever_activeset": ("cantilever", ["-T", "10", "-solver", "activeset", "-probes", "0,1.5,10,1.5", "-snapshots", "5"]),
    "cantilever_ipopt": ("cantilever", ["-T", "10", "-probes", "0,1.5,10,1.5", "-snapshots", "5"]),
    "cantilever_svk": ("cantilever", ["-T", "10", "-material", "svk", "-probes", "0,1.5,10,1.5", "-snapshots", "5"]),
    "cantilever_p2": ("cantilever", ["-T", "10", "-order", "2", "-solver", "activeset", "-probes", "0,1.5,10,1.5", "-snapshots", "5"]),
    "ring": ("ring", ["-solver", "activeset"]),
    "ring_svk": ("ring", ["-material", "svk"]),
    "corner": ("corner", ["-solver", "activeset"]),
    "corner_svk": ("corner", ["-material", "svk"]),
    "p2_test1": ("test1", ["-order", "2", "-solver", "activeset", "-T", "20", "-probes", "0,40"]),
    "p1_test1_probe": ("test1", ["-solver", "activeset", "-T", "20", "-probes", "0,40"]),
    "p1_fine_test1_probe": ("test1", ["-solver", "activeset", "-T", "20", "-probes", "0,40", "-snapshots", "none",
                                      "-mesh", os.path.join(ROOT, "meshes", "disk_fine.msh")]),
    "p2_coarse_activeset": ("test1", ["-order", "2", "-solver", "activeset", "-T", "14", "-mesh", COARSE]),
    "p2_coarse_ipopt": ("test1", ["-order", "2", "-T", "14", "-mesh", COARSE]),
    "p2_coarse_svk": ("test1", ["-order", "2", "-material", "svk", "-T", "14", "-mesh", COARSE]),
    "csm3_short": ("csm3", ["-T", "0.5"]),
    "csm3_short_initial": ("csm3", ["-T", "0.5", "-newton_precond", "initial"]),
    "cantilever_svk_step": ("cantilever", ["-T", "10", "-material", "svk", "-probes", "0,1.5,10,1.5", "-snapshots", "5",
                                           "-newton_precond", "step"]),
})
# the methods of docs/methods.md (tests/test_methods.py): mass, contact enforcement
REST = ["-u0y", "0", "-T", "10", "-probes", "0,40"]           # the disk resting on the foundation under gravity
F0_IMPACT = ["-fy", "0", "-v0y", "-0.5", "-u0y", "1", "-T", "40"]   # f = 0: one impact and the rebound
PENALTY_EPS = ("1e-2", "1e-3", "1e-4")
NITSCHE_GAMMA0 = ("1e3", "1e4", "1e5")
RUNS.update({
    "rest_constraint": ("test1", ["-solver", "activeset"] + REST),
    **{f"rest_penalty_{e}": ("test1", ["-contact", "penalty", "-penalty_eps", e] + REST) for e in PENALTY_EPS},
    "methods_singular": ("test1", ["-mass", "singular", "-solver", "activeset", "-T", "30"]),
    "methods_singular_ipopt": ("test1", ["-mass", "singular", "-T", "30", "-tol", "1e-10"]),
    "methods_lumped": ("test1", ["-mass", "lumped", "-solver", "activeset", "-T", "30"]),
    "methods_lumped_ipopt": ("test1", ["-mass", "lumped", "-T", "30", "-tol", "1e-10"]),
    "methods_penalty": ("test1", ["-contact", "penalty", "-penalty_eps", "1e-3", "-T", "30"]),
    "methods_penalty_test2": ("test2", ["-contact", "penalty", "-penalty_eps", "1e-3", "-T", "30"]),
    **{f"f0_{m}": ("test1", ["-mass", m, "-solver", "activeset"] + F0_IMPACT) for m in ("consistent", "singular", "lumped")},
    # the same impact at dt / 2 and dt / 4: the energy lost over it as dt -> 0
    **{f"f0_{m}_dt{dt}": ("test1", ["-mass", m, "-solver", "activeset", "-dt", dt] + F0_IMPACT)
       for m in ("consistent", "singular") for dt in ("0.025", "0.0125")},
    "f0_penalty": ("test1", ["-contact", "penalty"] + F0_IMPACT),
    **{f"freeflight_{m}": ("freeflight", ["-mass", m]) for m in ("lumped", "singular")},
    "penalty_p2": ("test1", ["-order", "2", "-contact", "penalty", "-T", "14", "-mesh", COARSE]),
    "cantilever_penalty": ("cantilever", ["-T", "10", "-contact", "penalty", "-penalty_eps", "1e-4", "-probes", "0,1.5,10,1.5",
                                          "-snapshots", "5"]),
    # Nitsche (theta 1, 0, -1), its limit gamma0 -> infinity, with Verlet as in [3], on a clamped body
    **{f"nitsche_theta{th}": ("test1", ["-contact", "nitsche", "-nitsche_theta", th, "-T", "30"]) for th in ("1", "0", "-1")},
    **{f"rest_nitsche_{g}": ("test1", ["-contact", "nitsche", "-nitsche_gamma0", g] + REST) for g in NITSCHE_GAMMA0},
    "verlet_nitsche": ("test1", ["-scheme", "verlet", "-contact", "nitsche", "-dt", "0.01", "-T", "30"]),
    "f0_nitsche": ("test1", ["-contact", "nitsche", "-nitsche_theta", "-1"] + F0_IMPACT),
    "cantilever_nitsche": ("cantilever", ["-T", "10", "-contact", "nitsche", "-probes", "0,1.5,10,1.5", "-snapshots", "5"]),
    # schemes: Newmark (classical gamma = 1/2, and damped), explicit Verlet with penalty
    # (the classical Newmark (1/4, 1/2) stops when its energy grows: tests/test_promises.py)
    "newmark_damped": ("test1", ["-scheme", "newmark", "-newmark_gamma", "0.6", "-newmark_beta", "0.3025", "-solver", "activeset",
                                 "-T", "30"]),
    "newmark_damped_test2": ("test2", ["-scheme", "newmark", "-newmark_gamma", "0.6", "-newmark_beta", "0.3025",
                                       "-contact", "penalty", "-T", "30"]),
    "newmark_freeflight": ("freeflight", ["-scheme", "newmark"]),
    "verlet_penalty": ("test1", ["-scheme", "verlet", "-contact", "penalty", "-dt", "0.01", "-T", "30"]),
    "verlet_freeflight": ("freeflight", ["-scheme", "verlet", "-dt", "0.04"]),
    "verlet_p2": ("test1", ["-scheme", "verlet", "-contact", "penalty", "-order", "2", "-dt", "0.005", "-T", "12",
                                   "-mesh", COARSE]),
    "cantilever_lumped": ("cantilever", ["-T", "10", "-mass", "lumped", "-solver", "activeset", "-probes", "0,1.5,10,1.5",
                                         "-snapshots", "5"]),
})
# -contact_quadrature gauss (tests/test_quadrature.py): penalty and Nitsche with their contact term on
# Gauss points; the vertex runs above are their counterparts
GAUSS = ["-contact_quadrature", "gauss"]
NITSCHE_GAMMA0_GAUSS = ("1e4", "1e5", "1e6")
RUNS.update({
    **{f"rest_penalty_gauss_{e}": ("test1", ["-contact", "penalty", "-penalty_eps", e] + GAUSS + REST) for e in PENALTY_EPS},
    **{f"rest_nitsche_gauss_{g}": ("test1", ["-contact", "nitsche", "-nitsche_gamma0", g] + GAUSS + REST)
       for g in NITSCHE_GAMMA0_GAUSS},
    "f0_penalty_gauss": ("test1", ["-contact", "penalty"] + GAUSS + F0_IMPACT),
    "penalty_gauss": ("test1", ["-contact", "penalty", "-penalty_eps", "1e-3", "-T", "30"] + GAUSS),
    "nitsche_gauss_theta1": ("test1", ["-contact", "nitsche", "-nitsche_theta", "1", "-T", "30"] + GAUSS),
    "verlet_nitsche_gauss": ("test1", ["-scheme", "verlet", "-contact", "nitsche", "-dt", "0.01", "-T", "30"] + GAUSS),
    "verlet_penalty_gauss": ("test1", ["-scheme", "verlet", "-contact", "penalty", "-dt", "0.01", "-T", "30"] + GAUSS),
    "penalty_gauss_test2": ("test2", ["-contact", "penalty", "-penalty_eps", "1e-3", "-T", "30"] + GAUSS),
    "nitsche_gauss_test2": ("test2", ["-contact", "nitsche", "-T", "20", "-snapshots", "none"] + GAUSS),
    "nitsche_incline": ("incline", ["-contact", "nitsche", "-T", "10", "-snapshots", "none"]),
    "nitsche_gauss_incline": ("incline", ["-contact", "nitsche", "-T", "10", "-snapshots", "none"] + GAUSS),
    "newmark_gauss_incline": ("incline", ["-scheme", "newmark", "-newmark_gamma", "0.6", "-newmark_beta", "0.3025",
                                          "-contact", "penalty", "-T", "10", "-snapshots", "none"] + GAUSS),
    "penalty_gauss_p2": ("test1", ["-order", "2", "-contact", "penalty", "-T", "14", "-mesh", COARSE] + GAUSS),
    "cantilever_penalty_gauss": ("cantilever", ["-T", "10", "-contact", "penalty", "-penalty_eps", "1e-4",
                                                "-probes", "0,1.5,10,1.5", "-snapshots", "5"] + GAUSS),
})
# the Neo-Hookean body: the paper's Test 1 and Test 2 to T = 120 (SVK collapses at t = 16.8),
# a spinning free flight, its dt-convergence, f = 0 impacts, P2
NH = ["-material", "neohookean"]
NH_SPIN_DTS = ("0.1", "0.05", "0.025")
RUNS.update({
    "neohookean_test1": ("test1", NH + ["-T", "120", "-snapshots", "15.25"]),
    # (t1 = 18 to the paper's horizon; 22 and 26 past their first rebound, T = 45)
    **{f"neohookean_test2_t1_{t1}": ("test2", NH + ["-T", T, "-t1", t1, "-snapshots", "none"])
       for t1, T in (("18", "120"), ("22", "45"), ("26", "45"))},
    "neohookean_spin": ("spin", NH + ["-snapshots", "none"]),
    **{f"neohookean_spin_dt{dt}": ("spin", NH + ["-dt", dt, "-T", "10", "-snapshots", "none", "-probes", "0,40,20,20"])
       for dt in NH_SPIN_DTS},
    "neohookean_f0_fixed": ("test1", NH + ["-fy", "0", "-v0y", "-0.5", "-u0y", "1", "-T", "20"]),
    "neohookean_f0_falling": ("test2", NH + ["-fy", "0", "-v0y", "-0.5", "-u0y", "1", "-t0", "2", "-t1", "8", "-T", "20"]),
    "p2_coarse_neohookean": ("test1", NH + ["-order", "2", "-T", "14", "-mesh", COARSE]),
    # a hard step: dt = 1 (the predictor inverts triangles; make stress has v0y = -5)
    "neohookean_dt1": ("test1", NH + ["-dt", "1", "-T", "40", "-snapshots", "none"]),
})
# every other scene with the Neo-Hookean body, on short horizons (scene: options)
NH_SCENES = {"bump": ["-T", "30"], "cantilever": ["-T", "10"], "corner": [], "csm3": ["-T", "0.5"], "freeflight": [],
             "incline": ["-T", "10"], "oblique": ["-T", "15"], "ring": [], "rising": ["-T", "20"], "wave": ["-T", "25"]}
RUNS.update({f"neohookean_scene_{scene}": (scene, NH + ["-snapshots", "none"] + args) for scene, args in NH_SCENES.items()})
# the small-strain limit: the disk resting on the foundation under a load scaled by s
SMALL_LOADS = (0.4, 0.2, 0.1)
for _s in SMALL_LOADS:
    for _m in ("svk", "neohookean", "linear"):
        RUNS[f"rest_{_m}_{_s}"] = ("test1", ["-material", _m, "-u0y", "0", "-fy", f"{-0.1 * _s:g}", "-T", "10",
                                             "-probes", "0,40"] + (["-solver", "activeset"] if _m == "linear" else []))
# the fast subset of make stress (postprocess/stress_cases.py)
RUNS.update({f"stress: {name}": case_args(name, horizon) for name, horizon in FAST.items()})
# runs allowed to stop with exit 4 (an SVK stress case that may collapse); the
# stress test then accepts it only as the clean break (postprocess/stress.py)
MAY_EXIT_4 = {f"stress: {name}" for name in FAST if may_break(name)}
# name: (exit status, stderr) of every run of the `runs` fixture
RUN_STATUS = {}


def run_scene(scene, out, args, check=True, env=None, **kwargs):
    """edp/run.sh SCENE OUT ARGS (with FORCE=1); returns the CompletedProcess."""
    p = subprocess.run([RUN, scene, str(out)] + list(args), capture_output=True, text=True,
                       env=dict(os.environ, FORCE="1", **(env or {})), **kwargs)
    if check and p.returncode != 0:
        raise AssertionError(f"{scene} {' '.join(args)} failed ({p.returncode}):\n{p.stdout}\n{p.stderr}")
    return p


def make(args, **kwargs):
    """make ARGS in the repository, as a user types it (not as a sub-make of make check's make)."""
    env = {k: v for k, v in os.environ.items() if k not in ("MAKEFLAGS", "MFLAGS", "MAKELEVEL", "MAKEOVERRIDES")}
    env.update(kwargs.pop("env", {}))
    return subprocess.run(["make"] + args, cwd=ROOT, capture_output=True, text=True, env=env, **kwargs)


def run_scenes(base, runs):
    """Every run of runs (name: (scene, args)) into base/name, two at a time; returns name: directory."""
    from concurrent.futures import ThreadPoolExecutor
    with ThreadPoolExecutor(2) as pool:
        list(pool.map(lambda item: run_scene(item[1][0], base / item[0], item[1][1]), runs.items()))
    return {name: str(base / name) for name in runs}


def restart_reproduces(scene, base, args, split, end):
    """SCENE ARGS run to T = split and restarted to T = end, against one run to T = end: their history.csv and
    checkpoint.txt must be byte-identical. Returns the restarted run's directory."""
    first, straight = base / "first", base / "straight"
    run_scene(scene, first, args + ["-T", str(split)])
    run_scene(scene, first, ["-restart", str(first), "-T", str(end), "-progress", "0"])
    run_scene(scene, straight, args + ["-T", str(end)])
    for name in ("history.csv", "checkpoint.txt"):
        assert (first / name).read_bytes() == (straight / name).read_bytes(), name
    return first


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


def square_mesh(path, physical, x0=0, y0=0, side=1, size=1):
    """gmsh meshes the square [x0, x0 + side] x [y0, y0 + side] (lines 1-4: bottom, right, top, left)
    into path (a .msh, MSH 2.2; its .geo beside it), with `physical` the Physical Curve lines
    ("Physical Curve(1)={1};..."). Returns path."""
    x1, y1 = x0 + side, y0 + side
    geo = str(path)[:-4] + ".geo"
    with open(geo, "w") as f:
        f.write(f"Point(1)={{{x0},{y0},0,{size}}};Point(2)={{{x1},{y0},0,{size}}};Point(3)={{{x1},{y1},0,{size}}};"
                f"Point(4)={{{x0},{y1},0,{size}}};Line(1)={{1,2}};Line(2)={{2,3}};Line(3)={{3,4}};Line(4)={{4,1}};"
                f"Curve Loop(1)={{1,2,3,4}};Plane Surface(1)={{1}};Physical Surface(1)={{1}};{physical}\n")
    subprocess.run(["gmsh", "-2", "-format", "msh22", geo, "-o", str(path)], check=True, capture_output=True)
    return path


def refused_into_copy(tmp_path, earlier, scene, args, env=None, **kwargs):
    """Run SCENE ARGS with FORCE=1 into a copy of the earlier run; returns the process
    and whether any file of the earlier run changed."""
    out = tmp_path / "copy"
    shutil.copytree(earlier, out)
    before = files_of(out)
    p = run_scene(scene, out, args, check=False, env=env, **kwargs)
    return p, files_of(out) != before


def shared_directory(tmp_path_factory, name):
    """A directory every worker of this session sees: under pytest-xdist (make check's -n 2) each worker has its
    own base temporary directory, popen-gwN, in one directory of the session."""
    base = tmp_path_factory.getbasetemp()
    if os.environ.get("PYTEST_XDIST_WORKER"):
        base = base.parent
    directory = base / name
    directory.mkdir(exist_ok=True)
    return directory


@pytest.fixture(scope="session")
def runs(tmp_path_factory):
    """Every run of RUNS, made once per session whatever the workers: each worker claims the runs no other has
    claimed (an exclusive file beside the run) and makes them, one at a time under pytest-xdist (the other worker
    keeps the second core busy), two at a time alone; then it waits for the runs the other worker claimed. A run's
    exit status is written beside it once it has ended (NAME.status), its stdout and stderr are NAME.stdout and
    NAME.stderr."""
    base = shared_directory(tmp_path_factory, "runs")
    at_once = 1 if os.environ.get("PYTEST_XDIST_WORKER") else 2
    pending = list(RUNS.items())
    active = []
    while pending or active:
        while pending and len(active) < at_once:
            name, (scene, args) = pending.pop(0)
            out = str(base / name)
            try:
                os.close(os.open(f"{out}.claim", os.O_CREAT | os.O_EXCL | os.O_WRONLY))
            except FileExistsError:
                continue                 # (another worker makes it)
            # stdout and stderr to files beside the run (the stress test reads stderr alone)
            logs = (open(f"{out}.stdout", "w"), open(f"{out}.stderr", "w"))
            proc = subprocess.Popen([RUN, scene, out, "-progress", "0", "-vtk", "0"] + args,
                                    stdout=logs[0], stderr=logs[1], text=True, env=dict(os.environ, FORCE="1"))
            active.append((out, proc, logs))
        time.sleep(0.2)
        for item in list(active):
            out, proc, logs = item
            if proc.poll() is not None:
                for f in logs:
                    f.close()
                with open(f"{out}.status.part", "w") as f:
                    f.write(f"{proc.returncode}\n")
                os.replace(f"{out}.status.part", f"{out}.status")
                active.remove(item)
    for name in RUNS:
        out = str(base / name)
        waited = 0
        while not os.path.exists(f"{out}.status"):
            assert waited < 7200, f"run {name}: the worker that claimed it has not ended it in 2 hours"
            time.sleep(0.5)
            waited += 0.5
        with open(f"{out}.status") as f:
            status = int(f.read())
        stdout, stderr = (open(f"{out}.{k}").read() for k in ("stdout", "stderr"))
        RUN_STATUS[name] = (status, stderr)
        allowed = (0, 4) if name in MAY_EXIT_4 else (0,)
        assert status in allowed, f"run {name} failed ({status}):\n{stdout}{stderr}"
    return {name: str(base / name) for name in RUNS}


@pytest.fixture(scope="session")
def run_status(runs):
    """name: (exit status, stderr) of each run."""
    return RUN_STATUS


@pytest.fixture(scope="session")
def histories(runs):
    return {name: read_run(d) for name, d in runs.items()}
