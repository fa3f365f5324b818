"""The Neo-Hookean material (issue 18; edp/lib/material/neohookean.idp), checked on its own: the
Gonzalez discrete gradient and its consistent tangent at random states, and -material neohookean
in the driver: the paper's Test 1 and Test 2 to T = 120 (past SVK's collapse), a spinning free
flight and its order in dt, impacts without load, the small-strain limit, P2, golden files, a
restart."""
import os

import numpy as np
import pytest

from conftest import NH_SCENES, NH_SPIN_DTS, ROOT, run_scene
from golden import compare
from history import contact_intervals, read_summary, rebound_peaks
from test_svk import NEWTON_TOL, assert_small_strain_limit, run_unit

NH_TEST2 = ("18", "22", "26")


@pytest.mark.parametrize("seed,order,scale", [(1, 1, None), (2, 1, None), (3, 1, 2), (1, 2, None)],
                         ids=["p1-seed1", "p1-seed2", "p1-large-strain", "p2-seed1"])
def test_discrete_gradient_identity_tangent_and_linear_limit(seed, order, scale):
    """At a random state (a 1 rad rotation plus smooth fields; with scale 2, strains with det F down to
    0.73): the discrete-gradient identity N(x).(x - u^n) = W(x) - W(u^n) to round-off (Gonzalez 2000:
    the mid-point scheme then conserves the energy, as Section 3's does for SVK; measured 2e-15 to
    1.3e-14); the consistent tangent N'(x) against a central difference of N (measured 1.4e-9 to
    1.8e-8: the difference's own error); and N'(0) = K / 2, the linear form of (1) with the same
    lambda, mu (measured 4e-15 to 1.2e-14); and, for a vanishing step (u^n = x), N(x) is the gradient
    of W at x against its central difference (measured 6.5e-11 to 4.0e-9): S(C) = 2 dW/dC at large
    strains too, not only in the linear limit (beta absorbs a mismatch in the identity, so that alone
    would not show one)."""
    v = run_unit(seed, order, material="neohookean", scale=scale)
    assert v["gradient"] < 1e-6, v
    assert v["identity"] < 1e-12, v
    assert v["tangent"] < 1e-6, v
    assert v["linear"] < 1e-12, v
    # a mirrored state, det F = -1 but det C = 1 (found by review: the energy tested det C): W = infinity
    # (1e300), and the force refuses it (status 1)
    assert v["inverted"] == 1e300 and v["inverted_force"] == 1, v


def test_neohookean_survives_the_papers_test1(histories, run_status):
    """-material neohookean with the paper's lambda = mu = 30 runs Test 1 to the paper's T = 120 (four
    impacts), where the St Venant-Kirchhoff body inverts a triangle at t = 16.8 (svk.md): W -> infinity
    as J -> 0, so a scheme that does not create energy keeps J > 0. With gravity on the fixed foundation
    the modified energy never rises in a step (Prop. 2's identity with the discrete gradient; measured
    2.8e-14 relative over T = 120), and (10) holds to round-off (measured 3e-14)."""
    h = histories["neohookean_test1"]
    assert run_status["neohookean_test1"][0] == 0 and h["t"][-1] == 120
    m = h["modified_energy"]
    assert np.diff(m).max() < 1e-12 * abs(m[0]) and m[-1] < m[0]
    assert h["max_penetration"].max() < 1e-9 and h["contact_pressure_low"].min() >= 0
    assert np.isfinite(np.column_stack(list(h.values()))).all()
    intervals = contact_intervals(h["t"], h["active_nodes"] > 0)
    start, end = intervals[0]
    assert abs(start - 8.95) < 0.06 and abs(end - 23.8) < 0.11, (start, end)      # (linear: [8.95, 23.95])
    assert len(intervals) == 4, intervals                    # measured [8.95, 23.8] [40.5, 54.7] [70.75, 84.8] [100.95, 116.05]
    # the history's min_J (smallest det F): 1 in free fall, well above 0 through every impact
    assert abs(h["min_J"][0] - 1) < 1e-12 and 0.6 < h["min_J"].min() < 0.8, h["min_J"].min()     # measured 0.682


@pytest.mark.parametrize("name", ["neohookean_test1"] + [f"neohookean_test2_t1_{t1}" for t1 in NH_TEST2]
                         + ["p2_coarse_neohookean"])
def test_neohookean_free_fall_is_exact_before_impact(histories, name):
    """A rigid body under a constant load: the mid-point scheme integrates it exactly, u2 = 4 - 0.05 t^2
    (as for the linear body, (1)-(2)); the Neo-Hookean force vanishes on rigid translations (C = I)."""
    h = histories[name]
    before = h["t"] < contact_intervals(h["t"], h["active_nodes"] > 0)[0][0]
    err = np.abs(h["u2_low"][before] - (4 - 0.05 * h["t"][before] ** 2)).max()
    assert err < 1e-10, f"{name}: free fall differs from 4 - 0.05 t^2 by {err:.3g}"      # measured 1.0e-13


