"""St Venant-Kirchhoff (paper Section 3): -material svk, solved by semi-smooth Newton.

Each test states the property it checks and the equation behind it. The runs are
in conftest.py. With the paper's lambda = mu = 30 the SVK body collapses in
Test 1 at t = 16.8 (test_test1_collapse_is_one_clear_error), so the Test 1 runs
here stop before that.
"""
import os
import subprocess

import numpy as np
import pytest

from conftest import ROOT, SMALL_LOADS, error_lines, run_scene
from driver import freefem_env
from golden import compare
from history import read_csv, read_parameters, read_summary

NEWTON_TOL = 1e-10      # -newton_tol default: |R + C'lm| relative to its terms


def run_unit(seed, order=1, material="svk", scale=None):
    """tests/edp/<material>_unit.edp (P1) or <material>_unit_p2.edp (P2) at a random state (a 1 rad
    rotation plus smooth fields of amplitude scale, 0.1 by default)."""
    env = freefem_env()
    script = f"tests/edp/{material}_unit.edp" if order == 1 else f"tests/edp/{material}_unit_p2.edp"
    p = subprocess.run(["FreeFem++-nw", "-nw", "-ns", "-v", "0", script, "-mesh", "meshes/disk.msh",
                        "-seed", str(seed)] + (["-scale", str(scale)] if scale else []), cwd=ROOT, capture_output=True,
                       text=True, env=env)
    assert p.returncode == 0, p.stdout + p.stderr
    values = {}
    for line in p.stdout.splitlines():
        parts = line.split()
        if parts and parts[0] in ("tangent", "identity", "linear", "gradient"):
            values[parts[0]] = float(parts[1])
        if parts and parts[0] == "inverted":
            values["inverted"], values["inverted_force"] = float(parts[1]), int(parts[2])
    return values


@pytest.mark.parametrize("seed,order", [(1, 1), (2, 1), (3, 1), (1, 2)])
def test_tangent_identity_and_linear_limit_at_a_random_state(seed, order):
    """The consistent tangent N'(x) against a central difference of the mid-point force N
    (relative error <= 1e-6); the discrete-gradient identity of Section 3,
    N(x).(x - u^n) = W(x) - W(u^n), to round-off; and N'(0) = K / 2, the linear form of (1).
    At P2 the 7-point rule integrates W, N and N' exactly, so the identity holds to round-off too.
    And for a vanishing step (u^n = x) N(x) is the gradient of the stored energy at x, against its
    central difference (<= 1e-6; measured 1.9e-10 to 9.1e-9): the stress is dW/dE at any state."""
    v = run_unit(seed, order)
    assert v["gradient"] <= 1e-6, f"N against the gradient of W: relative error {v['gradient']:.3g}"
    assert v["tangent"] <= 1e-6, f"tangent against central differences: relative error {v['tangent']:.3g}"
    assert v["identity"] <= 1e-12, f"energy identity: relative error {v['identity']:.3g}"
    assert v["linear"] <= 1e-12, f"N'(0) against K/2: relative error {v['linear']:.3g}"


def test_spinning_free_flight_conserves_energy_and_momenta(histories, runs):
    """Simo-Tarnow (the paper's [15]): without contact and with f = 0 (dead load), the SVK
    mid-point scheme conserves rho/2|v|^2 + int W exactly, and linear and angular momentum.
    The disk turns 1.5 rad (spin 0.05, T = 30)."""
    params = read_parameters(runs["svk_spin"])
    assert float(params["-spin"]) * float(params["-T"]) >= 1, "the scene must turn the disk at least 1 rad"
    h = histories["svk_spin"]
    e, am = h["energy"], h["angular_momentum"]
    assert np.abs(e - e[0]).max() <= 1e-9 * e[0], f"energy drifts by {np.abs(e - e[0]).max() / e[0]:.3g} (relative)"
    assert np.abs(am - am[0]).max() <= 1e-9 * abs(am[0]), \
        f"angular momentum drifts by {np.abs(am - am[0]).max() / abs(am[0]):.3g} (relative)"
    for c in ("v1_mean", "v2_mean"):
        assert np.ptp(h[c]) <= 1e-12, f"linear momentum ({c}) changes by {np.ptp(h[c]):.3g}"
    assert h["max_strain"].max() < 0.01, "the spinning SVK disk strains only by the centrifugal load"


