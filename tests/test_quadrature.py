"""-contact_quadrature gauss (docs/methods.md): penalty and Nitsche with their contact term integrated
on Gauss-Legendre points of the edges of Gamma_C (2 per edge at P1, 3 at P2) in place of the edges' end
nodes (the vertex rule, the default). Each test names the property and the equation behind it. That
the vertex rule is unchanged, byte for byte, is the golden tests' (test_golden.py, test_methods.py):
they pass with the files they had before the option existed."""
import os

import numpy as np
import pytest

from conftest import NITSCHE_GAMMA0_GAUSS, PENALTY_EPS, ROOT, refused_into_copy, run_scene
from history import contact_intervals, read_csv, read_freefem_mesh, read_run
from test_methods import assert_near_the_getfem_reference, penetration

GAUSS = ["-contact_quadrature", "gauss"]
QUIET = ["-progress", "0", "-snapshots", "none", "-vtk", "0"]


def stdout_of(runs, name):
    with open(f"{runs[name]}.stdout") as f:
        return f.read()


def mesh_area(run_dir):
    xy, tri = read_freefem_mesh(os.path.join(run_dir, "mesh.msh"))
    a = xy[tri]
    return 0.5 * np.abs((a[:, 1, 0] - a[:, 0, 0]) * (a[:, 2, 1] - a[:, 0, 1])
                        - (a[:, 2, 0] - a[:, 0, 0]) * (a[:, 1, 1] - a[:, 0, 1])).sum()


def test_vertex_is_the_default_and_the_rule_is_recorded(runs):
    """parameters.txt records the rule (a restart may not change it: test_restart_of_a_gauss_run_...)."""
    for name, rule in (("methods_penalty", "vertex"), ("nitsche_theta1", "vertex"), ("penalty_gauss", "gauss")):
        with open(os.path.join(runs[name], "parameters.txt")) as f:
            assert f"\n-contact_quadrature {rule}\n" in f.read(), name


def test_the_point_penalty_on_the_vertex_rule_is_the_schur_penalty(tmp_path, histories):
    """The gauss penalty is Nitsche's point machinery with U = the rows of (10) at the points, gamma =
    1/eps, S = 0: N(x) = U' diag(omega / eps) [U x - g]_+. On the vertex rule (a test hook routes the
    vertex penalty through it) that is contact/penalty.idp's A x + C' kappa [C x - g]_+ = L with
    kappa_j = w_j / eps, solved there on the Schur complement: the same run to round-off (measured
    4e-13 in u, 3e-12 relative in the multipliers), multipliers included (lm_j = sum_q omega_q [.]_+q / eps)."""
    out = tmp_path / "hook"
    run_scene("test1", out, ["-contact", "penalty", "-penalty_eps", "1e-3", "-T", "30"] + QUIET,
              env={"CONTACT_TEST_PENALTY_ON_POINTS": "1"})
    h, ref = read_run(str(out)), histories["methods_penalty"]
    assert np.abs(h["u2_low"] - ref["u2_low"]).max() < 1e-10
    for col in ("contact_pressure_low", "contact_force_y", "energy"):
        assert np.abs(h[col] - ref[col]).max() < 1e-10 * np.abs(ref[col]).max(), col
    assert (h["active_nodes"] == ref["active_nodes"]).all()


def assert_cauchy_first_order(histories, prefix, parameters):
    """Runs prefix_<p> of the resting disk, p one decade apart towards the limit: the differences in u
    between neighbours, and the penetration at the end (t = 10, the contact zone wide), fall 8 to 12x
    per decade. (The limit is (10) at the Gauss points, not at the nodes, so the runs are compared with
    each other, not with the constraint's run.)"""
    hs = [histories[f"{prefix}_{p}"] for p in parameters]
    diff = [max(np.abs(a["u2_low"] - b["u2_low"]).max(), np.abs(a["u2_probe0"] - b["u2_probe0"]).max())
            for a, b in zip(hs, hs[1:])]
    end = [h["max_penetration"][-1] for h in hs]
    for k in range(len(diff) - 1):
        assert 8 < diff[k] / diff[k + 1] < 12, f"{prefix}: differences {diff}"
    for k in range(len(end) - 1):
        assert 8 < end[k] / end[k + 1] < 12, f"{prefix}: penetration at the end {end}"


