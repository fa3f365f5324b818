"""Friction on Gamma_C (issue 35; edp/lib/contact/friction.idp, docs/friction.md): Tresca and Coulomb inside the
mid-point scheme, solved exactly by the stick and slip sets of the active-set solver.

Each run checks at every step, to round-off, the KKT conditions of (10) and those of friction (lm_T = 0 off the
pressed nodes, |lm_T| <= b on them, s = 0 where a node sticks, lm_T along s with |lm_T| = b where it slips): a step
that fails them stops the run with exit 4, so every run below that ends in 0 met them at every node and step.
The tests check what follows from them: Prop. 2 with friction, the momentum of (1), Coulomb's law in gross slip,
and that a coefficient of 0 is the frictionless run to the bit."""
import math
import os
import subprocess
import sys

import numpy as np
import pytest

from conftest import ROOT, error_lines, refused_into_copy, restart_reproduces, run_scene, run_scenes
from history import read_run

QUIET = ["-progress", "0", "-snapshots", "none"]
F = 0.3
# the disk launched touching the flat (its lowest point at X2 = 0) at v0x = 0.5, with no spin
SLIDE = ["-u0y", "0", "-T", "10"] + QUIET
RUNS = {
    "coulomb": ("oblique", SLIDE + ["-friction", "coulomb", "-friction_coefficient", str(F)]),
    "tresca": ("oblique", SLIDE + ["-friction", "tresca", "-friction_bound", "0.05"]),
    "coulomb_zero": ("oblique", SLIDE + ["-solver", "activeset", "-friction", "coulomb", "-friction_coefficient", "0"]),
    "frictionless": ("oblique", SLIDE + ["-solver", "activeset"]),
    "incline": ("incline", ["-T", "10", "-friction", "coulomb", "-friction_coefficient", str(F)] + QUIET),
    "test2": ("test2", ["-T", "30", "-friction", "coulomb", "-friction_coefficient", "1"] + QUIET),
}
FIXED = ("coulomb", "tresca", "incline")      # the fixed foundation, where Prop. 2 applies


@pytest.fixture(scope="module")
def friction_runs(tmp_path_factory):
    dirs = run_scenes(tmp_path_factory.mktemp("friction"), RUNS)
    return {name: read_run(d) for name, d in dirs.items()} | {"dirs": dirs}


@pytest.mark.parametrize("name", FIXED)
def test_energy_and_friction_work_never_increase(friction_runs, name):
    """Prop. 2 with friction: (4) tested with w = u^n on a fixed foundation, f constant, gives
    E^{n+1} - (f, u^{n+1}) + D^{n+1} <= E^n - (f, u^n), D^{n+1} = sum_j b_j |s_j| the step's friction work:
    the modified energy plus the cumulative friction_work never increases, per step, to round-off."""
    h = friction_runs[name]
    total = h["modified_energy"] + h["friction_work"]
    gain = np.diff(total).max()
    assert gain <= 1e-12 * abs(total[0]), f"{name}: E + D rises by {gain:.3g} in one step"
    assert h["friction_work"][-1] > 1e-3 * abs(total[0]), f"{name}: friction did no work ({h['friction_work'][-1]:.3g})"


@pytest.mark.parametrize("name", FIXED + ("test2",))
def test_friction_work_is_nonnegative_at_every_step(friction_runs, name):
    """D^{n+1} = sum_j b_j |s_j| >= 0: friction only dissipates, on a moving foundation too."""
    assert np.diff(friction_runs[name]["friction_work"]).min() >= 0


@pytest.mark.parametrize("name", ("coulomb", "tresca"))
def test_the_contact_force_changes_the_momentum_as_in_1(friction_runs, name):
    """(1) summed over the X1 translation (K has no force along a translation, f_1 = 0):
    M (v^{n+1} - v^n) / dt = -(C' lm_N + C_T' lm_T), so |body| (v1_mean^{n+1} - v1_mean^n) = dt contact_force_x.
    Every step with a contact force gives the same mass, the disk's (pi R^2 rho, less the polygon's deficit)."""
    h = friction_runs[name]
    dv, force, dt = np.diff(h["v1_mean"]), h["contact_force_x"][1:], np.diff(h["t"])
    pushed = np.abs(force) > 1e-3 * np.abs(force).max()
    mass = dt[pushed] * force[pushed] / dv[pushed]
    assert pushed.sum() > 20 and np.ptp(mass) < 1e-8 * mass.mean(), (mass.min(), mass.max())
    assert abs(mass.mean() / (math.pi * 20**2) - 1) < 5e-3