def test_spinning_free_flight_conserves_energy_with_another_density(histories):
    """The same conservation with rho = 2: the inertia 2 M (x - u^n - dt v^n) / dt^2 of the
    Newton residual and the energy v'Mv / 2 use the same mass matrix M (rho in it)."""
    e = histories["svk_spin_rho2"]["energy"]
    assert np.abs(e - e[0]).max() <= 1e-9 * e[0], f"energy drifts by {np.abs(e - e[0]).max() / e[0]:.3g} (relative)"


def test_spinning_linear_body_grows(histories):
    """Linear elasticity is not invariant under rotation: a rigid rotation strains it, and the
    spinning linear disk follows u = t omega x X (an infinitesimal rotation, zero energy), so it
    grows: its largest Green-Lagrange strain reaches 1 while the SVK disk's stays below 0.01."""
    lin, svk = histories["linear_spin"], histories["svk_spin"]
    assert lin["max_strain"][-1] > 1 > 100 * svk["max_strain"].max()
    assert np.all(np.diff(lin["max_strain"][1:]) > 0), "the linear disk's strain grows monotonically"


@pytest.mark.parametrize("name", ["svk_test1", "svk_test1_every_step", "svk_test2_t1_18"])
def test_free_fall_is_exact_before_impact(histories, name):
    """A rigid body under a constant load: the mid-point scheme is exact, u2 = 4 - 0.05 t^2, and
    SVK's internal force vanishes on rigid translations (E = 0)."""
    h = histories[name]
    before = h["t"] < h["t"][np.argmax(h["active_nodes"] > 0)]
    err = np.abs(h["u2_low"][before] - (4 - 0.05 * h["t"][before] ** 2)).max()
    assert err < 1e-10, f"{name}: free fall differs from 4 - 0.05 t^2 by {err:.3g}"


def test_modified_energy_never_increases_on_the_fixed_foundation(histories):
    """(1) with w = u^n and the identity of Section 3, f constant: the modified energy
    rho/2|v|^2 + int W - (f, u) cannot increase, up to the Newton tolerance."""
    for name in ("svk_test1", "svk_test1_every_step", "svk_stiff_test1"):
        m = histories[name]["modified_energy"]
        gain = np.diff(m).max()
        assert gain <= NEWTON_TOL * abs(m[0]), f"{name}: modified energy rises by {gain:.3g} in one step"


@pytest.mark.parametrize("name", ["svk_f0_fixed", "svk_f0_falling"])
def test_energy_never_increases_without_load(histories, name):
    """Prop. 2 for SVK, f = 0, foundation fixed or decreasing (u^n in K^{n+1}): the energy
    rho/2|v|^2 + int W does not increase, up to the Newton tolerance; and there is contact."""
    h = histories[name]
    e = h["energy"]
    assert h["active_nodes"].max() > 0, f"{name}: the disk never touches the foundation"
    gain = np.diff(e).max()
    assert gain <= NEWTON_TOL * e[0], f"{name}: energy rises by {gain:.3g} in one step"


@pytest.mark.parametrize("name", ["svk_test1", "svk_test1_every_step", "svk_test2_t1_18", "svk_f0_fixed", "svk_f0_falling",
                                  "svk_stiff_test1", "svk_incline", "svk_oblique"])
def test_contact_conditions(histories, name):
    """Constraint (10) to round-off (penetration <= 1e-9) and a non-negative contact stress
    alpha of (6); every value finite."""
    h = histories[name]
    assert h["max_penetration"].max() <= 1e-9, f"{name}: penetration {h['max_penetration'].max():.3g}"
    assert h["contact_pressure_low"].min() >= 0 and h["contact_force_y"].min() >= 0
    assert np.isfinite(np.column_stack(list(h.values()))).all()


def test_skip_free_gives_the_same_history(histories):
    """-skip_free 1 solves the unconstrained step first when no vertex was in contact; the
    answer is the same complementarity problem's."""
    a, b = histories["svk_test1"], histories["svk_test1_every_step"]
    n = len(b["t"])
    assert np.abs(a["u2_low"][:n] - b["u2_low"]).max() < 1e-9
    assert b["qp_solved"][1:].all() and a["qp_solved"][:n].sum() < b["qp_solved"].sum()


