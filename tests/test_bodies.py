"""Bodies that hit bodies (docs/bodies.md): a mesh of several bodies, the rows of the gap between them by dual
mortar inside the mid-point scheme (1)-(2), each step's QP (4) under them. Short runs of the two bars
(meshes/bars.geo: 10 x 1 each, lambda = 0, c = 10, v0 = +-0.01, h = 0.5, dt = 0.05)."""
import csv
import os
import sys

import numpy as np
import pytest

from conftest import ROOT, error_lines, refused_into_copy, restart_reproduces, run_scene

sys.path.insert(0, os.path.join(ROOT, "tests", "reference"))


def history(out):
    with open(os.path.join(out, "history.csv")) as f:
        rows = list(csv.DictReader(f))
    return {k: np.array([float(r[k]) if r[k] != "" else np.nan for r in rows]) for k in rows[0]}


@pytest.fixture(scope="module")
def bars(tmp_path_factory):
    out = tmp_path_factory.mktemp("bars") / "run"
    run_scene("bars", out, ["-progress", "0"])
    return history(out)


@pytest.fixture(scope="module")
def bars_1_2(tmp_path_factory):
    out = tmp_path_factory.mktemp("bars_1_2") / "run"
    run_scene("bars", out, ["-mesh", "meshes/bars_1_2.msh", "-v0x", "0.01,0", "-T", "4", "-progress", "0"], cwd=ROOT)
    return history(out)


def test_bars_conserve_momentum_to_round_off(bars):
    """No load, no foundation: the rows between bodies put equal and opposite forces on them (each row's coefficients
    sum to int phi_j n on both sides), so (1) summed over a translation keeps the total momentum: to 1e-12 of the
    bodies' momentum m v0 = 0.1, while each bar's own momentum turns over."""
    scale = 10 * 0.01
    for k in ("x", "y"):
        assert np.abs(bars[f"momentum_{k}"] - bars[f"momentum_{k}"][0]).max() <= 1e-12 * scale
    assert bars["body1_v1_mean"][0] == 0.01 and bars["body1_v1_mean"][-1] < -0.009
    assert bars["body_contact_nodes"].max() == 3 and bars["body_contact_force"].max() > 0


def test_the_snapshots_show_the_pressure_between_bodies(tmp_path):
    """A snapshot of several bodies carries body_pressure, each row's multiplier at its slave node: with dual
    multipliers a pressure, so over the touching end's three nodes, weighted by their dual functions' integrals (half
    of each adjacent end segment's length, deformed), it sums to history.csv's body_contact_force at that time, to
    1e-4 (the master end covers the slave end but for about 3e-5 of its length, deformed differently, and the dual
    functions integrate over the part covered)."""
    import meshio
    out = tmp_path / "snap"
    run_scene("bars", out, ["-snapshots", "1", "-T", "1", "-progress", "0"])
    vtu = meshio.read(out / "vonmises_t1.vtu")
    p = vtu.point_data["body_pressure"].ravel()
    pressed = np.nonzero(p > 0)[0]
    assert len(pressed) == 3 and np.abs(vtu.points[pressed, 0]).max() < 1e-9      # (the slave bar's end, at X1 = 0)
    pressed = pressed[np.argsort(vtu.points[pressed, 1])]
    x = vtu.points[pressed, :2] + vtu.point_data["displacement"][pressed, :2]
    half = np.hypot(*np.diff(x, axis=0).T) / 2                 # (the two end segments, deformed)
    weights = np.array([half[0], half[0] + half[1], half[1]])
    force = history(out)["body_contact_force"][-1]
    assert abs(weights @ p[pressed] - force) <= 1e-4 * force


def test_bars_energy_identity_and_prop_2(bars):
    """The mid-point identity E^{n+1} - E^n = lm . (C u^n - g) (rows_work; Prop. 2's proof), to round-off; rows_work
    <= 0 where u^n satisfies the rows the step ends with, and their linearisation about the result allows a rise of
    its order only: 1e-9 of E here. The energy the impact dissipates (constraint (10) at t_{n+1}) is small."""
    m, work = bars["modified_energy"], bars["rows_work"]
    assert np.abs(np.diff(m) - work[1:]).max() <= 1e-12 * m[0]
    assert work.max() <= 1e-9 * m[0]
    assert 0 <= m[0] - m[-1] <= 1e-7 * m[0]


