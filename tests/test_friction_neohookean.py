"""Friction on a body that solve/newton.idp steps (issue 35; edp/lib/solve/newton_friction.idp, docs/friction.md):
contact/friction.idp's stick and slip sets inside Newton's semi-smooth iteration, on the Neo-Hookean body (and the
St Venant-Kirchhoff one, which shares its Newton), in 2D and 3D, and -initial static on them
(edp/lib/body/initial_static.idp's chord iteration).

Each run checks at every step the KKT conditions of (10) and those of friction (frictionFails): a step that fails
them stops the run with exit 4, so every run below that ends in 0 met them at every node and step. The Newton step
conserves the energy with Gonzalez's discrete gradient (docs/svk.md), so Prop. 2 with friction holds as for the
linear body: E^{n+1} - (f, u^{n+1}) + D^{n+1} <= E^n - (f, u^n) on a fixed foundation."""
import math
import os

import numpy as np
import pytest

from conftest import ROOT, error_lines, refused_into_copy, restart_reproduces, run_scenes
from history import read_run

QUIET = ["-progress", "0", "-snapshots", "none"]
STIFF = ["-lambda", "3000", "-mu", "3000"]
G, R = 0.1, 20.0
RUNS = {   # the skidding disk (the slide scene: -initial static, v0x = 0.5, F = 0.3) on each non-linear body
    "neohookean": ("slide", ["-material", "neohookean", "-T", "10"] + QUIET),
    "svk": ("slide", ["-material", "svk", "-T", "10"] + QUIET),
    "tresca": ("slide", ["-material", "neohookean", "-friction", "tresca", "-friction_bound", "0.05", "-T", "10"] + QUIET),
    "rolls": ("roll", ["-material", "neohookean", "-T", "10"] + STIFF + QUIET),
    "at_rest": ("roll", ["-material", "neohookean", "-angle", "0", "-u0y", "0", "-T", "4"] + STIFF + QUIET),
    "ball": ("ball", ["-material", "neohookean", "-initial", "static", "-angle", "10", "-friction", "coulomb",
                      "-friction_coefficient", "0.5", "-T", "2"] + STIFF + QUIET),
    # the stiff Hertz ball launched at v0x = 0.5 from rest on the flat: its first step's sets cycle without the
    # shortened updates of solve/newton_friction.idp's newtonFrictionCycle
    "cycle": ("ball", ["-material", "neohookean", "-mesh", os.path.join(ROOT, "meshes", "hertz_coarse.msh"), "-initial", "static", "-friction",
                       "coulomb", "-friction_coefficient", "0.3", "-v0x", "0.5", "-dt", "0.1", "-T", "1"] + STIFF + QUIET),
}


@pytest.fixture(scope="module")
def nh_runs(tmp_path_factory):
    dirs = run_scenes(tmp_path_factory.mktemp("nh_friction"), RUNS)
    return {name: read_run(d) for name, d in dirs.items()}


@pytest.mark.parametrize("name", ("neohookean", "svk", "tresca", "rolls", "ball", "cycle"))
def test_energy_and_friction_work_never_increase(nh_runs, name):
    """Prop. 2 with friction on the non-linear body: the modified energy plus the cumulative friction_work never
    increases, per step, to the Newton solve's round-off (1e-12 of its size; 3e-13 measured), and D >= 0."""
    h = nh_runs[name]
    total = h["modified_energy"] + h["friction_work"]
    gain = np.diff(total).max()
    assert gain <= 1e-12 * np.abs(total).max(), f"{name}: E + D rises by {gain:.3g} in one step"
    assert np.diff(h["friction_work"]).min() >= 0


@pytest.mark.parametrize("name", ("neohookean", "svk"))
def test_gross_slip_is_coulomb_s_law(nh_runs, name):
    """Where every pressed node slips, each node's tangential force is F times its normal force, so their sums are
    too: |contact_force_x| = F contact_force_y to 1e-12, and the skidding disk both slips and sticks in its run."""
    h = nh_runs[name]
    slipping = (h["slip_nodes"] > 0) & (h["stick_nodes"] == 0)
    assert slipping.sum() > 20 and h["stick_nodes"].max() > 0
    assert np.abs(-h["contact_force_x"][slipping] / h["contact_force_y"][slipping] - 0.3).max() < 1e-12


def test_the_skidding_disk_on_tresca_slips_at_its_bound(nh_runs):
    """Tresca's law: a slipping node's tangential force is g times its weight on Gamma_C; where every pressed node
    slips the total is g times the pressed nodes' weights: it never exceeds g times the whole of Gamma_C's."""
    h = nh_runs["tresca"]
    assert h["slip_nodes"].max() > 0 and h["friction_work"][-1] > 0
    assert np.abs(h["contact_force_x"]).max() <= 0.05 * math.pi * R * (1 + 1e-9)


