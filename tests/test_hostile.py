"""Hostile inputs, generated, against the suite's contract (docs/errors.md), and the classes they found, each fixed at
its depth and kept here as a test of its own.

The generative test (Hypothesis, Debian's python3-hypothesis) draws what a demanding user might give: option values of
every kind (extremes, NaN, inf, negatives, wrong types, lists with bad separators, an option given twice, unknown keys),
scenes with a piece missing or wrong, mutated meshes (a label removed, a node off the plane, an inverted element, a
node twice, a truncated file), restarts with changed options or meshes, and signals at random times. Every case runs
into a copy of an earlier run, and must keep the contract:
  - the exit status is one of docs/errors.md's table, and never 1 (a bug in the suite) nor 6 (the run fails its own
    audit): a user's mistake is refused, exit 3;
  - a refusal is one error line that names what is at fault (an option given, the scene, the mesh, the restart), and
    leaves the earlier run byte-identical;
  - exit 0 means the run reached T and its files pass the audit (postprocess/audit.py, run again here).
make check runs it with a fixed seed (HOSTILE_SEED) and HOSTILE_EXAMPLES cases (100: about 1.5 minutes); `make hostile`
runs it again and again with fresh seeds for 30 minutes (tests/hostile.py) and prints the shrunk counterexamples."""
import os
import random
import shutil
import signal
import subprocess
import sys
import tempfile
import time

import pytest
from hypothesis import HealthCheck, given, note, seed, settings, strategies as st

from conftest import ROOT, RUN, error_lines, files_of, make, run_scene
from history import read_run

sys.path.insert(0, os.path.join(ROOT, "postprocess"))
sys.path.insert(0, os.path.join(ROOT, "tests"))
import audit  # noqa: E402
import parameter_table  # noqa: E402

MESHES = os.path.join(ROOT, "meshes")
COARSE = os.path.join(MESHES, "disk_coarse.msh")
BALL = os.path.join(MESHES, "hertz_coarse.msh")
QUIET = ["-progress", "0"]
# every run of a case is short: the coarse disk, T = 0.2 and at most 400 steps unless the case says otherwise
BASE = {"-T": "0.2", "-max_steps": "400", "-mesh": COARSE}
SIGNALLED = {-signal.SIGTERM, -signal.SIGINT, -signal.SIGHUP}
DOCUMENTED = {0, 3, 4, 5, 7, 8}
EXAMPLES = int(os.environ.get("HOSTILE_EXAMPLES", "100"))
SEED = int(os.environ.get("HOSTILE_SEED", "20261207"))
TIMEOUT = 40            # seconds a case may run before it is sent SIGTERM (a slow case is no failure: its signal is)

KEYS = [row["key"] for row in parameter_table.rows()]
NASTY = ["", "nan", "NaN", "inf", "-inf", "1e300", "-1e300", "1e-300", "-1e-300", "1e400", "1e-400", "0", "-0", "-1",
         "abc", "1,2", "1;2", "1,,2", "1 2", ",", "0x10", "1e", "2147483648", "99999999999999999999", "none", "flat",
         "bowl", "wave", "user", "gauss", "activeset", "ipopt", "newton", "svk", "neohookean", "penalty", "nitsche",
         "exact", "static", "every:0.1", "every:", "0,0.1", "3,1e400", "0.05", "0.1", "30", "2", "1", "0.5",
         COARSE, BALL, os.path.join(MESHES, "ring.msh"), os.path.join(MESHES, "nothing.msh"), MESHES]


def run_case(args, out, scene="test1", env=None, timeout=TIMEOUT):
    """edp/run.sh SCENE OUT ARGS (FORCE=1), sent SIGTERM after `timeout` s: (status, stdout, stderr)."""
    p = subprocess.Popen([RUN, scene, str(out)] + list(args), stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                         env=dict(os.environ, FORCE="1", **(env or {})), start_new_session=True)
    try:
        stdout, stderr = p.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        os.kill(p.pid, signal.SIGTERM)
        stdout, stderr = p.communicate()
    return p.returncode, stdout, stderr