def test_bars_gap_holds_at_every_node(bars):
    """The rows are linearised again about each result until they are its own (linearisations >= 2 on a contact
    step), so the true gap holds at the end of the step: no node of one bar inside the other beyond round-off."""
    assert bars["max_penetration_bodies"].max() <= 1e-10
    pressed = bars["body_contact_nodes"] > 0
    assert (bars["linearisations"][pressed] >= 2).all()


def test_bars_match_the_scipy_prototype(bars):
    """An independent implementation of the same discrete problem (tests/reference/scipy_bodies.py: numpy + scipy,
    the same mesh, dual mortar, the mid-point scheme) gives the same bodies' velocities and energy to 1e-9."""
    import scipy_bodies
    X, tris, boundary, node_body, _ = scipy_bodies.read_bodies(os.path.join(ROOT, "meshes", "bars.msh"), contact_label=2)
    ends = np.array([e for e in boundary if X[e[0], 0] == 0 and X[e[1], 0] == 0])      # (the touching ends only)
    h = scipy_bodies.run(X, tris, ends, node_body, 0.0, 50.0, 1.0, 0.01, 3.0, 0.05, method="dual")
    for b in (1, 2):
        assert np.abs(h[f"body{b}_v1_mean"] - bars[f"body{b}_v1_mean"][1:]).max() <= 1e-9 * 0.01
    assert np.abs(h["energy"] - bars["energy"][1:]).max() <= 1e-9 * bars["energy"][0]


def test_ipopt_agrees_with_the_active_set(bars, tmp_path):
    """-solver ipopt solves each step's QP under the same rows (in the same loop of linearisations): run with -tol
    1e-10 (its default 1e-8 itself moves the answer by about 1e-4 of v0 here), the bars' velocities agree with the
    exact active set's to 1e-5 of v0, and the energy to 1e-5 of E."""
    out = tmp_path / "ipopt"
    run_scene("bars", out, ["-solver", "ipopt", "-tol", "1e-10", "-progress", "0"])
    h = history(out)
    assert (h["qp_solved"] == bars["qp_solved"]).all()
    for b in (1, 2):
        assert np.abs(h[f"body{b}_v1_mean"] - bars[f"body{b}_v1_mean"]).max() <= 1e-5 * 0.01
    assert np.abs(h["energy"] - bars["energy"]).max() <= 1e-5 * bars["energy"][0]


def test_bars_of_two_materials_press_with_their_impedances(bars, tmp_path):
    """Per-body materials (-mu 50,200: c = 10 and 20, impedances Z = rho c = 10 and 20): until the stiffer bar's release
    wave returns (t = 2L/c_2 = 1), the force between them is Z1 Z2 / (Z1 + Z2) (2 v0) x height = 0.1333, the 1D wave
    solution; its mean over t in (0.2, 0.8) within 5% (h 0.5, dt 0.025), the momentum to 1e-12 of m v0. Lists of equal
    values give the scalars' history byte for byte (the P0 fields hold the same numbers)."""
    out = tmp_path / "materials"
    run_scene("bars", out, ["-mu", "50,200", "-dt", "0.025", "-progress", "0"])
    h = history(out)
    window = (h["t"] > 0.2) & (h["t"] < 0.8)
    assert abs(h["body_contact_force"][window].mean() - 0.4 / 3) <= 0.05 * 0.4 / 3
    assert np.abs(h["momentum_x"]).max() <= 1e-12 * 0.1
    same = tmp_path / "same"
    run_scene("bars", same, ["-mu", "50,50", "-rho", "1,1", "-lambda", "0,0", "-T", "0.5", "-progress", "0"])
    scalar = tmp_path / "scalar"
    run_scene("bars", scalar, ["-T", "0.5", "-progress", "0"])
    assert (same / "history.csv").read_bytes() == (scalar / "history.csv").read_bytes()