def test_gauss_penalty_tends_to_its_constraint_at_first_order_in_eps(histories):
    """Phi(u) = sum_q omega_q / (2 eps) [G_q u - g_q]_+^2: as eps -> 0 the step tends, at first order, to
    the QP (4) under (10) imposed at the Gauss points (measured 9.7x per decade in u, 9.7x and 10.0x in
    the end penetration, eps = 1e-2, 1e-3, 1e-4)."""
    assert_cauchy_first_order(histories, "rest_penalty_gauss", PENALTY_EPS)


def test_gauss_nitsche_tends_to_its_constraint_as_gamma0_grows(histories):
    """gamma = gamma0 / h -> infinity: Nitsche on Gauss points tends like 1 / gamma0 to (10) at the Gauss
    points (measured from gamma0 = 1e4: 10.1x per decade in u, 9.8x and 9.4x in the end penetration;
    between 1e3 and 1e4 only 6.3x, not yet asymptotic). That limit lets a node dip below the foundation
    between the points: while the contact zone is a couple of edges wide (t = 0.3) the lowest vertex,
    a corner of the polygonal boundary below the Gauss points of its two edges, is 0.0039 below the
    foundation for every gamma0 >= 1e4 (and eps <= 1e-4); the vertex rule has no such floor."""
    assert_cauchy_first_order(histories, "rest_nitsche_gauss", NITSCHE_GAMMA0_GAUSS)
    floor = [penetration(histories[f"rest_nitsche_gauss_{g}"]) for g in NITSCHE_GAMMA0_GAUSS]
    assert 0.0035 < floor[-1] < 0.0045 and abs(floor[-1] - floor[-2]) < 0.01 * floor[-1], floor
    assert penetration(histories["rest_nitsche_1e5"]) < 1e-4


@pytest.mark.parametrize("name,gamma", [
    ("rest_penalty_gauss_1e-3", None), ("rest_nitsche_gauss_1e5", None),
    ("nitsche_gauss_incline", None), ("penalty_gauss_test2", None), ("penalty_gauss_p2", None),
    ("verlet_penalty_gauss", 0.5), ("newmark_gauss_incline", 0.6)])
def test_contact_force_y_is_the_vertical_contact_force(histories, runs, name, gamma):
    """lm_j = sum_q phi_j(q) (omega [P]_+ / sqrt(1 + psi'^2))_q, so sum_j lm_j (contact_force_y) is the
    vertical contact force on the body on any foundation: the y-momentum of each step balances it,
    M (v^{n+1} - v^n) . e_y / dt = F_y + contact_force_y^{n+1} (mid-point, (1)-(2) with K e_y = 0),
    F_y + (1 - gamma) Fc^n + gamma Fc^{n+1} (Newmark, its acceleration M^-1 (F - K u - N(u)); Verlet:
    gamma = 1/2), to round-off. At rest (v constant) it is the weight. On the incline (psi' = tan 10
    deg) the force is along the plane's normal: its x-component is -psi' times its y-component."""
    h = histories[name]
    mass = mesh_area(runs[name])                       # rho = 1
    dt = h["t"][1] - h["t"][0]
    force = h["contact_force_y"]
    if gamma is not None:
        force = (1 - gamma) * force[:-1] + gamma * force[1:]
    else:
        force = force[1:]
    balance = mass * np.diff(h["v2_mean"]) / dt - (-0.1 * mass + force)
    assert h["active_nodes"].max() > 0
    assert np.abs(balance).max() < 1e-9 * mass * 0.1, np.abs(balance).max()
    if "incline" in name:
        slope = np.tan(10 * np.pi / 180)
        balance_x = mass * np.diff(h["v1_mean"]) / dt - (-slope * force)
        assert np.abs(balance_x).max() < 1e-9 * mass * 0.1, np.abs(balance_x).max()


def test_gauss_penalty_does_not_create_energy_over_an_impact(histories):
    """With f = 0 on the fixed foundation the step dissipates E + Phi (Phi = sum_q omega_q / (2 eps)
    [G_q x - g_q]_+^2 is convex and evaluated at t_{n+1}, as the constraint of Prop. 2): out of
    contact Phi = 0, so the energy after the rebound is at most the energy before the impact."""
    h = histories["f0_penalty_gauss"]
    contact = np.flatnonzero(h["active_nodes"] > 0)
    before, after = h["energy"][contact[0] - 1], h["energy"][contact[-1] + 1:]
    assert len(after) > 10 and (after <= before * (1 + 1e-12)).all()
    assert np.abs(np.diff(after)).max() < 1e-10 * before