def keep_contract(status, stdout, stderr, out, before, at_fault, args):
    """The suite's contract for one case (the module's docstring). at_fault: the words a refusal may name; before:
    the files of OUT before the case (None: OUT did not exist)."""
    note(f"args {args}\nstatus {status}\nstderr {stderr[-1500:]}")
    assert status in DOCUMENTED | SIGNALLED, f"exit {status}, not a documented status: {stderr[-600:]}"
    errors = [line for line in stderr.splitlines() if line.startswith("error:")]
    if status == 0:
        assert not errors, errors
        assert (out / "summary.txt").exists()
        assert audit.audit_run(str(out)) == []
        return
    if status in SIGNALLED:
        rows = open(out / "history.csv").read() if (out / "history.csv").exists() else ""
        assert rows == "" or rows.endswith("\n")           # no partial row
        return
    assert len(errors) == 1, f"exit {status} with {len(errors)} error lines: {stderr[-600:]}"
    if status == 3:
        assert any(word in errors[0] for word in at_fault), f"the refusal names none of {at_fault}: {errors[0]}"
        if before is None:
            assert not out.exists(), "a refused run into a new directory left it behind"
        else:
            assert files_of(out) == before, "a refused run changed the earlier run's files"


@pytest.fixture(scope="module")
def earlier(tmp_path_factory):
    """A finished run on the coarse disk with snapshots, VTU files and checkpoints (every 5 steps, and at T)."""
    out = tmp_path_factory.mktemp("hostile_earlier") / "run"
    run_scene("test1", out, ["-T", "0.5", "-mesh", COARSE, "-snapshots", "0,0.25", "-checkpoint_every", "5"] + QUIET)
    return out


def with_base(args, given, scene):
    """args, then BASE's options that the case does not give (the ball on its coarse mesh)."""
    base = dict(BASE, **({"-mesh": BALL} if scene == "ball" else {}))
    return args + [item for key, value in base.items() if key[1:] not in given for item in (key, value)]


def copy_of(earlier, base):
    out = base / "out"
    shutil.copytree(earlier, out)
    return out, files_of(out)


# ---- the strategies
values = st.one_of(st.sampled_from(NASTY), st.floats(allow_nan=True, allow_infinity=True).map(repr),
                   st.integers(-10 ** 12, 10 ** 12).map(str), st.text(alphabet="0123456789.,-+e:;x ", max_size=8))
option_lists = st.lists(st.tuples(st.sampled_from(KEYS + ["dtt", "Lambda", "np"]), values), min_size=1, max_size=3)


@st.composite
def option_cases(draw):
    options = draw(option_lists)
    scene = draw(st.sampled_from(["test1", "test2", "incline", "oblique", "bump", "wave", "ball"]))
    args, given = [], set()
    for key, value in options:
        args += ["-" + key, value]
        given.add(key)
    args = with_base(args, given, scene)
    if draw(st.booleans()) and draw(st.integers(0, 9)) == 0:
        args = args[:-1]                              # a key without its value
    return "options", scene, args, sorted(given) + ["T", "max_steps", "mesh", "scene"]


# values a user means, in combinations the tests did not name: each run must reach T and pass its audit, or be
# refused or stopped by a documented line
MEANT = {
    "friction": ["none", "tresca", "coulomb"], "friction_coefficient": ["0", "1e-300", "0.1", "1", "1e30"],
    "friction_bound": ["1e-300", "0.05", "1e30"], "gap": ["exact", "linearised"], "initial": ["static", "given"],
    "contact": ["penalty", "nitsche", "constraint"], "contact_quadrature": ["gauss", "vertex"],
    "scheme": ["newmark", "verlet", "midpoint"], "mass": ["lumped", "singular"], "material": ["svk", "neohookean"],
    "solver": ["ipopt", "activeset", "newton"], "angle": ["10", "-30", "59"], "foundation": ["bowl", "wave", "cosine", "none"],
    "foundation_velocity": ["-0.1", "0.1"], "fy": ["0", "-1e-6", "1e-3", "-1"], "fx": ["0.05"], "v0x": ["0.5", "-3"],
    "v0y": ["-5", "-0.5"], "spin": ["0.1"], "dt": ["0.01", "0.2", "1"], "order": ["2"], "belt_speed": ["0.3"],
    "level": ["-1", "3"], "u0y": ["0", "1e6"], "bowl_radius": ["1e6", "30"], "T": ["0.3", "1"], "rho": ["1e-6", "1e6"],
    "lambda": ["1e-3", "1e6"], "probes": ["0,40", "0,1e9"], "reference": ["0,40"], "diagnostics_every": ["3"],
    "snapshots": ["every:0.1", "0.1"], "vtk": ["0"], "checkpoint_every": ["1"], "tol": ["1e-6"],
}