def test_gross_slip_force_is_F_times_the_normal_force(friction_runs):
    """Coulomb: where every pressed node slips, each has |lm_T| = F lm_N (a flat foundation: the rows of (10) are
    unit vectors), so the total tangential force is F times the normal one, to round-off; it opposes the
    motion (the disk slides towards +X1)."""
    h = friction_runs["coulomb"]
    slipping = (h["slip_nodes"] > 0) & (h["stick_nodes"] == 0)
    assert slipping.sum() > 20
    ratio = -h["contact_force_x"][slipping] / h["contact_force_y"][slipping]
    assert np.abs(ratio - F).max() < 1e-9, ratio


def test_friction_turns_and_slows_the_sliding_disk(friction_runs):
    """Without friction the disk keeps v0x and does not turn; with Coulomb's, it slows and spins clockwise
    (omega < 0: the force -F N at its lowest point, towards -X1). (How far from rolling, v1 = -omega R, depends
    on the sag and the waves of this soft disk set down unstressed: docs/friction.md.)"""
    h, free = friction_runs["coulomb"], friction_runs["frictionless"]
    assert np.abs(free["v1_mean"] - 0.5).max() < 1e-12
    assert h["v1_mean"][-1] < 0.5 - 0.05 and h["angular_velocity"][-1] < -0.001


def test_zero_coefficient_is_the_frictionless_run_bit_for_bit(friction_runs):
    """-friction coulomb -friction_coefficient 0 is today's run: history.csv byte for byte (the friction code is
    not entered, and adds no column)."""
    dirs = friction_runs["dirs"]
    assert open(f"{dirs['coulomb_zero']}/history.csv", "rb").read() == open(f"{dirs['frictionless']}/history.csv", "rb").read()


def test_a_moving_foundation_with_friction_keeps_10(friction_runs):
    """Test 2 with F = 1: the foundation moves down on [9, 18] and the disk lands on it; (10) holds to round-off
    (the run checks it at each step) and the body does not rise through its own contact."""
    h = friction_runs["test2"]
    assert h["max_penetration"].max() <= 1e-9 and h["slip_nodes"].max() > 0 and h["stick_nodes"].max() > 0


REFUSALS = [
    (["-friction", "tresca"],
     "error: -friction tresca needs -friction_bound g > 0, the largest tangential stress on a pressed node (a bound "
     "of 0 is no friction: -friction none)"),
    (["-friction", "coulomb", "-friction_coefficient", "0.2", "-solver", "newton"],
     "error: -friction coulomb with -solver newton does not apply: use -solver activeset (the default with friction), "
     "which solves the step's stick and slip sets exactly, or ipopt"),
    (["-friction", "coulomb", "-friction_coefficient", "0.2", "-contact", "penalty"],
     "error: -friction coulomb with -contact penalty is not supported yet: it is implemented with -contact "
     "constraint, (10) imposed exactly"),
    (["-friction", "tresca", "-friction_bound", "1", "-scheme", "newmark"],
     "error: -friction tresca with -scheme newmark is not supported yet: it is implemented in the mid-point scheme "
     "(1)-(2)"),
    (["-friction", "coulomb", "-friction_coefficient", "-1"], "error: -friction_coefficient must be >= 0, got -1"),
    (["-friction", "tresca", "-friction_bound", "inf"], "error: -friction_bound must be a number, got 'inf'"),
    (["-friction", "coulomb", "-friction_coefficient", "nan"], "error: -friction_coefficient must be a number, got 'nan'"),
    (["-friction", "coulom"], "error: -friction must be none, tresca or coulomb; got 'coulom'"),
]


@pytest.mark.parametrize("args,line", REFUSALS, ids=[" ".join(a) for a, _ in REFUSALS])
def test_friction_refusals_leave_the_earlier_run_alone(tmp_path, earlier_run, args, line):
    """Each refusal is one line and exit 3, and the earlier run in OUT stays byte-identical."""
    p, changed = refused_into_copy(tmp_path, earlier_run, "test1", args + ["-T", "1"])
    assert p.returncode == 3 and error_lines(p) == [line], p.stderr
    assert not changed