def test_the_short_bar_stops_and_the_long_one_carries_the_momentum(bars_1_2):
    """Bars L and 2L, the short one striking the long one at rest: after 2L/c = 2 the short bar is at rest and the long
    one carries all the momentum, m v0 = 0.1, so its mean velocity is v0 / 2, exactly; here within 2% of v0 (h = 0.5,
    dt = 0.05; docs/bodies.md)."""
    v0 = 0.01
    assert abs(bars_1_2["body1_v1_mean"][-1]) <= 0.02 * v0
    assert abs(bars_1_2["body2_v1_mean"][-1] - v0 / 2) <= 0.02 * v0 / 2
    assert np.abs(bars_1_2["momentum_x"] - 0.1).max() <= 1e-12 * 0.1


def test_bodies_that_never_meet_have_no_rows(tmp_path):
    """Two bars 2 apart and moving apart: the search finds no pair of facing segments within its distance at any step, the step is
    the free one (no rows, no QP), and each bar keeps its velocity; the audit of the run checks the energy identity
    with each body's own translation taken out of a(u, u) (a mesh without rows between bodies once crashed
    FreeFEM on its empty triplets)."""
    out = tmp_path / "apart"
    run_scene("bars", out, ["-u0x", "-1,1", "-v0x", "-0.01,0.01", "-T", "1", "-progress", "0"])
    h = history(out)
    assert h["body_contact_nodes"].max() == 0 and h["qp_solved"].max() == 0
    # (to (2)'s round-off: that of u, whose lift is 1, over dt = 0.05, over the steps)
    assert np.abs(h["body1_v1_mean"] + 0.01).max() <= 1e-13 and np.abs(h["body2_v1_mean"] - 0.01).max() <= 1e-13


def test_restart_of_a_disk_on_a_disk_is_bit_identical(tmp_path):
    """The disk falling onto the disk on the foundation (coarse), run to t = 11.5 (after the impact) and restarted to
    12.5, writes the history and checkpoint of one run to 12.5, byte for byte: the bodies' rows, the foundation's
    working set and the active set start from the checkpoint's u and v alone."""
    restart_reproduces("disk_on_disk", tmp_path, ["-mesh", os.path.join(ROOT, "meshes", "two_disks_coarse.msh"),
                                                  "-progress", "0", "-checkpoint_every", "10"], 11.5, 12.5)


@pytest.fixture(scope="module")
def two_disks(tmp_path_factory):
    out = tmp_path_factory.mktemp("two_disks") / "run"
    run_scene("two_disks", out, ["-mesh", "meshes/two_disks_coarse.msh", "-T", "5", "-progress", "0"], cwd=ROOT)
    return history(out)


@pytest.fixture(scope="module")
def disk_on_disk(tmp_path_factory):
    out = tmp_path_factory.mktemp("disk_on_disk") / "run"
    run_scene("disk_on_disk", out, ["-mesh", "meshes/two_disks_coarse.msh", "-T", "13", "-progress", "0"], cwd=ROOT)
    return history(out)


def test_two_disks_head_on_conserve_momentum(two_disks):
    """Two of the paper's disks (coarse) meet head-on at +-0.5, curved surfaces whose rows change at every step: the
    total momentum stays 0 to 1e-12 of a disk's momentum m v0 (pi 20^2 x 0.5), each disk's velocity the other's
    reversed to the same round-off, and the energy identity holds (the audit of every run checks it)."""
    scale = np.pi * 400 * 0.5
    assert np.abs(two_disks["momentum_y"]).max() <= 1e-12 * scale
    assert np.abs(two_disks["body1_v2_mean"] + two_disks["body2_v2_mean"]).max() <= 1e-12 * 0.5
    assert two_disks["body_contact_nodes"].max() >= 3 and two_disks["body1_v2_mean"][-1] < 0.45
    m = two_disks["modified_energy"]
    assert np.abs(np.diff(m) - two_disks["rows_work"][1:]).max() <= 1e-10 * m[0]


def test_a_disk_falls_onto_a_disk_on_the_foundation(disk_on_disk):
    """A disk touches the foundation and another disk at once: the lower disk presses the flat foundation from the
    start, the upper one lands on it near t = 11, and (10) holds on the foundation to round-off throughout (the
    audit checks the momentum of (1) against the foundation's force: the bodies' forces on each other cancel)."""
    h = disk_on_disk
    assert (h["active_nodes"][1:] > 0).all() and h["max_penetration"].max() <= 1e-10
    touching = np.nonzero(h["body_contact_nodes"] > 0)[0]
    assert len(touching) > 0 and 10 < h["t"][touching[0]] < 12
    k = touching[0]        # (the lower disk holds the upper one up: it falls slower than g from then on)
    assert h["body2_v2_mean"][-1] - h["body2_v2_mean"][k] > -0.1 * (h["t"][-1] - h["t"][k]) + 0.05
    assert h["body_contact_force"][-1] > 0