@pytest.mark.parametrize("t1", NH_TEST2)
def test_neohookean_test2_to_the_papers_horizon(histories, run_status, t1):
    """The paper's Test 2 (the foundation lowered by 2 on [9, t1]) with the Neo-Hookean body, t1 = 18 to the paper's
    T = 120, 22 and 26 to T = 45, past their first rebound:
    it completes with J > 0 (measured min J 0.69 to 0.71); the foundation only descends, so u^n is in
    K^{n+1} and the modified energy never rises in a step (Prop. 2; measured <= 4.6e-14 relative);
    (10) holds to round-off; and, as for the linear body (Section 4.2), the foundation absorbs energy
    on [t0, t1] and the first rebound is lower than on the fixed foundation."""
    name = f"neohookean_test2_t1_{t1}"
    h, h1 = histories[name], histories["neohookean_test1"]
    assert run_status[name][0] == 0 and h["t"][-1] == (120 if t1 == "18" else 45)
    m = h["modified_energy"]
    assert np.diff(m).max() < 1e-12 * abs(m[0]), f"{name}: modified energy rises by {np.diff(m).max():.3g} in a step"
    assert h["max_penetration"].max() < 1e-9 and h["contact_pressure_low"].min() >= 0
    assert np.isfinite(np.column_stack(list(h.values()))).all()
    assert 0.6 < h["min_J"].min() < 0.8, h["min_J"].min()
    assert np.interp(float(t1), h["t"], m) < np.interp(9, h["t"], m) - 100
    peak = rebound_peaks(h["t"], h["u2_low"], contact_intervals(h["t"], h["active_nodes"] > 0))[0][1]
    peak1 = rebound_peaks(h1["t"], h1["u2_low"], contact_intervals(h1["t"], h1["active_nodes"] > 0))[0][1]
    assert peak < peak1, f"{name}: rebound {peak:.3f} not below Test 1's {peak1:.3f}"   # measured 3.82 (Test 1)


@pytest.mark.parametrize("name", ["neohookean_f0_fixed", "neohookean_f0_falling"])
def test_neohookean_energy_never_increases_without_load(histories, name):
    """Prop. 2 with the discrete gradient, f = 0, foundation fixed or lowered (u^n in K^{n+1}): the
    energy rho/2 |v|^2 + int W does not increase in any step, up to the Newton tolerance; there is
    contact, and J stays > 0. (The body is back at its reference position exactly when it touches,
    at t = 2: there |x| vanishes, and Newton's round-off floor must not (solve/newton.idp).)"""
    h = histories[name]
    e = h["energy"]
    assert h["active_nodes"].max() > 0, f"{name}: the disk never touches the foundation"
    gain = np.diff(e).max()
    assert gain <= NEWTON_TOL * e[0], f"{name}: energy rises by {gain:.3g} in one step"
    assert h["min_J"].min() > 0.5 and h["max_penetration"].max() < 1e-9


def test_neohookean_is_second_order_in_dt_without_contact(histories):
    """The mid-point scheme with the discrete gradient is second order in dt (Gonzalez 2000): on the
    spinning free flight (no load, no foundation; the spin strains the body), the RMS over t in [0, 10]
    (the coarsest run's times) of the differences of two probes' displacements between dt = 0.1, 0.05,
    0.025 shrinks 4x per halving (self-convergence; measured 3.96, and 3.94 / 4.01 with dt = 0.2 and
    0.0125 added). (The largest difference instead of the RMS is less regular: ratios 3.18, 3.68, 4.23
    over the same five steps.)"""
    runs = [histories[f"neohookean_spin_dt{dt}"] for dt in NH_SPIN_DTS]
    t = runs[0]["t"]
    cols = ("u1_probe0", "u2_probe0", "u1_probe1", "u2_probe1")

    def at(h):
        return np.array([np.interp(t, h["t"], h[c]) for c in cols])
    u = [at(h) for h in runs]
    diffs = [np.sqrt(((u[k] - u[k + 1]) ** 2).mean()) for k in range(len(u) - 1)]
    ratio = diffs[0] / diffs[1]
    print("NH spin, probe differences between dt halvings:", diffs, "ratio", ratio)
    assert 3.5 <= ratio <= 4.5, f"differences {diffs}: ratio {ratio:.3f}, expected about 4"


def test_neohookean_small_strain_limit(histories):
    """As the load shrinks by s, the Neo-Hookean body tends to linear elasticity with the same
    lambda, mu (its N'(0) = K / 2, tested above): the displacements are O(s) and their difference
    O(s^2), so it shrinks 4x per halving of s (observed >= 3.5x), on the disk resting on the
    foundation under f = -0.1 s."""
    assert_small_strain_limit(histories, "neohookean")


def test_neohookean_p2_conserves_and_contacts(histories, run_status):
    """P2 (-order 2, the coarse disk) through the first impact: the modified energy never rises in a
    step on the fixed foundation (Prop. 2), (10) holds at the P2 contact nodes to round-off, J > 0."""
    h = histories["p2_coarse_neohookean"]
    assert run_status["p2_coarse_neohookean"][0] == 0 and h["active_nodes"].max() > 0
    m = h["modified_energy"]
    assert np.diff(m).max() < 1e-12 * abs(m[0])
    assert h["max_penetration"].max() < 1e-9 and h["contact_pressure_low"].min() >= 0
    assert 0.5 < h["min_J"].min() < 1