def test_a_friction_run_restarts_to_the_bit(tmp_path):
    """A friction run's checkpoint keeps its stick and slip sets, lm_T and the friction work: restarted at t = 5, it
    gives the uninterrupted run's history.csv and checkpoint.txt byte for byte. A checkpoint whose sign of a slip is
    not -1, 0 or 1 is refused in one line (io/check_checkpoint.awk), and the run stays."""
    args = ["-u0y", "0", "-friction", "coulomb", "-friction_coefficient", "0.3", "-checkpoint_every", "50"] + QUIET
    first = restart_reproduces("oblique", tmp_path, args, 5, 10)
    # the sign array is the checkpoint's 6th (u, v, the active set, lm_N, the stick set, the signs, lm_T, the work)
    header, *rest = (first / "checkpoint.txt").read_text().splitlines()
    tokens = " ".join(rest).split()
    at = 0
    for _ in range(5):
        at += 1 + int(tokens[at])
    tokens[at + 1] = "2"
    edited = tmp_path / "edited"
    edited.mkdir()
    for f in first.iterdir():
        if f.is_file():
            (edited / f.name).write_bytes(f.read_bytes())
    (edited / "checkpoint.txt").write_text(header + "\n" + "\n".join(tokens[:-2]) + "\n" + " ".join(tokens[-2:]) + "\n")
    before = {f.name: f.read_bytes() for f in edited.iterdir() if f.is_file()}
    p = run_scene("oblique", tmp_path / "again", ["-restart", str(edited), "-T", "12"] + QUIET, check=False)
    assert p.returncode == 3 and error_lines(p) == [
        f"error: -restart {edited}: checkpoint.txt is corrupt: a slip's sign is '2'"], p.stderr
    assert {f.name: f.read_bytes() for f in edited.iterdir() if f.is_file()} == before


def test_a_coefficient_without_friction_warns(tmp_path):
    """-friction_coefficient with -friction none, or -belt_speed without friction, has no effect: the documented
    warning line, and the run goes on."""
    p = run_scene("test1", tmp_path / "run", ["-T", "1", "-friction_coefficient", "0.3"] + QUIET)
    assert "warning: -friction_coefficient has no effect: it applies to -friction coulomb" in p.stderr.splitlines()
    # a belt without friction (Coulomb with F = 0 is frictionless) moves nothing
    p = run_scene("test1", tmp_path / "belt", ["-T", "1", "-belt_speed", "1", "-friction", "coulomb"] + QUIET)
    assert ("warning: -belt_speed has no effect: the foundation's motion along itself acts on the body through "
            "friction only") in p.stderr.splitlines()


# -initial static (body/initial_static.idp): at rest in static contact under the load's part normal to the flat
STATIC = ["-initial", "static", "-solver", "activeset"] + QUIET


@pytest.mark.parametrize("scene,up,args", [("test1", "2", ["-u0y", "0", "-T", "10"]), ("ball", "3", ["-T", "3"])],
                         ids=["disk", "ball"])
def test_a_body_started_static_on_the_flat_stays_at_rest(tmp_path, scene, up, args):
    """-initial static solves K w = F - C' lm under (10) (frictionless, f normal to the flat foundation). The
    mid-point step (4) of a body at rest in that state is K u = F - C' lm again, so it stays: its velocity stays at
    round-off (1e-12), and the contact force is the body's weight from the first step (the disk's 1255.906 x 0.1),
    where a body set down unstressed would oscillate between about 0 and twice its weight."""
    out = tmp_path / scene
    p = run_scene(scene, out, STATIC + args)
    assert any(line.startswith("initial state: at rest in static contact (") for line in p.stdout.splitlines()), p.stdout
    h = read_run(str(out))
    v = np.column_stack([h[k] for k in h if k.startswith("v") and k.endswith(("_mean", "_low"))])
    assert np.abs(v).max() < 1e-12
    force = h[f"contact_force_{'yz'[int(up) - 2]}"][1:]
    assert np.ptp(force) < 1e-10 * force.mean()
    if scene == "test1":
        assert abs(force.mean() / 125.5906 - 1) < 1e-5


def test_the_stiff_disk_slides_down_the_incline_at_g_sin_minus_F_cos(tmp_path):
    """Coulomb's closed form for a body that slides (tan theta > 3 F): its centre accelerates down the slope at
    g (sin theta - F cos theta). The nearly rigid disk (lambda = mu = 3000) started static on the 10 degree incline
    with F = 0.02 slides in gross slip; its speed along the slope at t = 10 is the closed form's within 1% (0.23%)."""
    out = tmp_path / "incline"
    run_scene("incline", out, STATIC + ["-lambda", "3000", "-mu", "3000", "-friction", "coulomb",
                                        "-friction_coefficient", "0.02", "-T", "10"])
    h = read_run(str(out))
    theta, g = math.radians(10), 0.1
    speed = -(h["v1_mean"][-1] * math.cos(theta) + h["v2_mean"][-1] * math.sin(theta))
    assert abs(speed / (g * (math.sin(theta) - 0.02 * math.cos(theta)) * 10) - 1) < 0.01, speed
    assert h["stick_nodes"][-1] == 0 and h["slip_nodes"][-1] > 0


