"""The methods beside the paper's (issue 17; docs/methods.md): the lumped and singular mass
matrices, penalty and Nitsche contact, the Newmark and explicit Verlet schemes. Each test names the
property and the equation behind it."""
import os

import numpy as np
import pytest

from conftest import NITSCHE_GAMMA0, PENALTY_EPS, ROOT, refused_into_copy, run_scene
from golden import compare
from history import contact_intervals, read_csv


def penetration(h):
    return h["max_penetration"].max()


def assert_tends_to_the_constraint_at_first_order(histories, prefix, parameters):
    """The runs prefix_<p> of the resting disk, p one decade apart towards the constraint: their
    penetration and their difference in u from the constraint's run fall 10x per decade (8 to 12x)."""
    ref = histories["rest_constraint"]
    pen, diff = [], []
    for p in parameters:
        h = histories[f"{prefix}_{p}"]
        pen.append(penetration(h))
        diff.append(max(np.abs(h["u2_low"] - ref["u2_low"]).max(), np.abs(h["u2_probe0"] - ref["u2_probe0"]).max()))
    for k in range(len(parameters) - 1):
        assert 8 < pen[k] / pen[k + 1] < 12, f"{prefix}: penetration {pen}"
        assert 8 < diff[k] / diff[k + 1] < 12, f"{prefix}: difference from the constraint {diff}"


# ---- penalty: the step A x + C' lm(x) = L, lm = kappa [C x - g]_+ (contact/penalty.idp)

def test_penalty_tends_to_the_constraint_linearly_in_eps(histories):
    """As eps -> 0 the penalty step tends to the QP (4) under (10): on the disk resting under
    gravity, the penetration and the difference in u from the constraint's fall 10x per decade
    of eps (first order)."""
    assert_tends_to_the_constraint_at_first_order(histories, "rest_penalty", PENALTY_EPS)
    # the penalty law at the lowest point (X2 = 0 on the flat foundation): alpha = penetration / eps
    for e in PENALTY_EPS:
        h = histories[f"rest_penalty_{e}"]
        assert abs(-h["u2_low"][-1] - float(e) * h["contact_pressure_low"][-1]) < 1e-9 * abs(h["u2_low"][-1])


def test_penalty_solves_its_equation_and_the_constraint_is_violated_only_by_it(histories, run_status):
    for name in ("methods_penalty", "methods_penalty_test2", "f0_penalty", "penalty_p2", "cantilever_penalty"):
        h = histories[name]
        assert np.isfinite(np.column_stack(list(h.values()))).all(), name
        assert h["contact_pressure_low"].min() >= 0 and h["active_nodes"].max() > 0, name
        assert run_status[name][0] == 0
    # Test 1: the penetration of eps = 1e-3 is eps times the pressure (about 1e-3 x 26)
    assert 0.01 < penetration(histories["methods_penalty"]) < 0.05


def test_penalty_does_not_create_energy_over_an_impact(histories):
    """With f = 0 on the fixed foundation the step dissipates E + Phi (Phi = sum kappa [C x - g]_+^2 / 2
    is convex and evaluated at t_{n+1}, as the constraint of Prop. 2): out of contact Phi = 0, so
    the energy after the rebound is at most the energy before the impact."""
    h = histories["f0_penalty"]
    contact = np.flatnonzero(h["active_nodes"] > 0)
    before, after = h["energy"][contact[0] - 1], h["energy"][contact[-1] + 1:]
    assert len(after) > 10 and (after <= before * (1 + 1e-12)).all()
    assert np.abs(np.diff(after)).max() < 1e-10 * before      # and conserved again in flight


# ---- mass matrices (mass/matrix.idp, mass/singular.idp)

@pytest.mark.parametrize("mass", ["lumped", "singular"])
def test_free_flight_conserves_energy_and_momentum_with_any_mass(histories, mass):
    """Without contact the mid-point scheme conserves the modified energy (Prop. 2's identity with
    equality) and the momentum changes only by f t, for any symmetric positive definite M."""
    h, ref = histories[f"freeflight_{mass}"], histories["freeflight"]
    m = h["modified_energy"]
    assert np.abs(m - m[0]).max() < 1e-11 * abs(m[0])
    assert np.abs(h["v1_mean"] - h["v1_mean"][0]).max() < 1e-12
    assert np.abs(h["v2_mean"] - (h["v2_mean"][0] - 0.1 * h["t"])).max() < 1e-11
    if mass == "singular":
        # mass, centre of mass and inertia are the consistent M's, so the rigid motion's
        # kinetic energy (translation and spin) is too
        assert abs(h["energy"][0] - ref["energy"][0]) < 1e-12 * ref["energy"][0]