@st.composite
def meant_cases(draw):
    keys = draw(st.lists(st.sampled_from(sorted(MEANT)), min_size=2, max_size=4, unique=True))
    scene = draw(st.sampled_from(["test1", "incline", "oblique", "ball"]))
    args = []
    for key in keys:
        args += ["-" + key, draw(st.sampled_from(MEANT[key]))]
    return "options", scene, with_base(args, set(keys), scene), keys + ["T", "max_steps", "mesh", "scene"]


SCENE_PIECES = {
    "foundation": ['foundation = "user";', 'foundation = "bowl";', 'foundation = "wave";', 'foundation = "moon";'],
    "psi": ["macro userFoundationPsi(X1, t) (0.01 * X1^2) // EOM"],
    "dpsi": ["macro userFoundationDpsi(X1, t) (0.02 * X1) // EOM", "macro userFoundationDpsi(X1, t) (0.5) // EOM"],
    "assign": ["dt = 0.1;", "lambda = -5;", "T = 0.15;", "fy = 1e300;", "mu = nan;", 'solver = "activeset";',
               'snapshots = "0.1";', "order = 2;", "dt = 1e-400;"],
    "derived": ["macro sceneDerived() { dt = 0.1; lambda = 50; } // EOM", "macro sceneDerived() T = 0.1; // EOM"],
    "print": ['cout << "hello from the scene";', 'cout << "exit-status 7" << endl;', 'cout << "choice-order 2" << endl;'],
}


@st.composite
def scene_cases(draw):
    lines = ["// a generated scene"]
    for piece, choices in SCENE_PIECES.items():
        if draw(st.booleans()):
            lines.append(draw(st.sampled_from(choices)))
    lines.append('meshFile = "' + COARSE + '";')
    args = []
    for key, value in draw(st.lists(st.tuples(st.sampled_from(["dt", "lambda", "T", "fy"]), values), max_size=1)):
        args += ["-" + key, value]
    if "-T" not in args:
        args += ["-T", "0.2"]
    return "scene", "\n".join(lines) + "\n", args + ["-max_steps", "400"], ["scene", "userFoundation", "-foundation", "-dt", "-lambda", "-T",
                                                                             "-fy", "-mu", "-max_steps", "-snapshots",
                                                                             "-order", "-solver"]


def mutate_mesh(text, mutation, k):
    lines = text.split("\n")
    nodes, elements = lines.index("$Nodes"), lines.index("$Elements")
    n_nodes, n_elements = int(lines[nodes + 1]), int(lines[elements + 1])
    node_lines = range(nodes + 2, nodes + 2 + n_nodes)
    element_lines = range(elements + 2, elements + 2 + n_elements)
    triangles = [i for i in element_lines if lines[i].split()[1] == "2"]
    edges = [i for i in element_lines if lines[i].split()[1] == "1"]
    if mutation == "label removed":
        tag = lines[edges[k % len(edges)]].split()[3]
        kept = [lines[i] for i in element_lines if not (lines[i].split()[1] == "1" and lines[i].split()[3] == tag)]
        lines[elements + 1:elements + 2 + n_elements] = [str(len(kept))] + kept
    elif mutation == "label changed":
        f = lines[edges[k % len(edges)]].split()
        f[3] = "7"
        lines[edges[k % len(edges)]] = " ".join(f)
    elif mutation == "off the plane":
        f = lines[node_lines[k % n_nodes]].split()
        f[3] = "1"
        lines[node_lines[k % n_nodes]] = " ".join(f)
    elif mutation == "inverted":
        f = lines[triangles[k % len(triangles)]].split()
        f[-1], f[-2] = f[-2], f[-1]
        lines[triangles[k % len(triangles)]] = " ".join(f)
    elif mutation == "node twice":
        lines.insert(node_lines[k % n_nodes], lines[node_lines[k % n_nodes]])
        lines[nodes + 1] = str(n_nodes + 1)
    elif mutation == "node added":
        f = lines[node_lines[k % n_nodes]].split()
        f[0] = str(n_nodes + 100)
        lines.insert(nodes + 2 + n_nodes, " ".join(f))
        lines[nodes + 1] = str(n_nodes + 1)
    elif mutation == "truncated":
        lines = lines[:max(3, k % len(lines))]
    return "\n".join(lines)