def test_small_strain_limit(histories):
    """As the load shrinks by s, SVK tends to linear elasticity: the displacements are O(s)
    and their difference O(s^2) (the geometric terms of E), so it shrinks 4x per halving
    of s (observed >= 3.5x), on the disk resting on the foundation under f = -0.1 s."""
    assert_small_strain_limit(histories, "svk")


def assert_small_strain_limit(histories, material):
    """The largest difference of the top's u2 between MATERIAL and linear, resting under f = -0.1 s,
    shrinks >= 3.5x per halving of s (SMALL_LOADS)."""
    diffs = []
    for s in SMALL_LOADS:
        a, b = histories[f"rest_{material}_{s}"], histories[f"rest_linear_{s}"]
        diffs.append(np.abs(a["u2_probe0"] - b["u2_probe0"]).max())
    ratios = [diffs[k] / diffs[k + 1] for k in range(len(diffs) - 1)]
    print(f"{material} - linear, top of the disk:", dict(zip(SMALL_LOADS, diffs)), "ratios", ratios)
    assert all(r >= 3.5 for r in ratios), f"differences {diffs}: ratios {ratios}, expected about 4"


@pytest.mark.parametrize("name", ["svk_test1", "svk_stiff_test1"])
def test_history_matches_golden(histories, name):
    """SVK Test 1 to T = 16.5 (its collapse is at 16.8), and Test 1 with a stiff disk
    (lambda = mu = 300) to T = 45, against tests/golden/NAME.csv."""
    failures = compare(os.path.join(ROOT, "tests", "golden", f"{name}.csv"), histories[name])
    assert not failures, "\n".join(failures)


def test_test1_collapse_is_one_clear_error(tmp_path, runs):
    """With lambda = mu = 30 the SVK body collapses under the impact (SVK's stress peaks under
    compression): Newton, then its damped retry, fail at step 336 with an inverted triangle.
    The run stops with exit 4 and one line naming the step, the time and the reason, and
    history.csv keeps every step before it, identical to the run that stopped at T = 16.5."""
    out = tmp_path / "collapse"
    p = run_scene("test1", out, ["-material", "svk", "-T", "17", "-progress", "0", "-vtk", "0"], check=False)
    errors = error_lines(p)
    assert p.returncode == 4 and len(errors) == 1, p.stderr
    assert errors[0].startswith("error: newton failed at step 336, t = 16.8: triangle ") and "inverted (det F = " in errors[0]
    assert "history.csv keeps every step before it" in errors[0]
    rows = open(out / "history.csv").read().splitlines()
    assert len(rows) == 1 + 336 and rows[-1].startswith("335,")
    before = open(os.path.join(runs["svk_test1"], "history.csv")).read().splitlines()
    assert rows[:len(before)] == before
    assert not (out / "summary.txt").exists()


def test_restart_reproduces_the_run(tmp_path):
    """A restart from a checkpoint during contact (t = 9.5: the Newton warm start is the
    checkpoint's active set and multipliers) gives the same history as the run straight through."""
    args = ["-material", "svk", "-progress", "0", "-snapshots", "none"]
    straight, first, restarted = tmp_path / "straight", tmp_path / "first", tmp_path / "restarted"
    run_scene("test1", straight, args + ["-T", "10.5"])
    run_scene("test1", first, args + ["-T", "10", "-checkpoint_every", "190"])
    run_scene("test1", restarted, ["-restart", str(first), "-T", "10.5", "-progress", "0"])
    a, b = read_csv(straight / "history.csv"), read_csv(restarted / "history.csv")
    assert a["active_nodes"][190] > 0, "the checkpoint must be during contact"
    for c in a:
        assert np.array_equal(a[c], b[c]), f"column {c} differs after the restart"
    sa, sb = read_summary(straight), read_summary(restarted)
    for key in ("newton_iterations", "newton_retries", "gmres_iterations", "max_strain", "qp_steps"):
        assert sa[key] == sb[key], f"summary.txt {key}: {sa[key]} straight through, {sb[key]} after the restart"