def test_the_stiff_neo_hookean_disk_rolls_at_two_thirds_g_sin_theta(nh_runs):
    """A very large F sticks: the nearly rigid Neo-Hookean disk (lambda = mu = 3000) started static on the 10 degree
    incline with F = 0.5 (tan theta <= 3 F) rolls, its centre accelerating at 2/3 g sin(theta) and its spin at that
    over R. Released from the static state, the disk rocks on its elastic contact (a period of about 3), so the
    accelerations are the least-squares slopes of the speed and the spin over the run: within 1% and 2% (0.28% and
    1.42% measured; the linear body's speed is 4.8% short, docs/friction.md)."""
    h, theta = nh_runs["rolls"], math.radians(10)
    a = 2 / 3 * G * math.sin(theta)
    speed = -(h["v1_mean"] * math.cos(theta) + h["v2_mean"] * math.sin(theta))
    slope = np.polyfit(h["t"], speed, 1)[0]
    spin = np.polyfit(h["t"], h["angular_velocity"], 1)[0]
    assert abs(slope / a - 1) < 0.01, slope / a
    assert abs(spin * R / a - 1) < 0.02, spin * R / a
    assert h["slip_nodes"][1:].max() <= 1 and h["stick_nodes"][1:].min() >= 1


def test_the_neo_hookean_disk_started_static_on_the_flat_stays_at_rest(nh_runs):
    """-initial static on the Neo-Hookean body: the chord iteration's state, released at rest on the flat with
    friction, stays at rest: the contact force is the weight (125.5906) within 1e-6 at every step, and its speed
    stays below 1e-5 over 80 steps (4.6e-6 measured: the state holds its turn with a torque of 2e-5 of the weight
    times the radius of gyration, which the start line reports, so it is not exact to round-off as the linear
    body's is; a body set down unstressed instead oscillates with a speed of about 1e-2)."""
    h = nh_runs["at_rest"]
    assert np.abs(h["contact_force_y"][1:] / 125.5906 - 1).max() < 1e-6
    assert np.abs(np.column_stack([h["v1_mean"], h["v2_mean"]])).max() < 1e-5


def test_the_neo_hookean_ball_rolls_and_sticks(nh_runs):
    """3D: the stiff Neo-Hookean ball started static on the 10 degree plane with F = 0.5 sticks (its pressed node
    never slips) and turns about X2 as it rolls down the slope, in the sense of rolling (the spin times R has the
    sign of the speed along -X1)."""
    h = nh_runs["ball"]
    assert h["slip_nodes"].max() == 0 and h["stick_nodes"][1:].min() >= 1
    assert h["v1_mean"][-1] < 0 and h["angular_velocity_2"][-1] < 0


def test_a_neo_hookean_friction_run_restarts_to_the_bit(tmp_path):
    """The Newton step starts from the checkpoint's sets and multipliers: a Neo-Hookean friction run restarted at
    t = 2 gives the uninterrupted run's history.csv and checkpoint.txt byte for byte."""
    args = ["-material", "neohookean", "-checkpoint_every", "20"] + QUIET
    restart_reproduces("slide", tmp_path, args, 2, 4)


def test_newton_settles_where_its_sets_cycle(nh_runs):
    """Semi-smooth Newton on Coulomb's law need not converge from afar: at the stiff ball's first step (dt = 0.1) its
    sets went back and forth between two states (0 and 21 nodes sticking), neither the solution, and the run failed.
    With the updates shortened while the sets cycle, every step converges, the first to about 54 sticking and 34
    slipping nodes (the linear ball's: 56 and 32), and the ball skids (its contact point slides backwards)."""
    h = nh_runs["cycle"]
    assert len(h["t"]) == 11
    assert h["stick_nodes"][1] > 40 and h["slip_nodes"][1] > 20
    assert (h["v1_mean"][1:] - 19.7 * h["angular_velocity_2"][1:]).min() > 0


def test_ipopt_with_friction_on_a_non_linear_ball_names_newton(tmp_path, earlier_run):
    """-solver ipopt with friction on the 3D Neo-Hookean ball: the line names what the material's step is (Newton's),
    not the linear body's advice to use the active set, which the material refuses too; exit 3, the earlier run in OUT
    byte-identical."""
    p, changed = refused_into_copy(tmp_path, earlier_run, "ball", ["-material", "neohookean", "-friction", "coulomb",
                                                                   "-friction_coefficient", "0.3", "-solver", "ipopt",
                                                                   "-T", "1"])
    assert p.returncode == 3 and error_lines(p) == [
        "error: -solver ipopt does not apply to -material neohookean: its step is not the minimisation of a functional "
        "(the tangent of the mid-point force is not symmetric), so it is not the QP that ipopt solves; use -solver "
        "newton (the default for neohookean)"], p.stderr
    assert not changed