def test_singular_mass_dissipates_far_less_at_impact(histories):
    """f = 0, one impact on the fixed foundation: the constraint at t_{n+1} dissipates
    lm'(g - C u^n) >= 0 per step (Prop. 2). Without inertia at the contact nodes (singular mass)
    that loss is several times smaller than with the consistent or lumped mass; it is not 0, since
    (10) is imposed at t_{n+1}, not at the mid-point."""
    loss = {m: histories[f"f0_{m}"]["energy"][0] - histories[f"f0_{m}"]["energy"][-1]
            for m in ("consistent", "singular", "lumped")}
    for m, h in ((m, histories[f"f0_{m}"]) for m in loss):
        assert np.diff(h["energy"]).max() < 1e-9 * h["energy"][0], m
        assert loss[m] > 0, m
    assert loss["singular"] < loss["consistent"] / 5 and loss["lumped"] > loss["singular"], loss


def test_singular_mass_impact_loss_vanishes_as_dt_falls(histories):
    """f = 0 on the fixed foundation, one impact. By Prop. 2's identity a step changes the energy by
    -lm'(g - C u^n) <= 0: only a contact node that enters contact in the step (g - C u^n > 0 there)
    costs energy. With the singular mass such a node carries no momentum, so the loss is that of
    closing a gap of O(dt) under a bounded force, and it vanishes as dt -> 0 (measured 3.2x and 3.9x
    less per halving of dt: 1.3e-4, 4.0e-5, 1.0e-5 of the energy). With the consistent mass the
    contact nodes' momentum is destroyed at impact whatever dt (8.7e-4, 9.4e-4, 1.0e-3). So the
    singular mass method conserves the energy through impacts in the limit dt -> 0, not to round-off
    at a fixed dt: (10) at t_{n+1} makes each entering node's step dissipative (docs/methods.md)."""
    def loss(name):
        e = histories[name]["energy"]
        assert np.diff(e).max() < 1e-9 * e[0], name            # never a gain (Prop. 2)
        return (e[0] - e[-1]) / e[0]
    singular = [loss(n) for n in ("f0_singular", "f0_singular_dt0.025", "f0_singular_dt0.0125")]
    consistent = [loss(n) for n in ("f0_consistent", "f0_consistent_dt0.025", "f0_consistent_dt0.0125")]
    for k in range(2):
        assert singular[k] / singular[k + 1] > 2.5, singular      # at least first order; measured 3.2, 3.9
        assert consistent[k + 1] > 0.9 * consistent[k], consistent
    assert singular[-1] < consistent[-1] / 50, (singular, consistent)


def test_singular_mass_smooths_the_contact_stress(histories):
    """The singular mass method removes the oscillation of the contact stress at the lowest
    point during the first impact (Test 1, [10, 23]): its RMS about a 1.0-wide moving average
    is under a tenth of the consistent mass's."""
    def oscillation(h):
        t, a = h["t"], h["contact_pressure_low"]
        width = int(round(1.0 / (t[1] - t[0])))
        avg = np.convolve(a, np.ones(width + 1) / (width + 1), mode="same")
        s = (t >= 10) & (t <= 23)
        return np.sqrt(np.mean((a - avg)[s] ** 2))
    consistent, singular = oscillation(histories["test1"]), oscillation(histories["methods_singular"])
    assert singular < consistent / 10, (consistent, singular)


@pytest.mark.parametrize("mass", ["singular", "lumped"])
def test_both_qp_solvers_agree_with_any_mass(histories, mass):
    """IPOPT and the exact active-set solver solve the same QP (4): IPOPT at tol 1e-10, since its
    default 1e-8 alone moves u2_low by up to 2e-5 with the lumped mass (as test_solvers.py)."""
    a, b = histories[f"methods_{mass}"], histories[f"methods_{mass}_ipopt"]
    assert np.abs(a["u2_low"] - b["u2_low"]).max() < 1e-6
    assert penetration(a) < 1e-9 and penetration(b) < 1e-8


def test_lumped_mass_with_a_clamped_body(histories):
    h, ref = histories["cantilever_lumped"], histories["cantilever_activeset"]
    assert np.isfinite(h["u2_probe1"]).all() and penetration(h) < 1e-9
    assert np.abs(h["u2_probe0"]).max() == 0        # the clamped end stays put (eq. (2))
    # the same beam, another mass matrix: the tip differs, but not by much
    assert np.abs(h["u2_probe1"] - ref["u2_probe1"]).max() < 0.2 * np.abs(ref["u2_probe1"]).max()