mesh_cases = st.tuples(st.just("mesh"), st.sampled_from(["label removed", "label changed", "off the plane", "inverted",
                                                         "node twice", "node added", "truncated"]),
                       st.integers(0, 10 ** 6))
restart_changes = st.lists(st.tuples(st.sampled_from(["T", "dt", "lambda", "mesh", "order", "material", "snapshots",
                                                      "vtk", "checkpoint_every", "max_steps", "solver", "fy"]),
                                     st.sampled_from(["0.25", "0.5", "0.75", "1", "0.025", "40", "2", "svk", "0",
                                                      "0,0.25,0.75", "3", "activeset", "-0.2", COARSE, BALL,
                                                      os.path.join(MESHES, "disk.msh")])), max_size=2)
restart_cases = st.tuples(st.just("restart"), restart_changes, st.booleans())
signal_cases = st.tuples(st.just("signal"), st.sampled_from([signal.SIGTERM, signal.SIGINT, signal.SIGHUP]),
                         st.floats(0.05, 2.0))
cases = st.one_of(option_cases(), meant_cases(), meant_cases(), scene_cases(), mesh_cases, restart_cases, signal_cases)


@seed(SEED)
@settings(max_examples=EXAMPLES, deadline=None, database=None, derandomize=False,
          suppress_health_check=list(HealthCheck))
@given(case=cases)
def test_hostile_inputs_keep_the_contract(earlier, tmp_path_factory, case):
    """Every generated case keeps the contract of the module's docstring."""
    base = tmp_path_factory.mktemp("hostile")
    out, before = copy_of(earlier, base)
    kind = case[0]
    if kind == "options":
        _, scene, args, at_fault = case
        status, stdout, stderr = run_case(args + QUIET, out, scene)
        keep_contract(status, stdout, stderr, out, before, at_fault + ["-" + k for k in at_fault], args)
    elif kind == "scene":
        _, text, args, at_fault = case
        scene = base / "generated.idp"
        scene.write_text(text)
        note(text)
        status, stdout, stderr = run_case(args + QUIET, out, str(scene))
        keep_contract(status, stdout, stderr, out, before, at_fault + [str(scene)], args)
    elif kind == "mesh":
        _, mutation, k = case
        mesh = base / "mutated.msh"
        mesh.write_text(mutate_mesh(open(COARSE).read(), mutation, k))
        args = ["-mesh", str(mesh), "-T", "0.2"]
        status, stdout, stderr = run_case(args + QUIET, out)
        keep_contract(status, stdout, stderr, out, before, ["-mesh", str(mesh)], [mutation, k])
    elif kind == "restart":
        _, changes, into_itself = case
        args = ["-restart", str(out)]
        for key, value in changes:
            args += ["-" + key, value]
        target = out if into_itself else base / "other"
        status, stdout, stderr = run_case(args + QUIET, target)
        at_fault = ["-restart"] + ["-" + key for key, _ in changes] + [str(out)]
        if into_itself:
            keep_contract(status, stdout, stderr, out, before, at_fault, args)
        else:
            keep_contract(status, stdout, stderr, target, None, at_fault, args)
            assert files_of(out) == before, "a restart into another directory changed the run it read"
    else:
        _, sig, after = case
        p = subprocess.Popen([RUN, "test1", str(out), "-T", "20", "-mesh", COARSE] + QUIET, stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE, text=True, env=dict(os.environ, FORCE="1"), start_new_session=True)
        time.sleep(after)
        p.send_signal(sig)
        stdout, stderr = p.communicate(timeout=60)
        keep_contract(p.returncode, stdout, stderr, out, before, [], [sig, after])
        if p.returncode in SIGNALLED and (out / "checkpoint.txt").exists() and not (out / "summary.txt").exists():
            status, stdout, stderr = run_case(["-restart", str(out)] + QUIET, out)   # and the run continues from it
            keep_contract(status, stdout, stderr, out, files_of(out), ["-restart"], ["restart after", sig])


