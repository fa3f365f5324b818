"""The methods beside the paper's (issue 17; docs/methods.md): the lumped and singular mass
matrices, and penalty contact. Each test names the property and the equation behind it."""
import os

import numpy as np
import pytest

from conftest import PENALTY_EPS, ROOT, refused_into_copy, run_scene
from golden import compare


def penetration(h):
    return h["max_penetration"].max()


# ---- penalty: the step A x + C' lm(x) = L, lm = kappa [C x - g]_+ (contact_penalty.idp)

def test_penalty_tends_to_the_constraint_linearly_in_eps(histories):
    """As eps -> 0 the penalty step tends to the QP (4) under (10): on the disk resting under
    gravity, the penetration and the difference in u from the constraint's fall 10x per decade
    of eps (first order)."""
    ref = histories["rest_constraint"]
    pen, diff = [], []
    for e in PENALTY_EPS:
        h = histories[f"rest_penalty_{e}"]
        pen.append(penetration(h))
        diff.append(max(np.abs(h["u2_low"] - ref["u2_low"]).max(), np.abs(h["u2_probe0"] - ref["u2_probe0"]).max()))
    for k in range(len(PENALTY_EPS) - 1):
        assert 8 < pen[k] / pen[k + 1] < 12, f"penetration {pen}"
        assert 8 < diff[k] / diff[k + 1] < 12, f"difference from the constraint {diff}"
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


# ---- mass matrices (mass.idp, mass_singular.idp)

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

@pytest.mark.parametrize("name", ["methods_singular", "methods_lumped", "methods_penalty"])
def test_method_history_matches_golden(histories, name):
    failures = compare(os.path.join(ROOT, "tests", "golden", f"{name}.csv"), histories[name])
    assert not failures, "\n".join(failures)


def test_restart_reproduces_a_penalty_singular_mass_run(tmp_path):
    opts = ["-contact", "penalty", "-mass", "singular", "-snapshots", "none", "-progress", "0", "-checkpoint_every", "50"]
    run_scene("test1", tmp_path / "full", opts + ["-T", "16"])
    run_scene("test1", tmp_path / "part", opts + ["-T", "12"])
    run_scene("test1", tmp_path / "part", ["-restart", str(tmp_path / "part"), "-T", "16"])
    assert (tmp_path / "full" / "history.csv").read_bytes() == (tmp_path / "part" / "history.csv").read_bytes()


def test_singular_mass_refused_when_it_cannot_stay_positive_definite(tmp_path, earlier_run):
    """The thin cantilever's 21 contact vertices hold too much of its mass: moving it changes M's
    entries by more than the 1/4 that guarantees a positive definite M (mass_singular.idp)."""
    p, changed = refused_into_copy(tmp_path, earlier_run, "cantilever", ["-mass", "singular", "-T", "1", "-snapshots", "none", "-progress", "0"])
    lines = [line for line in p.stderr.splitlines() if line.strip()]
    assert p.returncode == 3 and len(lines) == 1 and "beyond the 1/4 that keeps it positive definite" in lines[0], p.stderr
    assert not changed