# ---- golden histories of the new methods, and restarts

@pytest.mark.parametrize("name", ["methods_singular", "methods_lumped", "methods_penalty", "newmark_damped", "verlet_penalty",
                                  "nitsche_theta1", "nitsche_theta0", "nitsche_theta-1", "verlet_nitsche"])
def test_method_history_matches_golden(histories, name):
    failures = compare(os.path.join(ROOT, "tests", "golden", f"{name}.csv"), histories[name])
    assert not failures, "\n".join(failures)


@pytest.mark.parametrize("scene,opts,horizons", [
    ("test1", ["-contact", "penalty", "-mass", "singular"], ("12", "16")),
    ("test2", ["-contact", "nitsche", "-nitsche_theta", "-1"], ("12.5", "14")),
    ("test2", ["-scheme", "newmark", "-newmark_gamma", "0.6", "-newmark_beta", "0.3025", "-solver", "activeset"], ("12.5", "20")),
], ids=["penalty-singular", "nitsche-moving", "newmark-moving"])
def test_restart_reproduces_the_run(tmp_path, scene, opts, horizons):
    """A restart from a checkpoint during contact gives the uninterrupted run's rows, byte for
    byte: the active set, the multipliers (and Newmark's acceleration, recomputed from them)."""
    opts = opts + ["-snapshots", "none", "-progress", "0", "-checkpoint_every", "50"]
    stop, end = horizons
    run_scene(scene, tmp_path / "full", opts + ["-T", end])
    run_scene(scene, tmp_path / "part", opts + ["-T", stop])
    run_scene(scene, tmp_path / "part", ["-restart", str(tmp_path / "part"), "-T", end])
    assert (tmp_path / "full" / "history.csv").read_bytes() == (tmp_path / "part" / "history.csv").read_bytes()


def test_singular_mass_refused_when_it_cannot_stay_positive_definite(tmp_path, earlier_run):
    """The thin cantilever's 21 contact vertices hold too much of its mass: moving it changes M's
    entries by more than the 1/4 that guarantees a positive definite M (mass/singular.idp)."""
    p, changed = refused_into_copy(tmp_path, earlier_run, "cantilever", ["-mass", "singular", "-T", "1", "-snapshots", "none", "-progress", "0"])
    lines = [line for line in p.stderr.splitlines() if line.strip()]
    assert p.returncode == 3 and len(lines) == 1 and "beyond the 1/4 that keeps it positive definite" in lines[0], p.stderr
    assert not changed


# ---- schemes: Newmark (scheme/newmark.idp), explicit Verlet (scheme/verlet.idp)

@pytest.mark.parametrize("name", ["newmark_freeflight", "verlet_freeflight"])
def test_free_flight_momentum_and_energy_for_every_scheme(histories, name):
    """Without contact the momentum changes only by f t (every scheme here is exact for a constant
    acceleration), and a rigid motion's energy is kept."""
    h = histories[name]
    assert np.abs(h["v1_mean"] - h["v1_mean"][0]).max() < 1e-12
    assert np.abs(h["v2_mean"] - (h["v2_mean"][0] - 0.1 * h["t"])).max() < 1e-11
    m = h["modified_energy"]
    assert np.abs(m - m[0]).max() < 1e-11 * abs(m[0])


def test_newmark_trapezoidal_is_the_midpoint_scheme_without_contact(histories):
    """beta = 1/4, gamma = 1/2 is the trapezoidal rule, which for a linear body is the mid-point
    scheme (1)-(2) as long as no contact force enters the acceleration."""
    a, b = histories["newmark_freeflight"], histories["freeflight"]
    assert np.abs(a["u2_low"] - b["u2_low"]).max() < 1e-10 and np.abs(a["v2_low"] - b["v2_low"]).max() < 1e-10


def test_damped_newmark_keeps_its_energy_bounded(histories, run_status):
    """The finding of docs/methods.md: with the contact force in the acceleration and gamma = 1/2,
    the constrained equations (an index-3 differential-algebraic system) are integrated without
    damping, and the energy grows during the first impact (Krause-Walloth [8]; the run stops:
    test_promises.py); gamma = 0.6 damps it: bounded, and lower at the end. Not monotone (its damping
    is of the high frequencies, in another norm than this energy): at most 0.03% above the start."""
    d = histories["newmark_damped"]["modified_energy"]
    assert d.max() <= d[0] * (1 + 1e-3) and d[-1] < d[0] * 0.99
    assert "warning" not in run_status["newmark_damped"][1]