STATIC_REFUSALS = [
    (["-initial", "static", "-foundation", "cosine"], "error: -initial static needs -foundation flat (a plane of any -angle): on the cosine "
     "foundation its static state is not defined here; use -initial given"),
    (["-initial", "static", "-foundation_velocity", "-0.1"], "error: -initial static needs a fixed foundation: -foundation_velocity is -0.1; use "
     "-initial given"),
    (["-initial", "rest"], "error: -initial must be given or static; got 'rest'"),
]


@pytest.mark.parametrize("args,line", STATIC_REFUSALS, ids=[" ".join(a[2:] or a) for a, _ in STATIC_REFUSALS])
def test_initial_static_refusals_leave_the_earlier_run_alone(tmp_path, earlier_run, args, line):
    """-initial static where it is not defined or not implemented: one line, exit 3, the earlier run unchanged."""
    p, changed = refused_into_copy(tmp_path, earlier_run, "test1", args + ["-T", "1"])
    assert p.returncode == 3 and error_lines(p) == [line], p.stderr
    assert not changed


@pytest.fixture(scope="module")
def friction_scenes(tmp_path_factory):
    runs = {"slide": ("slide", QUIET), "slide_left": ("slide", ["-v0x", "-0.5"] + QUIET), "belt": ("belt", QUIET),
            "roll": ("roll", QUIET)}
    return {name: read_run(d) for name, d in run_scenes(tmp_path_factory.mktemp("scenes"), runs).items()}


def test_the_belt_is_the_slide_seen_from_the_belt(friction_scenes):
    """(1)-(2) with (10) on a flat foundation are Galilean invariant (a translation at constant velocity costs no
    strain, and the rows of (10) do not depend on X1 when psi' = 0): the disk set down on the belt moving at V = 0.5
    is the disk launched at -0.5 on the fixed flat, plus V t. Its v1_mean, u1_mean, spin, friction work and
    slip count agree to round-off, so the slip is taken relative to the belt, and m_j = V dt."""
    belt, slide = friction_scenes["belt"], friction_scenes["slide_left"]
    assert np.abs(belt["v1_mean"] - (slide["v1_mean"] + 0.5)).max() < 1e-12
    assert np.abs(belt["u1_mean"] - (slide["u1_mean"] + 0.5 * belt["t"])).max() < 1e-11
    assert np.abs(belt["angular_velocity"] - slide["angular_velocity"]).max() < 1e-13
    assert np.abs(belt["friction_work"] - slide["friction_work"]).max() < 1e-10 * slide["friction_work"][-1]
    assert (belt["slip_nodes"] == slide["slip_nodes"]).all() and (belt["stick_nodes"] == slide["stick_nodes"]).all()


def test_the_belt_does_work_and_the_balance_holds(friction_scenes):
    """With the foundation moving along itself by m_j over a step, testing (4) with u^n gives
    E^{n+1} - (f, u^{n+1}) + D^{n+1} <= E^n - (f, u^n) + W^{n+1}, W^{n+1} = -lm_T . m the work of the belt on the body
    (history.csv's foundation_work, cumulative): that balance holds at every step to 1e-12, and the belt's work over
    the run is positive (it speeds the disk up and spins it; on a step where the disk overtakes the belt, it brakes)."""
    h = friction_scenes["belt"]
    total = h["modified_energy"] + h["friction_work"] - h["foundation_work"]
    assert np.diff(total).max() <= 1e-12 * np.abs(total).max()
    assert h["foundation_work"][-1] > 100
    assert (friction_scenes["slide"]["foundation_work"] == 0).all()


def test_the_roll_scene_rolls(friction_scenes):
    """roll (the 10 degree incline, F = 0.5 > tan 10 / 3): the disk started static rolls down (omega > 0, towards
    -X1, counter-clockwise) with its contact patch sticking, and friction does almost no work (0.1% of the energy
    the disk gains)."""
    h = friction_scenes["roll"]
    assert h["v1_mean"][-1] < -0.1 and h["angular_velocity"][-1] > 0.005
    assert h["stick_nodes"][-1] > 5 and h["slip_nodes"][-1] == 0
    assert h["friction_work"][-1] < 1e-3 * (h["energy"][-1] - h["energy"][0])