def test_gauss_nitsche_first_impact_and_no_energy_gain(histories, runs):
    """theta = 1, gamma0 = 1000 on Gauss points keeps the first impact of Test 1 ([8.95, 23.9], as the
    constraint) with a penetration of a few 1e-3, and no step raises the modified energy above its start.
    Its trace constant C (sum omega h sigma_nu(z)^2 <= C z'K z) is computed on its own points: on the
    flat foundation the same 120.78386 as the vertex rule's (sigma_nu is the triangle's at both rules'
    points, with the same weights h/2), on Test 2's curved one at t = 0 119.68753 (vertex: 119.68733)."""
    h = histories["nitsche_gauss_theta1"]
    start, end = contact_intervals(h["t"], h["active_nodes"] > 0)[0]
    assert abs(start - 8.95) < 0.06 and abs(end - 23.9) < 0.11, (start, end)
    assert 1e-3 < penetration(h) < 0.01
    m = h["modified_energy"]
    assert m.max() <= m[0] * (1 + 1e-12)
    assert "theta = 1 is well posed, and keeps its augmented energy bounded, for -nitsche_gamma0 above C = 120.78386" in stdout_of(runs, "nitsche_gauss_theta1")
    assert "theta = 1 is well posed, and keeps its augmented energy bounded, for -nitsche_gamma0 above C = 119.68753" in stdout_of(runs, "nitsche_gauss_test2")


@pytest.mark.parametrize("vertex,gauss,most,interval", [
    ("methods_penalty", "penalty_gauss", 0.01, 0.06),
    ("nitsche_theta1", "nitsche_gauss_theta1", 0.01, 0.06),
    ("verlet_penalty", "verlet_penalty_gauss", 0.06, 0.2),
    ("verlet_nitsche", "verlet_nitsche_gauss", 0.06, 0.2),
    ("methods_penalty_test2", "penalty_gauss_test2", 0.01, 0.06),
    ("nitsche_incline", "nitsche_gauss_incline", 0.01, None),
    ("penalty_p2", "penalty_gauss_p2", 0.01, 0.06),
    ("cantilever_penalty", "cantilever_penalty_gauss", 0.01, 0.06),
])
def test_gauss_and_vertex_differ_but_agree_to_engineering_accuracy(histories, vertex, gauss, most, interval):
    """The option is not a no-op: u2 at the reference point (the cantilever: its tip) differs from the
    vertex rule's by more than 1e-3; and the two rules solve the same physics: by less than `most`
    (against u2's range of 4), the first contact interval the same within `interval`. Measured max
    |du2| to T = 30 (Test 1, 2), 14 (P2), 10 (incline, cantilever): mid-point penalty 0.0041, Nitsche
    0.0046, Test 2 penalty 0.0033, incline Nitsche 0.0027, P2 penalty 0.0041, cantilever 0.0027;
    explicit Verlet penalty 0.031, Nitsche 0.037, whose first impact ends at 23.75 against the vertex
    rule's 23.94 (GetFEM's: 23.83), the mid-point ones within one or two steps."""
    a, b = histories[vertex], histories[gauss]
    col = "u2_probe1" if "cantilever" in vertex else "u2_low"
    diff = np.abs(a[col] - b[col]).max()
    assert 1e-3 < diff < most, diff
    if interval is not None:                          # (the incline's disk starts touching)
        ia, ib = (contact_intervals(h["t"], h["active_nodes"] > 0)[0] for h in (a, b))
        assert abs(ia[0] - ib[0]) <= interval and abs(ia[1] - ib[1]) <= interval, (ia, ib)
    assert np.isfinite(b[col]).all() and b["active_nodes"].max() > 0
    if "cantilever" in vertex:
        assert np.abs(b["u2_probe0"]).max() == 0     # Gamma_D clamped (eq. (2))


@pytest.mark.parametrize("contact,critical,bound", [("nitsche", "0.027389", 0.2), ("penalty", "0.0251218", 0.25)])
def test_verlet_gauss_is_near_the_getfem_reference(histories, runs, contact, critical, bound):
    """Explicit Verlet with the contact force on Gauss points, dt = 0.01 ([3]'s scheme; the GetFEM
    reference integrates its Nitsche brick with a composite Gauss rule): its critical step is computed
    with the gauss contact stiffness (P'WP - S'WS, penalty U' diag(omega/eps) U: larger than the vertex
    rule's 0.0196 and 0.0207, whose stiffness sits on single nodes), and the run is as near the
    reference as the vertex rule's: first contact within 0.15, u2_low within the vertex tests' bound,
    the energy within 1.5%. The rule does not bring the curves nearer (the mesh and code differ):
    max |u2_low - reference| on the first impact (t <= 24) Nitsche vertex 0.039, gauss 0.043, penalty
    vertex 0.053, gauss 0.060; to t = 30, where the rebound's phase dominates, 0.124-0.128 for all four;
    the impact ends at 23.94, 23.75, 23.93, 23.89 (GetFEM: 23.83)."""
    name = f"verlet_{contact}_gauss"
    assert f"note: -scheme verlet: critical step {critical}, -dt 0.01" in stdout_of(runs, name)
    assert_near_the_getfem_reference(histories[name], bound)
    m = histories[name]["modified_energy"]
    assert np.abs(m - m[0]).max() < 0.015 * m[0]