def test_newmark_keeps_the_constraint_exactly(histories):
    assert penetration(histories["newmark_damped"]) < 1e-9


def assert_near_the_getfem_reference(h, u2_bound):
    """The first impact of the reference ([8.95, 23.83]) within 0.15, and u2_low within u2_bound."""
    ref = read_csv(os.path.join(ROOT, "tests", "reference", "getfem-verlet-nitsche-test1.csv"))
    start, end = contact_intervals(h["t"], h["active_nodes"] > 0)[0]
    assert abs(start - 8.95) <= 0.15 and abs(end - 23.83) <= 0.15, (start, end)
    s = ref["t"] <= h["t"][-1]
    assert np.abs(np.interp(ref["t"][s], h["t"], h["u2_low"]) - ref["u2_low"][s]).max() < u2_bound


def test_verlet_penalty_agrees_with_the_getfem_reference(histories):
    """The GetFEM reference is explicit Verlet with Nitsche contact (theta = 1, gamma0 = 1000) at
    dt = 0.01 ([3]); explicit Verlet with penalty (eps = 1e-3) is the nearest method here: same
    first contact to 0.15, u2_low to 0.25, the energy within 1.5% of its start."""
    h = histories["verlet_penalty"]
    assert_near_the_getfem_reference(h, 0.25)
    m = h["modified_energy"]
    assert np.abs(m - m[0]).max() < 0.015 * m[0]


def test_verlet_refuses_a_step_above_its_critical_step(tmp_path, earlier_run):
    """The explicit scheme is stable only for dt below 2 / sqrt(lambda_max(M^-1 (K + C' kappa C))):
    the paper's dt = 0.05 is above it on the paper's disk with eps = 1e-3 (about 0.0207), so the
    run is refused with one line that names the limit, and nothing changes."""
    p, changed = refused_into_copy(tmp_path, earlier_run, "test1", ["-scheme", "verlet", "-contact", "penalty", "-T", "1",
                                                                    "-progress", "0"])
    lines = [line for line in p.stderr.splitlines() if line.strip()]
    assert p.returncode == 3 and len(lines) == 1, p.stderr
    assert "-dt 0.05 is above the critical step 0.0206" in lines[0] and "-allow_above_critical 1" in lines[0]
    assert not changed


def test_verlet_just_below_the_critical_step_is_stable_and_above_it_stops(tmp_path, histories):
    """Free flight at 94% of the critical step (0.0426 without contact) keeps its energy
    (verlet_freeflight); at 106%, asked for on purpose, the run blows up, and the energy guard stops
    it with exit 4 and one line at the step where its energy has grown by 10% (before, at the first
    non-finite step), never exit 0 (Prop. 2 without contact: the energy is conserved)."""
    p = run_scene("freeflight", tmp_path / "above", ["-scheme", "verlet", "-dt", "0.045", "-allow_above_critical", "1",
                                                      "-T", "30.06", "-progress", "0", "-snapshots", "none"], check=False)
    assert "note: -scheme verlet: critical step 0.0426" not in p.stdout
    assert "above the critical step 0.0426" in p.stderr
    errors = [line for line in p.stderr.splitlines() if line.startswith("error:")]
    assert p.returncode == 4 and len(errors) == 1, p.stderr
    assert errors[0].startswith("error: the modified energy grew from") and "explicit Verlet is stable only below" in errors[0]
    assert "without a foundation" in errors[0]
    h = read_csv(os.path.join(tmp_path, "above", "history.csv"))
    assert np.isfinite(h["energy"]).all() and h["energy"][-1] < 2 * h["energy"][0]


def test_verlet_runs_at_p2(histories):
    h = histories["verlet_p2"]
    assert np.isfinite(h["u2_low"]).all() and h["active_nodes"].max() > 0


# ---- Nitsche (contact/nitsche.idp)

def test_nitsche_tends_to_the_constraint_as_gamma0_grows(histories):
    """gamma = gamma0 / h -> infinity: Nitsche's step tends to the QP (4) under (10), the penetration
    and the difference in u falling about as 1 / gamma0 (10x per decade, measured 9.6-10.8)."""
    assert_tends_to_the_constraint_at_first_order(histories, "rest_nitsche", NITSCHE_GAMMA0)