def test_the_snapshots_show_the_traction_and_the_stick_slip_state(tmp_path):
    """The .vtu of a friction run carries, on Gamma_C, the tangential traction on the body (-lm_T / w_j, along t)
    and the state (0 free, 1 sticking, 2 slipping). Skidding at t = 2 every pressed node slips, its traction
    -F times its pressure (alpha of eq. (6)) against the motion; rolling at t = 10 the nodes that stick carry at most
    F times it. A frictionless .vtu has neither field."""
    meshio = pytest.importorskip("meshio")
    out = tmp_path / "slide"
    run_scene("slide", out, ["-snapshots", "2,10", "-progress", "0"])
    skid, roll = (meshio.read(str(out / f"vonmises_t{t}.vtu")).point_data for t in (2, 10))
    pressed = skid["contact_pressure"] > 0
    assert pressed.sum() > 5 and (skid["contact_state"][pressed] == 2).all()
    assert np.abs(skid["tangential_traction"][pressed] / skid["contact_pressure"][pressed] + F).max() < 1e-12
    assert (skid["tangential_traction"][~pressed] == 0).all()
    sticking = roll["contact_state"] == 1
    assert sticking.sum() > 5
    assert (np.abs(roll["tangential_traction"][sticking]) <= F * roll["contact_pressure"][sticking] * (1 + 1e-12)).all()
    run_scene("test1", tmp_path / "plain", ["-T", "1", "-snapshots", "1", "-progress", "0"])
    assert "contact_state" not in meshio.read(str(tmp_path / "plain" / "vonmises_t1.vtu")).point_data


@pytest.mark.parametrize("scene", ["slide", "roll"])
def test_ipopt_agrees_with_the_active_set(tmp_path, scene):
    """-solver ipopt, the paper's solver, with friction: the step with the slip bounds fixed is a smooth convex
    program (|s| replaced by a slack z >= |s|), and the bounds are a fixed point (contact/friction_ipopt.idp, about 5
    IPOPT solves a step here). It agrees with the exact active set to IPOPT's tolerance (-tol 1e-8): the skidding
    slide (every pressed node slipping) and the rolling disk (its patch sticking), over 30 steps."""
    runs = {}
    for solver in ("ipopt", "activeset"):
        out = tmp_path / solver
        run_scene(scene, out, ["-solver", solver, "-T", "1.5"] + QUIET)
        runs[solver] = read_run(str(out))
    a, b = runs["ipopt"], runs["activeset"]
    for column, size in (("v1_mean", 0.5), ("angular_velocity", 0.01), ("u1_mean", 1), ("u2_mean", 1)):
        assert np.abs(a[column] - b[column]).max() < 1e-7 * size, column
    for column in ("contact_force_x", "contact_force_y", "friction_work"):
        assert np.abs(a[column] - b[column]).max() < 1e-6 * max(np.abs(b[column]).max(), 1.0), column   # (D = 0 rolling)
    assert (a["slip_nodes"] == b["slip_nodes"]).all() and (a["stick_nodes"] == b["stick_nodes"]).all()
    assert 1 <= a["newton_iterations"][1:].min() and a["newton_iterations"].max() <= 20


# 3D: two tangent families, the slip a vector in the tangent plane (contact/friction_rows.idp, contact/friction.idp)
HERTZ_COARSE = os.path.join(ROOT, "meshes", "hertz_coarse.msh")


@pytest.fixture(scope="module")
def ball_runs(tmp_path_factory):
    base = tmp_path_factory.mktemp("ball")
    runs = {"skid": ("ball", ["-initial", "static", "-v0x", "0.5", "-friction", "coulomb", "-friction_coefficient", "0.3",
                              "-T", "2"] + QUIET),
            "oblique": ("oblique_ball", ["-mesh", HERTZ_COARSE, "-dt", "0.2"] + QUIET)}
    return {name: read_run(d) for name, d in run_scenes(base, runs).items()} | {"dirs": {k: str(base / k) for k in runs}}