# ---- the classes the hostile trial found, each fixed at its depth and tested here on its own

def scene_file(tmp_path, name, text):
    path = tmp_path / f"{name}.idp"
    path.write_text("// " + name + "\n" + text)
    return str(path)


@pytest.mark.parametrize("np_args", [[], ["-np", "2", "-solver", "activeset"]], ids=["serial", "np2"])
def test_what_a_scene_prints_is_not_the_runs_protocol(tmp_path, np_args):
    """A scene's own output never steers the run: a line left without its newline (it made the run stop with exit 3 and
    no message) and a line `exit-status 7` (it made a finished -np run exit 7): both runs reach T, exit 0."""
    text = 'cout << "hello from the scene";\ncout << "exit-status 7" << endl;\nT = 0.5;\n'
    p = run_scene(scene_file(tmp_path, "printing", text), tmp_path / "out", ["-mesh", COARSE] + np_args + QUIET, check=False)
    assert p.returncode == 0 and error_lines(p) == [], p.stderr


def test_the_command_line_wins_over_scene_derived(tmp_path):
    """docs/parameters.md: the command line wins over the scene, sceneDerived included. A sceneDerived that sets -dt and
    -lambda left the run at the scene's 0.1 and 50 with -dt 0.05 -lambda 40 given, and exit 0."""
    text = "T = 0.5;\nmacro sceneDerived() { dt = 0.1; lambda = 50; } // EOM\n"
    out = tmp_path / "out"
    run_scene(scene_file(tmp_path, "derived", text), out, ["-dt", "0.05", "-lambda", "40", "-mesh", COARSE] + QUIET)
    recorded = dict(line.split(None, 1) for line in open(out / "parameters.txt").read().splitlines())
    assert float(recorded["-dt"]) == 0.05 and float(recorded["-lambda"]) == 40


def test_a_run_without_ipopt_leaves_no_ipopt_opt_and_a_finished_run_can_be_extended(tmp_path):
    """IPOPT's options are a file of the runs that use it only; and every run ends with a checkpoint at T, so that one
    shorter than -checkpoint_every steps (here 10 of 100) can be extended (`-restart OUT -T 1` was refused: no
    checkpoint), to the same rows as one run to T = 1."""
    out, straight = tmp_path / "out", tmp_path / "straight"
    args = ["-T", "0.5", "-mesh", COARSE, "-solver", "activeset", "-snapshots", "none"] + QUIET
    run_scene("test1", out, args)
    assert not (out / "ipopt.opt").exists() and (out / "checkpoint.txt").exists()
    run_scene("test1", out, ["-restart", str(out), "-T", "1"] + QUIET)
    run_scene("test1", straight, args[2:] + ["-T", "1"])
    assert open(out / "history.csv").read() == open(straight / "history.csv").read()
    run_scene("test1", tmp_path / "ipopt", ["-T", "0.1", "-mesh", COARSE, "-snapshots", "none"] + QUIET)
    assert (tmp_path / "ipopt" / "ipopt.opt").exists()


STATIC_REFUSALS = [
    (["-fy", "0"], "error: -initial static needs a load that presses the body onto the foundation (f.n < 0, n the flat's "
                   "upward normal): here f.n = 0 (-fx 0, -fy 0, -angle 0), so no static contact holds the body; use "
                   "-initial given"),
    (["-fy", "0.1"], "error: -initial static needs a load that presses the body onto the foundation (f.n < 0, n the "
                     "flat's upward normal): here f.n = 0.1 (-fx 0, -fy 0.1, -angle 0), so no static contact holds the "
                     "body; use -initial given"),
    (["-contact", "penalty"], "error: -initial static with -contact penalty is not supported: its static state is (10)'s, "
                              "the contact imposed exactly, where the penalty method's contact force would differ and the "
                              "body would not start at rest; use -contact constraint, or -initial given"),
]