@pytest.mark.parametrize("theta", ["1", "0", "-1"])
def test_nitsche_first_impact_and_no_energy_gain(histories, theta):
    """Every theta keeps the first impact of Test 1 ([8.95, 23.9], as the constraint) with a
    penetration of a few 1e-3 at gamma0 = 1000, and no step raises the modified energy above its
    start (the theta term at K's mid-point, the contact term at t_{n+1})."""
    h = histories[f"nitsche_theta{theta}"]
    start, end = contact_intervals(h["t"], h["active_nodes"] > 0)[0]
    assert abs(start - 8.95) < 0.06 and abs(end - 23.9) < 0.11, (start, end)
    assert 1e-3 < penetration(h) < 0.01
    m = h["modified_energy"]
    assert m.max() <= m[0] * (1 + 1e-12)


def test_nitsche_with_f0_loses_energy_only_at_the_impact(histories):
    h = histories["f0_nitsche"]
    e = h["energy"]
    assert e[-1] < e[0] and e.max() <= e[0] * (1 + 1e-12)


def test_verlet_nitsche_is_the_getfem_reference_scheme(histories):
    """Explicit Verlet with Nitsche (theta = 1, gamma0 = 1000) at dt = 0.01 is the reference's own
    method ([3]; another mesh and code): first contact within 0.15, u2_low within 0.2, the
    reference's penetration (0.055) in size."""
    h = histories["verlet_nitsche"]
    assert_near_the_getfem_reference(h, 0.2)
    assert 0.01 < penetration(h) < 0.06


def test_nitsche_with_a_clamped_body(histories, run_status):
    h = histories["cantilever_nitsche"]
    assert np.abs(h["u2_probe0"]).max() == 0 and h["active_nodes"].max() > 0
    assert "warning" not in run_status["cantilever_nitsche"][1]


@pytest.mark.parametrize("theta,gamma0,least", [("1", "100", "120.78"), ("0", "20", "30.19")])
def test_nitsche_refuses_a_gamma0_below_its_stability_bound(tmp_path, earlier_run, theta, gamma0, least):
    """Nitsche's step is well posed, and for theta = 1 its augmented energy positive, only for
    gamma0 > (1 + theta)^2 C / 4, C the discrete trace constant (sum omega h sigma_nu(z)^2 <= C z'Kz,
    [1]); computed at start-up (C = 120.78 on the paper's disk with lambda = mu = 30). Below it the
    energy of Test 1 with f = 0 grew to 1e45 (theta = 0, gamma0 = 10) with exit 0; now refused,
    one line naming the bound, nothing changed. theta = -1 has no bound."""
    p, changed = refused_into_copy(tmp_path, earlier_run, "test1", ["-contact", "nitsche", "-nitsche_theta", theta,
                                                                    "-nitsche_gamma0", gamma0, "-T", "1", "-progress", "0"])
    lines = [line for line in p.stderr.splitlines() if line.strip()]
    assert p.returncode == 3 and len(lines) == 1, p.stderr
    assert f"-nitsche_gamma0 {gamma0} is not above {least}" in lines[0] and "-nitsche_theta -1" in lines[0], lines[0]
    assert not changed


def test_nitsche_active_set_failure_says_what_it_means(tmp_path):
    """theta = -1 accepts any gamma0 > 0, but at gamma0 = 1 the stress dominates P(u) and the
    semi-smooth Newton cycles between sets when the disk first touches: exit 4, one line that says
    so and what to change, the history kept."""
    p = run_scene("test1", tmp_path / "cycle", ["-contact", "nitsche", "-nitsche_theta", "-1", "-nitsche_gamma0", "1", "-fy", "0",
                                                "-v0y", "-0.5", "-u0y", "1", "-T", "4", "-progress", "0", "-snapshots", "none"],
                  check=False)
    errors = [line for line in p.stderr.splitlines() if line.startswith("error:")]
    assert p.returncode == 4 and len(errors) == 1, p.stderr
    assert "the active set did not settle" in errors[0] and "a larger -nitsche_gamma0" in errors[0], errors[0]
    h = read_csv(os.path.join(tmp_path, "cycle", "history.csv"))
    assert len(h["t"]) > 10 and np.isfinite(h["energy"]).all()


def test_nitsche_default_gamma0_is_stable_on_every_body(tmp_path):
    """The default gamma0 is 1000 (the reference's, on the paper's disk, 8.3 C there), or 8 C where
    that is larger: on the corner scene C = 1651.57, and 1000 was refused (review); the run records
    the gamma0 it used, so a restart continues with it."""
    out = tmp_path / "corner"
    p = run_scene("corner", out, ["-contact", "nitsche", "-T", "1", "-progress", "0", "-snapshots", "none"])
    assert "-nitsche_gamma0 is 8 C = 13212.6 on this body" in p.stdout
    assert "-nitsche_gamma0 13212.57" in (out / "parameters.txt").read_text()