def test_a_stack_started_static_carries_the_weights(tmp_path):
    """Two stiff disks stacked on the flat foundation (coarse), started at rest in static contact (-initial static: K w
    = F - C' lm under the foundation's rows and those between the bodies, linearised again until they are the
    result's own, each body's slide along the floor and turn held). The step (4) from that state is its equilibrium,
    K u = F - C' lm: the floor carries both weights f |Omega_1| + f |Omega_2| to round-off (1e-12), and the lower disk
    the upper one's weight, to 1e-8: the force between them is reported as a magnitude, and the mesh's asymmetry
    leaves a tangential part, of the order of the holding force the start line reports (hold: 6e-5 of the load), whose
    square adds 3e-9. The bodies stay at rest but for the slide that force drives, 2 hold f T at most (the upper disk
    bears the whole load's 2 hold on its own weight)."""
    sys.path.insert(0, os.path.join(ROOT, "postprocess"))
    import audit
    out = tmp_path / "stack"
    p = run_scene("stack", out, ["-mesh", "meshes/two_disks_coarse.msh", "-progress", "0"], cwd=ROOT)
    held = [line for line in p.stdout.splitlines() if line.startswith("initial state: at rest in static contact")]
    hold = float(held[0].split("holding their slide and turn is ")[1].split()[0]) if held else 1
    assert hold < 1e-3
    areas = audit.mesh_measures(str(out))[3]
    lower, upper = (0.1 * areas[k] for k in sorted(areas))
    h = history(out)
    assert abs(h["contact_force_y"][1] - (lower + upper)) <= 1e-12 * (lower + upper)
    assert abs(h["body_contact_force"][1] - upper) <= 1e-8 * upper
    for k in ("body1_v1_mean", "body1_v2_mean", "body2_v1_mean", "body2_v2_mean"):
        assert np.abs(h[k]).max() <= 3 * hold * 0.1 * 2
    assert h["max_penetration_bodies"].max() <= 1e-12 and h["max_penetration"].max() <= 1e-12


def test_a_disk_dropped_on_a_clamped_slab(tmp_path):
    """A foundation that deforms (slab: meshes/slab.geo, the paper's disk, coarse, 0.5 above a stiff slab 80 x 10
    clamped at its ends, Gamma_D; no rigid foundation). Until it touches the sagging slab (near t = 4.15) the disk falls
    freely, its mean acceleration f / rho = -0.1 to 1e-12 (the mid-point scheme is exact on a translation under a
    constant load); from then on the slab's rows hold it (a force between the bodies; at T = 6 it falls at 0.533, not
    the free 0.6), with nodes overlapping by less than 1e-3 (the curved disk's h^2 / 8R bounds it)."""
    out = tmp_path / "slab"
    run_scene("slab", out, ["-u0y", "0.5,0", "-T", "6", "-progress", "0"])
    h = history(out)
    touching = np.nonzero(h["body_contact_nodes"] > 0)[0]
    assert len(touching) > 0 and 4 < h["t"][touching[0]] < 4.5
    k = touching[0]
    a = np.diff(h["body1_v2_mean"]) / (h["t"][1] - h["t"][0])
    assert np.abs(a[:k - 1] + 0.1).max() <= 1e-12 and h["body1_v2_mean"][-1] > -0.6 + 0.05
    assert h["body_contact_force"][k:].min() > 0 and h["max_penetration_bodies"].max() < 1e-3