@pytest.mark.parametrize("args,line", STATIC_REFUSALS, ids=["no load", "lifting load", "penalty"])
def test_initial_static_refuses_what_it_cannot_place(earlier, tmp_path, args, line):
    """-initial static claimed "at rest in static contact" for a body hanging in the air (-fy 0, 0 pressed nodes), and
    left a penalty body off rest (its force 100 against a weight of 126): refused now, exit 3, the run unchanged."""
    out, before = copy_of(earlier, tmp_path)
    p = run_scene("test1", out, ["-initial", "static", "-u0y", "0", "-T", "0.2", "-mesh", COARSE] + args + QUIET,
                  check=False)
    assert p.returncode == 3 and error_lines(p) == [line], p.stderr
    assert files_of(out) == before


def test_initial_static_names_a_load_too_light_to_rest_the_body(tmp_path):
    """The ball under f = -1e-6 presses one node, about which it turns for ever: the iterates ran 1000 times (100 s)
    and said "did not settle". They stop once the set is stable at its floor, and the line names the cause."""
    p = run_scene("ball", tmp_path / "out", ["-initial", "static", "-fz", "-1e-6", "-u0z", "0", "-T", "0.2",
                                             "-mesh", BALL, "-solver", "activeset"] + QUIET, check=False, timeout=120)
    assert p.returncode == 3 and error_lines(p)[0].startswith(
        "error: -initial static: the static contact problem did not settle: the load presses the body onto the "
        "foundation at 1 node only, about which it turns freely"), p.stderr


def test_too_many_processes_are_refused_before_any_starts(tmp_path):
    """-np 1024 on the coarse ball started about a thousand FreeFEM processes before the driver refused it: run.sh
    checks the mesh file's nodes first (0.1 s) and leaves no directory."""
    start = time.time()
    p = run_scene("ball", tmp_path / "out", ["-np", "1024", "-mesh", BALL, "-solver", "activeset", "-T", "0.1"] + QUIET,
                  check=False)
    assert p.returncode == 3 and error_lines(p) == [
        f"error: -np 1024 needs at least 50 mesh vertices per process (ffddm's subdomains and their overlap), and the "
        f"mesh {BALL} has 534: use -np 10 or fewer"], p.stderr
    assert time.time() - start < 20 and not (tmp_path / "out").exists()


def test_make_friction_says_it_does_not_use_np_and_make_sliding_refuses_a_bad_one():
    """make friction NP=2 and make sliding NP=2 ignored NP silently, and make sliding NP=abc was not refused."""
    p = make(["-n", "friction", "NP=2"])
    assert p.stdout.startswith("note: make friction runs its cases serially: every one has -friction, which does not "
                               "run on -np (docs/parallel.md); NP=2 is not used")
    p = make(["-n", "sliding", "NP=abc"])
    assert p.returncode == 2 and "NP must be a whole number of processes per run from 1 to 1024" in p.stderr
    assert "--np 2" in make(["-n", "sliding", "NP=2"]).stdout


@pytest.mark.parametrize("scene,mesh", [("oblique", COARSE), ("oblique_ball", BALL)], ids=["disk", "ball"])
def test_a_vanishing_friction_coefficient_still_does_its_work(tmp_path, scene, mesh):
    """F = 1e-300: friction_work read 0 while 15 nodes slipped (|lm_T|^2 underflowed); it is sum b_j |s_j| > 0, as
    IPOPT gave (3e-299), and below F times a normal force's work."""
    out = tmp_path / "out"
    args = ["-T", "1", "-friction", "coulomb", "-friction_coefficient", "1e-300", "-mesh", mesh, "-snapshots", "none"]
    run_scene(scene, out, args + (["-u0y", "0"] if scene == "oblique" else []) + QUIET)
    h = read_run(str(out))
    slipping = h["slip_nodes"] > 0
    assert slipping.any() and h["friction_work"][-1] > 0 and h["friction_work"][-1] < 1e-296