def test_verlet_critical_step_uses_the_gauss_contact_stiffness(tmp_path, earlier_run):
    """dt = 0.024 is above the vertex penalty's critical step (0.0207) and below the gauss penalty's
    (0.0251): refused with one line for the one, run (95.5% of it) for the other."""
    args = ["-scheme", "verlet", "-contact", "penalty", "-dt", "0.024", "-T", "0.48"] + QUIET
    p, changed = refused_into_copy(tmp_path, earlier_run, "test1", args)
    assert p.returncode == 3 and "is above the critical step 0.0206" in p.stderr and not changed, p.stderr
    p = run_scene("test1", tmp_path / "gauss", args + GAUSS)
    assert "critical step 0.0251218, -dt 0.024 is 95.5% of it" in p.stdout


@pytest.mark.parametrize("scene,opts,horizons", [
    ("test2", ["-contact", "penalty"], ("12.5", "14")),
    ("incline", ["-scheme", "newmark", "-newmark_gamma", "0.6", "-newmark_beta", "0.3025", "-contact", "nitsche"], ("5", "6")),
    ("test1", ["-scheme", "verlet", "-contact", "nitsche", "-dt", "0.01"], ("10", "10.5")),
], ids=["penalty-moving", "newmark-nitsche-sloped", "verlet-nitsche"])
def test_restart_of_a_gauss_run_is_byte_identical(tmp_path, scene, opts, horizons):
    """A restart from a checkpoint during contact gives the uninterrupted run's rows, byte for byte: the
    Gauss points' foundation (moving), the points' active set (restarted from the nodes' active set,
    it settles to the same one), and Newmark's acceleration recomputed from N(u^n) on a slope. The
    rule is recorded and may not change on a restart."""
    opts = opts + GAUSS + ["-snapshots", "none", "-progress", "0", "-checkpoint_every", "50"]
    stop, end = horizons
    run_scene(scene, tmp_path / "full", opts + ["-T", end])
    run_scene(scene, tmp_path / "part", opts + ["-T", stop])
    p = run_scene(scene, tmp_path / "part", ["-restart", str(tmp_path / "part"), "-T", end, "-contact_quadrature", "vertex"],
                  check=False)
    assert p.returncode == 3 and "-contact_quadrature vertex differs from the run's -contact_quadrature gauss" in p.stderr
    run_scene(scene, tmp_path / "part", ["-restart", str(tmp_path / "part"), "-T", end])
    assert (tmp_path / "full" / "history.csv").read_bytes() == (tmp_path / "part" / "history.csv").read_bytes()


def test_an_unknown_rule_is_refused_and_an_unused_one_is_a_warning(tmp_path, earlier_run):
    """-contact_quadrature is vertex or gauss (exit 3, one line naming it, nothing changed); with the
    constraint (imposed at the nodes) or without a foundation it has no effect, and says so."""
    p, changed = refused_into_copy(tmp_path, earlier_run, "test1", ["-contact", "penalty", "-contact_quadrature", "simpson",
                                                                    "-T", "1"] + QUIET)
    lines = [line for line in p.stderr.splitlines() if line.strip()]
    assert p.returncode == 3 and len(lines) == 1 and not changed, p.stderr
    assert "-contact_quadrature must be vertex or gauss; got 'simpson'" in lines[0]
    for args, why in ((["-solver", "activeset"], "it applies to -contact penalty and nitsche"),
                      (["-contact", "penalty", "-foundation", "none"], "this run has no foundation (-foundation none), so nothing touches Gamma_C")):
        p = run_scene("test1", tmp_path / "warn", args + GAUSS + ["-T", "0.1", "-progress", "0", "-snapshots", "none"])
        warnings = [line for line in p.stderr.splitlines() if line.startswith("warning: -contact_quadrature")]
        assert len(warnings) == 1 and warnings[0].startswith(f"warning: -contact_quadrature has no effect: {why}"), p.stderr