def test_neohookean_disks_collide_through_their_newton_step(tmp_path):
    """-material neohookean with several bodies (solve/newton_bodies.idp): semi-smooth Newton on the mid-point step's
    complementarity problem, the rows between bodies built again about each iterate, each iteration's KKT system solved
    directly. Two of the paper's disks (coarse) head-on at 0.5 each to T = 3 (contact from t = 2): the total momentum
    stays 0 to 1e-12 of m v0 = 628 (measured 4e-14 over T = 12) and the discrete gradient's identity E^{n+1} - E^n =
    rows_work holds to 1e-10 of E (the audit's check, passed; measured 3e-12)."""
    out = tmp_path / "nh"
    run_scene("two_disks", out, ["-mesh", "meshes/two_disks_coarse.msh", "-material", "neohookean", "-solver", "newton",
                                 "-T", "3", "-progress", "0"], cwd=ROOT)
    h = history(out)
    assert h["body_contact_nodes"].max() >= 3 and h["newton_iterations"][1:].min() >= 1
    assert np.abs(h["momentum_y"] - h["momentum_y"][0]).max() <= 1e-12 * 628
    m = h["modified_energy"]
    assert np.abs(np.diff(m) - h["rows_work"][1:]).max() <= 1e-10 * m[0]
    assert h["max_penetration_bodies"].max() < 0.1


@pytest.mark.parametrize("mesh,lam", [("patch", 30), ("patch_fine", 30), ("patch", 0)])
def test_the_contact_patch_test(tmp_path, mesh, lam):
    """The contact patch test (Taylor and Papadopoulos 1991): two blocks 4 x 1 on the flat foundation, their meshes
    not matching along the interface (meshes/patch.geo: 9 against 7 segments; patch_fine: 18 against 14), pressed by
    p = 0.1 on the upper block's top (-traction), started in static contact. The exact stress is uniform, -p in X2,
    which P1 holds exactly: each dual mortar multiplier at the lower block's top nodes (the snapshot's body_pressure)
    is p, to 1e-6 (measured 1e-14), as a force per length of the deformed interface, p W0 / W (lambda = 30: Poisson's
    expansion widens the blocks by 4e-4; lambda = 0: none, p itself), and the floor's pressure at each node is p."""
    import meshio
    out = tmp_path / "patch"
    run_scene("patch", out, ["-mesh", f"meshes/{mesh}.msh", "-lambda", str(lam), "-snapshots", "0.5", "-progress", "0"],
              cwd=ROOT)
    vtu = meshio.read(out / "vonmises_t0.5.vtu")
    body, floor = vtu.point_data["body_pressure"].ravel(), vtu.point_data["contact_pressure"].ravel()
    top, base = np.nonzero(body)[0], np.nonzero(floor)[0]
    x = vtu.points[:, 0] + vtu.point_data["displacement"][:, 0]
    width = x[top].max() - x[top].min()
    assert len(top) == {"patch": 10, "patch_fine": 19}[mesh] and len(base) == len(top)
    assert np.abs(body[top] / (0.1 * 4 / width) - 1).max() <= 1e-6
    assert np.abs(floor[base] / 0.1 - 1).max() <= 1e-6
    assert (width - 4 > 1e-4) == (lam > 0)


def test_bodies_on_a_curved_foundation_keep_its_exact_gap(tmp_path):
    """-gap exact with several bodies (docs/sliding.md): the disk_on_disk pair (coarse) in the bowl (R = 60), the lower
    disk resting at its bottom. The foundation's rows are linearised about u^n, then about each result of the step
    with the rows between bodies (each such step settling those first) until the exact gap holds: no contact node
    below the true psi beyond 1e-10 of the body's size (the linearised (10) leaves 9e-4 by T = 14)."""
    out = tmp_path / "bowl"
    run_scene("disk_on_disk", out, ["-mesh", "meshes/two_disks_coarse.msh", "-foundation", "bowl", "-gap", "exact",
                                    "-T", "3", "-progress", "0"], cwd=ROOT)
    h = history(out)
    assert h["active_nodes"][1:].min() > 0 and h["max_penetration_exact"].max() <= 1e-10 * 40
    summary = dict(line.split(None, 1) for line in open(out / "summary.txt") if line.strip())
    assert int(summary["exact_gap_rounds"]) > 0