def test_3d_skidding_ball_keeps_prop2_and_the_momentum_of_1(ball_runs):
    """The ball started static on the flat and launched at v0x = 0.5 with Coulomb's F = 0.3: E - (f, u) + D never
    rises (Prop. 2 with friction, to 1e-12 of it); the contact force changes the momentum as (1) says along X1 and
    X2, every step giving the same mass; and it starts to roll: omega about X2 grows (v = omega x r at the contact)."""
    h = ball_runs["skid"]
    total = h["modified_energy"] + h["friction_work"]
    assert np.diff(total).max() <= 1e-12 * np.abs(total).max() and h["friction_work"][-1] > 1
    dt = np.diff(h["t"])
    for axis in ("x", "y"):
        force, dv = h[f"contact_force_{axis}"][1:], np.diff(h[f"v{'12'['xy'.index(axis)]}_mean"])
        pushed = np.abs(force) > 1e-3 * np.abs(h["contact_force_x"]).max()
        mass = dt[pushed] * force[pushed] / dv[pushed]
        assert pushed.sum() > 10 and np.ptp(mass) < 1e-7 * mass.mean(), (axis, mass.min(), mass.max())
    assert (np.diff(h["angular_velocity_2"][1:]) > 0).all() and h["angular_velocity_2"][-1] > 0.004


def test_3d_oblique_impact_in_gross_slip(ball_runs):
    """The oblique scene's 3D twin (oblique_ball, on the coarse Hertz ball, dt = 0.2): thrown at the flat with
    v_t / v_n = 4 > (7/2) F (1 + e), it slides throughout the impact, so the tangential impulse is F times the normal
    one (within 1%: 0.01% here) and it leaves spinning at omega = 5 F (1 + e) v_n / (2 R) (within 1%: 0.44%), e its
    normal restitution, measured."""
    h = ball_runs["oblique"]
    assert h["stick_nodes"].max() == 0 and h["slip_nodes"].max() > 20
    normal = h["contact_force_z"].sum()
    tangential = np.hypot(h["contact_force_x"].sum(), h["contact_force_y"].sum())
    assert abs(tangential / normal / 0.3 - 1) < 0.01, tangential / normal
    e = h["v3_mean"][-1] / 0.0125
    assert 0.95 < e < 1.05
    omega = 5 * 0.3 * (1 + e) * 0.0125 / (2 * 20)
    assert abs(h["angular_velocity_2"][-1] / omega - 1) < 0.01, (h["angular_velocity_2"][-1], omega)


def test_3d_ipopt_agrees_with_the_active_set(tmp_path):
    """-solver ipopt on a 3D body solves the step's dual in (lm_N, lm_T) on the candidate contact nodes, with the slip
    bounds |lm_T,j| <= b_j as smooth ball constraints (the primal's cone |s| <= z has no constraint qualification at
    its apex, where a sticking node sits: contact/friction_ipopt.idp). It agrees with the exact active set to IPOPT's
    tolerance (-tol 1e-8) on the ball over 20 steps: skidding (Coulomb, every pressed node slipping), Tresca, and rolling
    down the tilted-g slope (its patch sticking; a node at the patch's edge, |lm_T| within -tol of b, may count as
    either); and thrown onto Test 2's moving foundation (ball_moving to T = 13, 79 steps in contact, where the
    bounds' fixed point once went back and forth between two solves). The forces are compared with the total one:
    the y force is round-off's on these runs, symmetric in X2."""
    tilt = ["-fx", repr(0.1 * math.sin(math.radians(10))), "-fz", repr(-0.1 * math.cos(math.radians(10)))]
    static = ["-initial", "static"]
    cases = {"skid": ("ball", static + ["-v0x", "0.5", "-friction", "coulomb", "-friction_coefficient", "0.3", "-T", "1"]),
             "tresca": ("ball", static + ["-v0x", "0.5", "-friction", "tresca", "-friction_bound", "0.5", "-T", "1"]),
             "roll": ("ball", static + tilt + ["-friction", "coulomb", "-friction_coefficient", "0.5", "-T", "1"]),
             "moving": ("ball_moving", ["-t1", "22", "-v0x", "0.2", "-friction", "coulomb", "-friction_coefficient", "0.3",
                                        "-T", "13"])}
    runs = {f"{case} {solver}": (scene, ["-solver", solver] + args + QUIET)
            for case, (scene, args) in cases.items() for solver in ("ipopt", "activeset")}
    h = {name: read_run(d) for name, d in run_scenes(tmp_path, runs).items()}
    for case in cases:
        a, b = h[case + " ipopt"], h[case + " activeset"]
        for column, size in (("v1_mean", 0.5), ("angular_velocity_2", 0.01), ("u1_mean", 1), ("u3_mean", 1)):
            assert np.abs(a[column] - b[column]).max() < 1e-7 * size, (case, column)
        force = np.abs(b["contact_force_z"]).max()      # (the y force is round-off's on these symmetric runs)
        for column in ("contact_force_x", "contact_force_y", "contact_force_z"):
            assert np.abs(a[column] - b[column]).max() < 1e-6 * force, (case, column)
        assert np.abs(a["friction_work"] - b["friction_work"]).max() < 1e-6 * max(b["friction_work"].max(), 1.0), case
        assert (a["active_nodes"] == b["active_nodes"]).all(), case
        edge = np.abs(a["slip_nodes"] - b["slip_nodes"])
        assert edge.max() <= (1 if case == "roll" else 0) and (edge > 0).sum() <= 2, case
        assert a["newton_iterations"].max() <= 30, case       # (IPOPT solves a step: the bounds' fixed point)


