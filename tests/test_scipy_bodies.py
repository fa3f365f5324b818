"""The two-body prototype of tests/reference/scipy_bodies.py: the mid-point scheme (1)-(2) with constraint (10)
between two bodies (node to segment, re-linearised to the true gap), on the two bars' impact, against what the
scheme must give and the bars' closed form (postprocess/bars_exact.py). Fast, no FreeFEM: the reference that the
FreeFEM bodies will be compared with."""
import numpy as np
import pytest

import bars_exact
import scipy_bodies
from scipy_bodies import bars

MU, RHO, V0, LENGTH = 50.0, 1.0, 0.01, 10.0


@pytest.fixture(scope="module")
def history():
    return bars((LENGTH, LENGTH), size=0.5, mu=MU, rho=RHO, v0=V0, T=2.5, dt=0.05)


def test_momentum_is_conserved_to_round_off(history):
    """The rows' coefficients sum to zero in each component (the contact forces are equal and opposite), and the
    translations are in K's kernel: the scheme conserves the total momentum exactly, here to 1e-12 of m v0."""
    scale = RHO * LENGTH * 1.0 * V0
    assert np.abs(history["momentum_x"]).max() <= 1e-12 * scale
    assert np.abs(history["momentum_y"]).max() <= 1e-12 * scale


def test_energy_never_increases_and_the_true_gap_holds(history):
    """Prop. 2 between bodies: E^{n+1} <= E^n, and at the end of every step the true gap between the bodies holds at
    every node (the step re-linearised about its result). Prop. 2 holds for the step's own rows; the rows are
    re-linearised until the closest points hold to 1e-13 of a segment, and what that leaves, times the contact
    force, bounds the energy's rise: 3.5e-10 E^0 at most here, within 1e-9 E^0."""
    e = history["energy"]
    assert np.all(np.diff(e) <= 1e-9 * e[0])
    assert history["max_penetration"].max() <= 1e-12


def test_the_bars_impact_is_the_closed_forms_within_the_meshs_error(history):
    """Equal bars at +-v0 (lambda = 0, c = sqrt(2 mu/rho)): contact lasts 2L/c (to one step), its mean force is
    rho c v0 h within 5%, and the bars leave with their velocities reversed within 5% on this coarse mesh (h = 0.5,
    dt = 0.05: c dt/h = 1; the rest stays in the bars as waves the mesh disperses)."""
    exact = bars_exact.impact((LENGTH, LENGTH), (V0, -V0), MU, RHO)
    t, force = history["t"], history["contact_force"]
    dt = t[1] - t[0]
    touching = t[force > 0]
    assert abs(touching[-1] - exact["contact_end"]) <= 1.01 * dt
    assert force[force > 0].mean() == pytest.approx(exact["contact_force"], rel=0.05)
    after = (history["body1_v1_mean"][-1], history["body2_v1_mean"][-1])
    assert after == pytest.approx(exact["mean_velocity_after"], rel=0.05)


NON_MATCHING = ((1 / 3, 1 / 4), (1 / 4, 1 / 3), (0.17, 0.23))


@pytest.mark.parametrize("sizes", NON_MATCHING + ((0.2, 0.2),), ids=lambda s: f"{s[0]:.3g}-{s[1]:.3g}")
def test_the_contact_patch_test_mortar_passes_and_node_to_segment_fails_on_non_matching_meshes(sizes):
    """Taylor and Papadopoulos's patch test: two blocks with non-matching meshes pressed by a uniform pressure p = 1
    (static, frictionless). The mortar rows, with standard or dual (biorthogonal) multipliers, carry it across
    uniformly, every multiplier within 1e-6 of p; the
    one-pass node-to-segment rows do so only where the meshes match, and miss by more than 5% where they do not
    (the slave nodes cannot integrate the master's shape functions): why the bodies' rows are to be mortar's."""
    for method in ("mortar", "dual"):
        _, _, _, mortar = scipy_bodies.patch_test(sizes, method)
        assert np.abs(mortar - 1).max() <= 1e-6, method
    _, _, _, nodes = scipy_bodies.patch_test(sizes, "nts")
    miss = np.abs(nodes - 1).max()
    assert (miss > 0.05) if sizes in NON_MATCHING else (miss <= 1e-6), miss


def test_mortar_rows_keep_the_momentum_but_let_a_node_pass_the_surface():
    """The bars with mortar's rows: the momentum is conserved to round-off as with node to segment (the rows'
    coefficients sum to the same on both bodies), but the weighted gap does not hold the gap at each node: a node
    passes the other surface by 1.7e-5 here (0.2% of v0 2L/c), where node to segment keeps it to round-off."""
    h = bars((LENGTH, LENGTH), size=0.5, mu=MU, rho=RHO, v0=V0, T=2.5, dt=0.05, method="mortar")
    assert np.abs(h["momentum_x"]).max() <= 1e-12 * RHO * LENGTH * V0
    assert 1e-6 < h["max_penetration"].max() < 1e-4


def test_dual_mortar_rows_keep_the_momentum_and_the_nodes_gap():
    """The bars with dual mortar's rows (biorthogonal multipliers: the slave block is diagonal, so each row is its
    node's gap against the mortar projection of the other surface): momentum to round-off, and no node passes the
    other surface by more than 1e-9 (measured 1.1e-11; standard mortar 1.7e-5), with Prop. 2's E^{n+1} <= E^n."""
    h = bars((LENGTH, LENGTH), size=0.5, mu=MU, rho=RHO, v0=V0, T=2.5, dt=0.05, method="dual")
    assert np.abs(h["momentum_x"]).max() <= 1e-12 * RHO * LENGTH * V0
    assert h["max_penetration"].max() <= 1e-9
    assert np.all(np.diff(h["energy"]) <= 1e-9 * h["energy"][0])