def test_a_cradle_of_three_disks_passes_the_momentum_along(tmp_path):
    """Three disks in a row (meshes/cradle.geo, coarse), the first struck at 0.1 towards the others: the middle disk
    is a master to the first and a slave to the third, and each pair's forces cancel, so the total momentum stays
    m v0 to 1e-12; after t = 1.5 the last disk carries it nearly whole (0.98 v0) and the first nearly stops."""
    out = tmp_path / "cradle"
    run_scene("cradle", out, ["-mesh", "meshes/cradle_coarse.msh", "-T", "1.5", "-progress", "0"], cwd=ROOT)
    h = history(out)
    p0 = h["momentum_x"][0]
    assert np.abs(h["momentum_x"] - p0).max() <= 1e-12 * p0
    assert h["body3_v1_mean"][-1] > 0.95 * 0.1 and abs(h["body1_v1_mean"][-1]) < 0.1 * 0.1
    assert h["body_contact_nodes"].max() >= 4


def test_oblique_disks_in_gross_slip_take_f_times_the_normal_impulse(tmp_path):
    """Coulomb's friction between bodies (F = 0.3): two stiff disks (coarse) meet obliquely, sliding fast enough to slip
    throughout (no row ever sticks). The impulse on the lower disk, its momentum's change resolved step by step along
    the line of centres and across it, has its tangential part F times its normal part, within 1% (measured 0.30001);
    the friction work grows and E^{n+1} - E^n = rows_work - (D^{n+1} - D^n), to round-off."""
    out = tmp_path / "oblique"
    run_scene("oblique_disks", out, ["-mesh", "meshes/two_disks_coarse.msh", "-progress", "0"], cwd=ROOT)
    h = history(out)
    assert h["body_stick_nodes"].max() == 0 and h["body_slip_nodes"].max() > 0
    c1 = np.stack([h["body1_u1_mean"], 20 + h["body1_u2_mean"]])
    c2 = np.stack([h["body2_u1_mean"], 62 + h["body2_u2_mean"]])
    n = (c2 - c1) / np.hypot(*(c2 - c1))
    n = (n[:, 1:] + n[:, :-1]) / 2                       # (the line of centres over each step)
    dv = np.diff(np.stack([h["body1_v1_mean"], h["body1_v2_mean"]]), axis=1)
    normal, tangential = (dv * n).sum(), (dv * np.stack([-n[1], n[0]])).sum()
    assert abs(abs(tangential / normal) - 0.3) <= 0.01 * 0.3
    D = h["body_friction_work"]
    assert np.diff(D).min() >= 0 and D[-1] > 0
    m = h["modified_energy"]
    assert np.abs(np.diff(m) - h["rows_work"][1:] + np.diff(D)).max() <= 1e-10 * abs(m[0])


def test_friction_between_bodies_under_ipopt_agrees_with_the_active_set(tmp_path):
    """-solver ipopt with Coulomb's friction between bodies: with the bounds fixed the step is a smooth convex program
    (the slip's modulus as a slack), and Coulomb's bounds F lm_N come by a fixed point of such programs to IPOPT's -tol.
    The oblique disks (coarse) to T = 2.2, four steps in gross slip: at -tol 1e-10 the bodies' mean velocities agree
    with the exact active set's to 1e-10 of their 1.5 (measured 4e-13), and so does the friction work."""
    runs = {}
    for solver in ("activeset", "ipopt"):
        out = tmp_path / solver
        run_scene("oblique_disks", out, ["-mesh", "meshes/two_disks_coarse.msh", "-solver", solver, "-tol", "1e-10",
                                         "-T", "2.2", "-progress", "0"], cwd=ROOT)
        runs[solver] = history(out)
    a, b = runs["activeset"], runs["ipopt"]
    assert a["body_slip_nodes"].max() > 0 and (b["body_slip_nodes"] == a["body_slip_nodes"]).all()
    for k in ("body1_v1_mean", "body1_v2_mean", "body2_v1_mean", "body2_v2_mean"):
        assert np.abs(a[k] - b[k]).max() <= 1e-10 * 1.5
    assert abs(a["body_friction_work"][-1] - b["body_friction_work"][-1]) <= 1e-9 * a["body_friction_work"][-1]


def test_restart_with_friction_between_bodies_is_bit_identical(tmp_path):
    """The oblique disks (coarse) run to t = 2.3, mid-contact, and restarted to 2.5 write the history and checkpoint of
    one run to 2.5, byte for byte: the checkpoint keeps the friction work."""
    restart_reproduces("oblique_disks", tmp_path, ["-mesh", os.path.join(ROOT, "meshes", "two_disks_coarse.msh"),
                                                   "-progress", "0", "-checkpoint_every", "5"], 2.3, 2.5)