def test_a_3d_ipopt_friction_run_restarts_to_the_bit(tmp_path):
    """The dual's candidate nodes start from the last step's pressed set and its multipliers, both in the checkpoint:
    the skidding ball on IPOPT restarted at t = 0.5 gives the uninterrupted run's files byte for byte."""
    args = ["-initial", "static", "-v0x", "0.5", "-friction", "coulomb", "-friction_coefficient", "0.3", "-solver",
            "ipopt", "-checkpoint_every", "10"] + QUIET
    restart_reproduces("ball", tmp_path, args, 0.5, 1)


def test_a_3d_friction_run_restarts_to_the_bit(tmp_path):
    """In 3D the next step starts from the slip's directions too (its semi-smooth Newton rows are linearised about
    them), so the checkpoint keeps them: the skidding ball restarted at t = 1 gives the uninterrupted run's
    history.csv and checkpoint.txt byte for byte."""
    args = ["-initial", "static", "-v0x", "0.5", "-friction", "coulomb", "-friction_coefficient", "0.3",
            "-checkpoint_every", "20"] + QUIET
    restart_reproduces("ball", tmp_path, args, 1, 2)


def test_the_oblique_impact_model_slides_throughout_above_4chi_minus_1_and_never_gains_energy():
    """postprocess/oblique_theory.py, Maw, Barber and Fawcett's model of the oblique impact (Hertz, Coulomb point by
    point) solved by the method of dimensionality reduction: above their threshold Psi1 = 4 chi - 1 (e = 1) the ball
    slides throughout, so it leaves as the rigid ball in gross slip does (Psi2 = Psi1 - 4 chi, the spin omega_gs),
    to 1e-3; below it part of the contact sticks, and the spin is less. At every incidence the tangential kinetic
    energy, 1/2 m v_t^2 + 1/2 I omega^2, does not grow (the springs are unloaded at separation; friction dissipates)."""
    sys.path.insert(0, os.path.join(ROOT, "postprocess"))
    import oblique_theory
    nu, k = 0.25, 0.397
    c, chi = 2 * (1 - nu) / (2 - nu), (1 - nu) / (2 - nu) * (1 + 1 / k)
    psi1 = np.array([0.25, 0.5, 1, 2, 3, 4, 4 * chi - 1.5, 4 * chi - 1 + 0.2, 7, 10])
    psi2, spin = oblique_theory.rebound(psi1, nu, k)
    above = psi1 > 4 * chi - 1
    assert np.abs(psi2 - (psi1 - 4 * chi))[above].max() < 1e-3 and np.abs(spin - 1)[above].max() < 1e-3
    assert spin[~above].max() < 0.99
    omega = 2 * spin / k                                   # (F = V_n1 = h = m = 1, e = 1)
    vt2 = psi2 / c + omega
    assert (0.5 * vt2**2 + 0.5 * k * omega**2 <= 0.5 * (psi1 / c) ** 2 * (1 + 1e-9)).all()