def test_a_failed_newton_is_retried_to_the_same_answer(tmp_path, histories):
    """With -newton_max_iter 2 the first attempt fails on every contact step (Newton needs 3
    iterations there); the retry from u^n with damped updates and 4x the iterations solves
    the same problem, so the history is the default run's within the Newton tolerance."""
    out = tmp_path / "retried"
    run_scene("test1", out, ["-material", "svk", "-T", "10", "-newton_max_iter", "2", "-progress", "0", "-snapshots", "none"])
    summary = read_summary(out)
    assert int(summary["newton_retries"]) > 0
    a, b = read_csv(out / "history.csv"), histories["svk_test1"]
    n = len(a["t"])
    assert np.abs(a["u2_low"] - b["u2_low"][:n]).max() < 1e-9
    assert np.abs(a["contact_force_y"] - b["contact_force_y"][:n]).max() < 1e-6


def test_newton_failure_without_retry_is_one_clear_error(tmp_path):
    """-newton_retry 0: the first failed step stops the run with exit 4 and one line naming
    the step, the time and the reason; history.csv keeps every step before it."""
    out = tmp_path / "failed"
    p = run_scene("test1", out, ["-material", "svk", "-T", "10", "-newton_max_iter", "2", "-newton_retry", "0",
                                 "-progress", "0", "-snapshots", "none"], check=False)
    errors = error_lines(p)
    assert p.returncode == 4 and len(errors) == 1, p.stderr
    assert errors[0].startswith("error: newton failed at step 179, t = 8.95: no convergence in 2 Newton iterations")
    rows = open(out / "history.csv").read().splitlines()
    assert len(rows) == 1 + 179 and rows[-1].startswith("178,")
    assert not (out / "summary.txt").exists()


def test_make_svk_measures_the_three_bodies_alike(runs, histories):
    """make svk's measurements (postprocess/svk_measures.py) on this suite's short Test 1 runs of the
    three bodies (linear to T = 45, SVK to 16.5, Neo-Hookean to 120): the first contact starts at the
    same step for all (the free fall is the same), det F from the snapshots equals the history's min_J
    (metrics() fails otherwise; the linear body's min J comes from its snapshots alone) and lies in
    (0, 1) under the impact, and the modified energy does not rise in a step on the fixed foundation."""
    import svk_measures
    for model, name in (("linear", "test1"), ("svk", "svk_test1"), ("neohookean", "neohookean_test1")):
        res = {"case": "test1", "model": model, "dir": runs[name], "broke": None, "wall": 0.0}
        m = svk_measures.metrics(res, histories[name])
        assert m["first_contact"][0] == 8.95, f"{model}: first contact at {m['first_contact']}"
        assert 0 < m["snapshot_min_J"][0] < 1, f"{model}: min J at the snapshots {m['snapshot_min_J']}"
        e0, _, rise = m["energy"]
        assert rise <= 1e-8 * abs(e0), f"{model}: the modified energy rises by {rise:.3g} in one step"


def test_make_svk_uniaxial_stresses_are_the_derivatives_of_the_energies():
    """svk_uniaxial's curves: under uniaxial strain F = diag(s, 1) each model's P11 is dW/ds of its
    stored energy (W_svk = lambda/2 tr(E)^2 + mu E:E, W_nh = mu/2 (tr C - 2 - 2 ln J) + lambda/2 (ln J)^2),
    checked by central differences, and all three have the slope lambda + 2 mu at s = 1."""
    from svk_measures import uniaxial_stress
    lam, mu = 30.0, 30.0
    W = {"linear": lambda s: (lam + 2 * mu) / 2 * (s - 1) ** 2,
         "svk": lambda s: (lam / 2 + mu) * ((s * s - 1) / 2) ** 2,
         "neohookean": lambda s: mu / 2 * (s * s - 1 - 2 * np.log(s)) + lam / 2 * np.log(s) ** 2}
    s, h = np.linspace(0.3, 1.3, 11), 1e-6
    P = uniaxial_stress(s, lam, mu)
    for model, w in W.items():
        assert np.abs((w(s + h) - w(s - h)) / (2 * h) - P[model]).max() < 1e-6, model
        up, down = (uniaxial_stress(np.array([1 + d]), lam, mu)[model][0] for d in (h, -h))
        assert abs((up - down) / (2 * h) - (lam + 2 * mu)) < 1e-5, f"{model}: slope at s = 1"