REFUSED = {
    "a list of the wrong length": ("bars", ["-v0x", "0.01,-0.01,0"],
                                   "-v0x 0.01,-0.01,0 gives 3 values, and -mesh meshes/bars.msh holds 2 bodies"),
    "a list on a mesh of one body": ("test1", ["-v0x", "0.1,0.2"], "-v0x 0.1,0.2 gives 2 values, and -mesh "),
    "an empty value in a list": ("bars", ["-v0x", "0.01,"], "-v0x 0.01, has an empty value"),
    "a value that is not a number": ("bars", ["-v0x", "0.01,x"], "-v0x must be a number, got 'x'"),
    "a body's mu not positive": ("bars", ["-mu", "50,-1"], "-mu must be > 0 (body 2), got -1"),
    "a body's lambda + mu not positive": ("bars", ["-lambda", "0,-60"], "-lambda must be > -mu (lambda + mu > 0) (body 2)"),
    "friction between bodies and a foundation": ("disk_on_disk", ["-mesh", "meshes/two_disks_coarse.msh", "-friction",
                                                 "coulomb", "-friction_coefficient", "0.2"], "and a foundation yet"),
    "Tresca between bodies without its bound": ("oblique_disks", ["-mesh", "meshes/two_disks_coarse.msh", "-friction",
                                                "tresca"], "-friction tresca needs -friction_bound g > 0"),
    "several bodies under Newmark": ("bars", ["-scheme", "newmark"], "with -scheme newmark: it is the mid-point"),
    "a list of materials with a Newton body": ("bars", ["-material", "svk", "-solver", "newton", "-mu", "50,200"],
                                               "with -material svk and a list of -lambda, -mu or -rho yet"),
    "a Newton body started static": ("stack", ["-mesh", "meshes/two_disks_coarse.msh", "-material", "neohookean",
                                               "-solver", "newton"], "with -material neohookean and -initial static yet"),
    "several bodies with P2": ("bars", ["-order", "2"], "with -order 2 yet"),
    "several bodies on two processes": ("bars", ["-np", "2"], "holds 2 bodies, and contact between bodies is not "
                                        "available on 2 processes: run it on one"),
}


@pytest.mark.parametrize("case", list(REFUSED))
def test_refusals_of_several_bodies(tmp_path, earlier_run, case):
    """What contact between bodies is not built for, and a per-body list that does not fit the mesh, are refused in
    one line, exit 3, before anything of the earlier run changes."""
    scene, args, message = REFUSED[case]
    p, changed = refused_into_copy(tmp_path, earlier_run, scene, args + ["-T", "0.1"], cwd=ROOT)
    errors = error_lines(p)
    assert p.returncode == 3 and len(errors) == 1 and message in errors[0], p.stderr
    assert not changed


def test_two_3d_bodies_are_refused(tmp_path, earlier_run):
    """Two cubes, one above the other, each its own Physical Volume: contact between 3D bodies is not built yet, and
    the run says so in one line, exit 3, before anything of the earlier run changes."""
    import subprocess
    geo = tmp_path / "cubes.geo"
    geo.write_text('SetFactory("OpenCASCADE");Geometry.AutoCoherence=0;Box(1)={0,0,0,1,1,1};Box(2)={0,0,1.5,1,1,1};'
                   "Physical Volume(1)={1};Physical Volume(2)={2};Physical Surface(1)={1:12};Mesh.MeshSizeMax=0.5;\n")
    subprocess.run(["gmsh", "-3", "-format", "msh22", str(geo), "-o", str(tmp_path / "cubes.msh")], check=True,
                   capture_output=True)
    p, changed = refused_into_copy(tmp_path, earlier_run, "ball", ["-mesh", str(tmp_path / "cubes.msh"), "-T", "0.1"])
    errors = error_lines(p)
    assert p.returncode == 3 and len(errors) == 1 and "holds 2 bodies" in errors[0] and "in 3D yet" in errors[0], p.stderr
    assert not changed