def test_neohookean_dt1_keeps_j_positive(histories, runs, run_status):
    """dt = 1 on Test 1: the predictor u^n + dt v^n inverts triangles during the impact; the first
    attempt refuses it at once (W is infinite there), and the retry from u^n, every update halved
    until det F > 0, solves the step. The run completes with retries, J > 0, (10) to round-off and
    no energy rise (Prop. 2; measured 6.9e-13 relative to T = 120, make stress)."""
    h = histories["neohookean_dt1"]
    assert run_status["neohookean_dt1"][0] == 0 and h["t"][-1] == 40 and h["active_nodes"].max() > 0
    assert int(read_summary(runs["neohookean_dt1"])["newton_retries"]) > 0
    m = h["modified_energy"]
    assert np.diff(m).max() < NEWTON_TOL * abs(m[0]) and h["min_J"].min() > 0.5
    assert h["max_penetration"].max() < 1e-9


@pytest.mark.parametrize("scene", sorted(NH_SCENES))
def test_neohookean_runs_every_scene(histories, run_status, scene):
    """-material neohookean runs every scene (the paper's two and spin are above): each completes with
    finite values and J > 0, (10) to round-off with a non-negative contact stress; where the foundation
    is fixed (or absent) and the load constant, the modified energy never rises in a step beyond the
    Newton tolerance times the energies' size (Prop. 2 with the discrete gradient, the bound of SVK's
    tests; measured <= 3.0e-12 of |m| + |energy|, csm3 and cantilever, which start at rest with m = 0; rising and
    wave move their foundation, and do work on the body)."""
    name = f"neohookean_scene_{scene}"
    h = histories[name]
    assert run_status[name][0] == 0
    assert np.isfinite(np.column_stack(list(h.values()))).all()
    assert h["min_J"].min() > 0.2, h["min_J"].min()
    assert h["max_penetration"].max() < 1e-9 and h["contact_pressure_low"].min() >= 0
    if scene not in ("rising", "wave"):
        m = h["modified_energy"]
        rise, size = np.diff(m).max(), np.abs(m).max() + np.abs(h["energy"]).max()
        assert rise < NEWTON_TOL * size, f"{name}: the modified energy rises by {rise:.3g} in a step (energies {size:.3g})"


@pytest.mark.parametrize("name", ["neohookean_test1", "neohookean_test2_t1_18"])
def test_neohookean_history_matches_golden(histories, name):
    """Test 1 and Test 2 (t1 = 18) with the Neo-Hookean body to T = 120, against tests/golden/NAME.csv
    (written from this code's runs; the tolerances of the linear files)."""
    failures = compare(os.path.join(ROOT, "tests", "golden", f"{name}.csv"), histories[name])
    assert not failures, "\n".join(failures)


def test_neohookean_free_flight_with_spin_conserves_energy_and_momenta(histories):
    """No load, no foundation, 1.5 rad of spin by T = 30: the discrete gradient conserves the energy
    (measured 8.6e-12 relative), the angular momentum int rho (X + u) x v (9.0e-12) and the linear
    momentum (1e-14) (Gonzalez 2000)."""
    h = histories["neohookean_spin"]
    e, L = h["energy"], h["angular_momentum"]
    assert np.abs(e - e[0]).max() < 1e-10 * e[0]
    assert np.abs(L - L[0]).max() < 1e-10 * abs(L[0])
    assert np.abs(h["v1_mean"] - h["v1_mean"][0]).max() < 1e-12 and np.abs(h["v2_mean"] - h["v2_mean"][0]).max() < 1e-12


def test_neohookean_restart_reproduces_the_run(tmp_path):
    """A restart from a checkpoint during contact gives the uninterrupted run's rows, byte for byte."""
    opts = ["-material", "neohookean", "-snapshots", "none", "-progress", "0", "-checkpoint_every", "50"]
    run_scene("test1", tmp_path / "full", opts + ["-T", "14"])
    run_scene("test1", tmp_path / "part", opts + ["-T", "12.5"])
    run_scene("test1", tmp_path / "part", ["-restart", str(tmp_path / "part"), "-T", "14"])
    assert (tmp_path / "full" / "history.csv").read_bytes() == (tmp_path / "part" / "history.csv").read_bytes()


def test_min_j_shows_svk_collapsing_where_neohookean_does_not(histories):
    """The history's min_J (non-linear runs): on the paper's Test 1, SVK's smallest det F falls to 0.49
    by t = 16.5, 0.3 before its triangle inverts (svk.md), while the Neo-Hookean body's never goes
    below 0.69 through the whole impact."""
    svk, nh = histories["svk_test1"], histories["neohookean_test1"]
    assert svk["min_J"].min() < 0.55 and nh["min_J"].min() > 0.65
    assert "min_J" not in histories["test1"]                 # a linear run pays nothing for it