def test_make_friction_writes_its_table_and_figure(tmp_path):
    """make friction's study (postprocess/friction.py): every case runs on its three bodies, and summary.md,
    friction.csv and the figure are written. The issue's aim holds: on the stiff Neo-Hookean disk and ball started
    static every closed form is met within 2% (1.51% at most, measured; the ball's against the rigid body of its
    mesh), and the gross-slip impulse ratio of the 3D oblique impact within 1% of F; below gross slip the oblique ball
    follows Maw, Barber and Fawcett's model. A bad option is one line, exit 2, nothing written."""
    out = tmp_path / "friction"
    p = subprocess.run(["/usr/bin/python3", os.path.join(ROOT, "postprocess", "friction.py"), "--out", str(out)],
                       capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    rows = {tuple(line.split(",")[:3]): float(line.split(",")[5]) for line in (out / "friction.csv").read_text().splitlines()[1:]}
    assert abs(rows[("oblique ball", "linear", "tangential impulse / normal impulse")]) < 0.01
    stiff = {key: value for key, value in rows.items() if key[1] == "stiff Neo-Hookean"}
    assert len(stiff) == 20 and max(abs(v) for v in stiff.values()) < 0.02, stiff
    assert len(rows) == 42 and (out / "summary.md").exists() and (out / "friction.png").stat().st_size > 10000
    # below gross slip (oblique.csv): the linear Hertz ball against Maw, Barber and Fawcett's model, whose shape it
    # follows: the contact point turns back, Psi2 lowest at Psi1 = 3 to 4, the gross-slip line above 4 chi - 1 = 5.03.
    # Measured: Psi2 within 0.35 of the model, the spin within 0.055 of its; in gross slip Psi2 0.12 from the rigid
    # line and the spin 2.7% short (the levers of the contact forces: docs/friction.md)
    sweep = np.genfromtxt(out / "oblique.csv", delimiter=",", names=True)
    assert len(sweep) == 8 and (out / "friction_oblique.png").stat().st_size > 10000
    assert sweep["psi1"][np.argmin(sweep["psi2"])] in (3, 4) and sweep["psi2"].min() < -1.2
    assert np.abs(sweep["psi2"] - sweep["psi2_theory"]).max() < 0.4
    assert np.abs(sweep["spin_ratio"] - sweep["spin_ratio_theory"]).max() < 0.06
    slides = sweep["psi1"] >= 6
    assert np.abs(sweep["psi2"] - sweep["psi2_gross_slip"])[slides].max() < 0.15
    assert np.abs(sweep["spin_ratio"] - 1)[slides].max() < 0.03
    bad = subprocess.run(["/usr/bin/python3", os.path.join(ROOT, "postprocess", "friction.py"), "--jobs", "0", "--out",
                          str(tmp_path / "bad")], capture_output=True, text=True)
    assert bad.returncode == 2 and len(bad.stderr.splitlines()) == 1 and not (tmp_path / "bad").exists()


def test_friction_on_p2_elements(tmp_path):
    """P2 (its contact nodes are Gamma_C's vertices and edge midpoints, the rows of (10) at each): the skidding slide
    keeps Prop. 2 with friction to 1e-12, and where every pressed node slips the tangential force is F times the normal
    one to 1e-12, as on P1; its speed after 80 steps is P1's within 1e-3."""
    out = tmp_path / "p2"
    run_scene("slide", out, ["-order", "2", "-T", "4"] + QUIET)
    h = read_run(str(out))
    total = h["modified_energy"] + h["friction_work"]
    assert np.diff(total).max() <= 1e-12 * np.abs(total).max()
    slipping = (h["slip_nodes"] > 0) & (h["stick_nodes"] == 0)
    assert slipping.sum() > 20 and np.abs(-h["contact_force_x"][slipping] / h["contact_force_y"][slipping] - F).max() < 1e-12
    p1 = tmp_path / "p1"
    run_scene("slide", p1, ["-T", "4"] + QUIET)
    assert abs(h["v1_mean"][-1] - read_run(str(p1))["v1_mean"][-1]) < 1e-3


def test_initial_static_settles_on_a_very_stiff_incline(tmp_path):
    """The disk at lambda = mu = 30000 on the 10 degree incline presses a single node at first, about which the
    proximal iterates turn it by the same small step every iterate (it did not settle in 1000); with eps a tenth as
    large whenever they drift so, it settles in 21. Released without friction it slides, its normal force the static
    one, m g cos(theta) (the rows' multipliers sum to m g cos^2(theta)), to 1e-4 at every step (3e-5 here: the
    tangential load, applied at t = 0, sets off small elastic waves)."""
    out = tmp_path / "stiff"
    p = run_scene("incline", out, ["-initial", "static", "-lambda", "30000", "-mu", "30000", "-T", "1"] + QUIET)
    line = [s for s in p.stdout.splitlines() if s.startswith("initial state:")][0]
    assert int(line.split("(")[1].split(" ")[0]) < 100, line
    force = read_run(str(out))["contact_force_y"][1:]
    assert np.abs(force / (1255.906 * 0.1 * math.cos(math.radians(10))**2) - 1).max() < 1e-4