def test_ipopt_failure_names_its_status_and_the_exact_solver(tmp_path):
    """IPOPT with F = 1e30 stopped with "status 4" alone; the active set runs the same case cleanly."""
    args = ["-T", "0.5", "-friction", "coulomb", "-friction_coefficient", "1e30", "-snapshots", "none"] + QUIET
    p = run_scene("incline", tmp_path / "ipopt", args + ["-solver", "ipopt"], check=False)
    assert p.returncode == 4 and "(IPOPT's iterates diverged" in error_lines(p)[0] and \
        "-solver activeset solves this step exactly, without IPOPT)" in error_lines(p)[0], p.stderr
    run_scene("incline", tmp_path / "activeset", args + ["-solver", "activeset"])


def test_the_linearised_gap_is_watched_against_the_true_foundation(tmp_path):
    """Under the paper's (10), Gamma_C can sink below the true psi where it is curved (max_penetration_exact reached
    7.1% of the body's size with exit 0 and no word): beyond 1% the run ends with a warning naming it (it is (10)'s own
    error, which make sliding measures: no stop); -gap exact keeps the same run on psi."""
    p = run_scene("bowl", tmp_path / "warn", ["-gap", "linearised", "-bowl_radius", "30", "-bowl_start", "60", "-T", "40",
                                              "-mesh", COARSE] + QUIET)
    assert any(line.startswith("warning: Gamma_C went 2.8") and "7% of the body's size 40, though (10) holds" in line
               for line in p.stderr.splitlines()), p.stderr
    run_scene("bowl", tmp_path / "exact", ["-gap", "exact", "-bowl_radius", "30", "-bowl_start", "60", "-T", "10",
                                           "-mesh", COARSE] + QUIET)


def test_the_exact_gap_at_the_bowls_rim_names_the_slope(tmp_path):
    """The bowl started at 89.9 degrees failed at every dt with "a smaller -dt may help": psi is vertical there."""
    p = run_scene("bowl", tmp_path / "rim", ["-bowl_start", "89.9", "-T", "40"] + QUIET, check=False)
    assert p.returncode == 4 and "psi is nearly vertical under the pressed vertices (slope " in error_lines(p)[0] and \
        "start the body where the foundation is less steep" in error_lines(p)[0], p.stderr


def test_options_that_do_nothing_say_so(tmp_path):
    """-bowl_start with -foundation bowl outside the bowl scene did nothing, silently."""
    p = run_scene("test1", tmp_path / "out", ["-foundation", "bowl", "-bowl_start", "40", "-T", "0.1", "-mesh", COARSE]
                  + QUIET)
    assert "warning: -bowl_start has no effect: only a scene that places the body from it reads it (edp/scenes/bowl.idp's "\
           "sceneDerived), and this scene does not" in p.stderr.splitlines()


def test_a_body_far_from_its_origin_keeps_its_energy(tmp_path):
    """a(u, u) from u's deformation, not u (-bowl_radius 1e6 put the disk 5e5 away: E read -24.7 at rest and
    E - (f, u) rose by 15.7 in one step); the ball moved 1e6 along X2 the same (its E rose by 2.96, exit 6)."""
    out = tmp_path / "bowl"
    run_scene("bowl", out, ["-bowl_radius", "1e6", "-T", "4", "-mesh", COARSE] + QUIET)
    h = read_run(str(out))
    assert abs(h["energy"][0]) < 1e-9 and (h["modified_energy"][1:] - h["modified_energy"][:-1]).max() <= 1e-9
    run_scene("ball", tmp_path / "ball", ["-u0y", "1e6", "-T", "0.3", "-mesh", BALL] + QUIET)


def test_a_mesh_with_an_unlabelled_boundary_is_refused(earlier, tmp_path):
    """docs/geometry.md: every boundary edge (3D: face) carries a label. A square labelled on one side ran with
    labels FreeFEM chose and ended in exit 7 "disk full?"; a ball without its Gamma_N surface likewise."""
    square = tmp_path / "square.msh"
    square.write_text(mutate_mesh(open(COARSE).read(), "label removed", 10 ** 5))
    out, before = copy_of(earlier, tmp_path)
    p = run_scene("test1", out, ["-mesh", str(square), "-T", "0.2"] + QUIET, check=False)
    assert p.returncode == 3 and "boundary edges carry no Physical Curve label, such as the edge from" in \
        error_lines(p)[0] and files_of(out) == before, p.stderr
    lines = open(BALL).read().split("\n")
    k = lines.index("$Elements")
    elements = [e for e in lines[k + 2:k + 2 + int(lines[k + 1])] if not (e.split()[1] == "2" and e.split()[3] == "2")]
    ball = tmp_path / "ball.msh"
    ball.write_text("\n".join(lines[:k + 1] + [str(len(elements))] + elements + lines[k + 2 + int(lines[k + 1]):]))
    p = run_scene("ball", tmp_path / "ball", ["-mesh", str(ball), "-T", "0.2"] + QUIET, check=False)
    assert p.returncode == 3 and "boundary faces carry no Physical Surface label" in error_lines(p)[0], p.stderr


def test_a_restart_on_a_mesh_of_another_dimension_is_refused_by_its_name(earlier, tmp_path):
    """A 2D run restarted with a 3D -mesh was refused as "does not record -fz" (or crashed); the 3D one with a 2D mesh
    as "-reference must be one x,y pair"."""
    out, before = copy_of(earlier, tmp_path)
    p = run_scene("test1", out, ["-restart", str(out), "-mesh", BALL, "-T", "1"] + QUIET, check=False)
    assert p.returncode == 3 and error_lines(p)[0].startswith(f"error: -restart: -mesh {BALL} (a 3D body) differs from "
                                                              "the run's -mesh "), p.stderr
    assert files_of(out) == before


def test_a_scene_missing_a_macro_it_needs_is_refused(tmp_path):
    """A user foundation with userFoundationPsi and without userFoundationDpsi stopped with exit 1, "a bug in the
    suite"; it is the scene's mistake: exit 3, naming the macro."""
    text = 'foundation = "user";\nmacro userFoundationPsi(X1, t) (0.01 * X1^2) // EOM\nT = 0.5;\n'
    p = run_scene(scene_file(tmp_path, "half", text), tmp_path / "out", ["-mesh", COARSE] + QUIET, check=False)
    assert p.returncode == 3 and error_lines(p) == [
        "error: -foundation user needs the scene to define macros userFoundationPsi(X1, t) and userFoundationDpsi(X1, t); "
        "it lacks userFoundationDpsi(X1, t)"], p.stderr


def test_a_scene_psi_that_jumps_between_the_checked_points_is_named(tmp_path):
    """A user psi with a plateau between the points the foundation check samples (X1 in (0.52, 0.58), its slope macro
    0), under -gap exact: the disk sliding onto it gains energy, and the guard's line said "please report it" citing
    (10) and Prop. 2; it names the scene's psi now."""
    text = ('foundation = "user";\ngap = "exact";\nmacro userFoundationPsi(X1, t) ((X1 > 0.52) * (X1 < 0.58) * 0.2) // EOM\n'
            'macro userFoundationDpsi(X1, t) (0.) // EOM\nu0y = 0;\nv0x = 0.5;\nT = 5;\nsolver = "activeset";\n')
    p = run_scene(scene_file(tmp_path, "plateau", text), tmp_path / "out", ["-mesh", COARSE, "-snapshots", "none"] + QUIET,
                  check=False)
    assert p.returncode == 4 and "the scene's psi may jump, have a userFoundationDpsi that is not its derivative, or " \
        "move, between the points and times its check samples" in error_lines(p)[0], p.stderr


def test_the_force_columns_follow_the_method_in_effect_not_an_option(tmp_path):
    """-contact_quadrature gauss with the constraint (10) has no effect (its warning says so), but the force columns
    took the Gauss points' branch and wrote 0 while the disk was pressed: exit 6, found by make hostile. They follow
    the contact method in effect."""
    p = run_scene("incline", tmp_path / "out", ["-T", "0.3", "-contact_quadrature", "gauss", "-mesh", COARSE] + QUIET)
    assert "warning: -contact_quadrature has no effect" in p.stderr
    assert read_run(str(tmp_path / "out"))["contact_force_y"][1:].min() > 0
