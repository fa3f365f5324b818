"""Any body, any mesh: a clamped boundary Gamma_D (eq. (2)), the scenes beyond the disk,
P2 elements, the Turek-Hron CSM3 benchmark, and the bad input of a general geometry.
Each test states the property it checks and the equation of the paper behind it."""
import os
import shutil
import subprocess

import numpy as np
import pytest

from conftest import ROOT, error_lines, refused_into_copy, run_scene
from driver import freefem_env
from golden import compare
from history import read_parameters, read_run, read_summary


def first_contact(h):
    return int(np.argmax(h["active_nodes"] > 0))


@pytest.mark.parametrize("name", ["cantilever_activeset", "cantilever_ipopt", "cantilever_svk", "cantilever_p2"])
def test_clamped_end_stays_fixed_and_the_free_end_strikes(histories, name):
    """Eq. (2), u = 0 on Gamma_D, at every step and for every solver and material: probe 0
    is the clamped end's midpoint (0, 1.5), exactly 0. The free end strikes the foundation
    (contact within T = 10), with (10) kept (no penetration) and alpha >= 0 (eq. (6))."""
    h = histories[name]
    assert np.abs(h["u1_probe0"]).max() == 0 and np.abs(h["u2_probe0"]).max() == 0
    k = first_contact(h)
    assert k > 0 and 4 < h["t"][k] < 5, f"{name}: first contact at t = {h['t'][k]}"
    assert h["max_penetration"].max() <= 1e-9
    assert h["contact_force_y"].min() >= -1e-9
    assert h["u2_probe1"].min() < -1, "the free end's midpoint must come down more than the gap (1)"


@pytest.mark.parametrize("name", ["cantilever_activeset", "cantilever_ipopt", "cantilever_p2"])
def test_clamped_beam_energy_identity(histories, name):
    """Prop. 2 with Gamma_D: the reaction on Gamma_D does no work (u = 0 there), so the
    mid-point scheme conserves E - (f, u) exactly while no node touches, and contact can
    only dissipate it on a fixed foundation."""
    h = histories[name]
    E = h["modified_energy"]
    k = first_contact(h)
    scale = np.abs(h["energy"]).max()
    assert np.abs(E[:k] - E[0]).max() <= 1e-9 * scale, f"{name}: drift before contact"
    rise = np.diff(E).max()
    assert rise <= 1e-6 * scale, f"{name}: E - (f, u) rose by {rise:.3g}"


def test_clamped_beam_solvers_agree(histories):
    """IPOPT and the active-set solver solve the same QP (4) with Gamma_D eliminated; SVK
    and linear stay within 15% of the free end's deflection of each other in this
    moderate-rotation impact (measured: 0.096 of about 1.06)."""
    a, b, s = histories["cantilever_activeset"], histories["cantilever_ipopt"], histories["cantilever_svk"]
    assert np.abs(a["u2_probe1"] - b["u2_probe1"]).max() <= 1e-5
    assert np.abs(a["u2_probe1"] - s["u2_probe1"]).max() <= 0.15 * np.abs(a["u2_probe1"]).max()


@pytest.mark.parametrize("name,order", [("cantilever_activeset", []), ("cantilever_p2", ["-order", "2"])])
def test_clamped_restart_reproduces_the_run(tmp_path, histories, name, order):
    """A restart of a clamped body, P1 or P2, continues the same discrete problem: the rows
    after the checkpoint equal the uninterrupted run's (T = 10). The restart is given no
    -order: edp/run.sh takes it from the run's parameters.txt."""
    first = tmp_path / "first"
    run_scene("cantilever", first, ["-T", "6", "-solver", "activeset", "-probes", "0,1.5,10,1.5", "-checkpoint_every", "40",
                                    "-snapshots", "5", "-progress", "0", "-vtk", "0"] + order)
    run_scene("cantilever", first, ["-restart", str(first), "-T", "10", "-progress", "0"])
    restarted, whole = read_run(str(first)), histories[name]
    for column in ("u2_low", "u2_probe1", "energy", "contact_force_y"):
        assert np.array_equal(restarted[column], whole[column]), column


def test_ring_models_part_ways(histories):
    """A thin ring flattens on impact (large deflection): the linear and St Venant-Kirchhoff
    rings (Section 3) differ by more than 10% in the largest shortening of the vertical
    diameter (probe 0 is the top); both keep (10)."""
    lin, svk = histories["ring"], histories["ring_svk"]
    short = {k: (h["u2_probe0"] - h["u2_low"]).min() for k, h in (("linear", lin), ("svk", svk))}
    assert short["linear"] < -3 and short["svk"] < -3, short
    assert abs(short["svk"] - short["linear"]) > 0.1 * abs(short["linear"]), short
    for h in (lin, svk):
        assert h["max_penetration"].max() <= 1e-9


def rotation_degrees(h):
    """Rotation of the segment between probes 0 and 1 (7 apart, level at t = 0)."""
    return np.degrees(np.arctan2(h["u2_probe1"] - h["u2_probe0"], 7 + h["u1_probe1"] - h["u1_probe0"]))


@pytest.mark.parametrize("name", ["corner", "corner_svk"])
def test_corner_impact_turns_the_body(histories, name):
    """Off-centre impact: before contact the fall is a rigid translation (no rotation, to
    round-off); the contact force (10) acts left of the centre of mass, so the body turns
    clockwise. The foundation is flat and frictionless, so the contact force is vertical
    and the horizontal momentum stays 0."""
    h = histories[name]
    angle = rotation_degrees(h)
    k = first_contact(h)
    assert np.abs(angle[:k]).max() <= 1e-9
    assert angle[-1] < -20, f"{name}: turned {angle[-1]:.1f} degrees"
    assert np.abs(h["v1_mean"]).max() <= 1e-10
    assert h["max_penetration"].max() <= 1e-9


def test_corner_svk_turns_further_than_the_linear_body(histories):
    """A linear body cannot rotate far (eps of a rotation is not 0): its probes stop
    turning near 50 degrees, while the St Venant-Kirchhoff body tips over (> 90)."""
    assert rotation_degrees(histories["corner_svk"])[-1] < -90 < rotation_degrees(histories["corner"])[-1]


def test_p2_free_fall_contact_and_agreement_with_p1(histories):
    """P2 (-order 2): the fall before impact is exact (u2 = 4 - 0.05 t^2, the mid-point
    scheme integrates constant gravity exactly); (10) holds at every P2 node of Gamma_C;
    E - (f, u) is conserved before contact and never rises (Prop. 2); and P2 is more
    accurate than P1 on the same mesh: the top of the disk, through the first impact and
    the lift-off (T = 20), is at most half as far from P1 on the mesh refined once
    (measured: 0.079 against 0.243)."""
    p2, p1, fine = histories["p2_test1"], histories["p1_test1_probe"], histories["p1_fine_test1_probe"]
    t = p2["t"]
    k = first_contact(p2)
    assert np.abs(p2["u2_low"][:k] - (4 - 0.05 * t[:k] ** 2)).max() <= 1e-9
    assert p2["max_penetration"].max() <= 1e-9
    E = p2["modified_energy"]
    assert np.abs(E[:k] - E[0]).max() <= 1e-9 * np.abs(p2["energy"]).max()
    assert np.diff(E).max() <= 1e-6 * np.abs(p2["energy"]).max()
    p2_error = np.abs(p2["u2_probe0"] - fine["u2_probe0"]).max()
    p1_error = np.abs(p1["u2_probe0"] - fine["u2_probe0"]).max()
    assert 0 < p2_error <= 0.5 * p1_error, f"top of the disk against P1 refined: P2 {p2_error:.3g}, P1 {p1_error:.3g}"


def test_p2_every_solver_and_material(histories):
    """P2 for every solver and material on the coarse disk: IPOPT and the active-set solver
    give the same QP solution; SVK runs through the first impact keeping (10)."""
    a, b, s = histories["p2_coarse_activeset"], histories["p2_coarse_ipopt"], histories["p2_coarse_svk"]
    assert np.abs(a["u2_low"] - b["u2_low"]).max() <= 1e-5
    assert np.abs(a["energy"] - b["energy"]).max() <= 1.5e-4
    for h in (a, b, s):
        assert h["max_penetration"].max() <= 1e-9 and (h["active_nodes"] > 0).any()


def test_csm3_short_horizon(runs, histories):
    """Turek-Hron CSM3 (St Venant-Kirchhoff, P2, Gamma_D on the cylinder, gravity): to
    t = 0.5 against tests/golden/csm3_short.csv; the mid-point scheme of Section 3
    conserves E - (f, u) to the Newton tolerance (Simo-Tarnow); A is probe 0 and the
    reference point, and parameters.txt names it."""
    h = histories["csm3_short"]
    failures = compare(os.path.join(ROOT, "tests", "golden", "csm3_short.csv"), h)
    assert not failures, "\n".join(failures)
    E = h["modified_energy"]
    assert np.abs(E - E[0]).max() <= 1e-8 * np.abs(h["energy"]).max()
    assert np.array_equal(h["u2_probe0"], h["u2_low"])
    assert read_parameters(runs["csm3_short"])["-reference"] == "0.6,0.2"
    assert read_summary(runs["csm3_short"])["material"] == "svk"


@pytest.mark.parametrize("step,initial,fewer", [("csm3_short", "csm3_short_initial", 5),
                                                 ("cantilever_svk_step", "cantilever_svk", 1.2)])
def test_step_preconditioner_changes_only_the_linear_solves(runs, histories, step, initial, fewer):
    """-newton_precond step preconditions GMRES with the tangent at each step's start
    instead of A (the undeformed one): Newton still solves the same mid-point step of
    Section 3 (with (10) and Gamma_D on the cantilever) to -newton_tol 1e-10, so the
    histories agree to 1e-9 of each column's size; GMRES takes fewer iterations
    (measured: 2.97 against 32.2 per Newton iteration on CSM3, which swings far from
    its undeformed state; 3.64 against 5.72 on the cantilever, whose contact rows keep
    A's Schur complement)."""
    a, b = histories[step], histories[initial]
    for column in ("u1_low", "u2_low", "energy", "modified_energy", "u2_probe0", "contact_force_y"):
        scale = max(np.abs(b[column]).max(), np.abs(b["energy"]).max())   # (E - (f, u) and the force may be 0)
        assert np.abs(a[column] - b[column]).max() <= 1e-9 * scale, column
    sa, sb = read_summary(runs[step]), read_summary(runs[initial])
    per_newton = {name: int(s["gmres_iterations"]) / int(s["newton_iterations"]) for name, s in ((step, sa), (initial, sb))}
    assert per_newton[step] * fewer <= per_newton[initial], per_newton


def test_step_preconditioner_restart_reproduces_the_run(tmp_path, runs, histories):
    """-newton_precond step depends on u^n and v^n only, so a restart of CSM3 from a
    checkpoint continues the same run: the rows and the Newton and GMRES counts equal
    the uninterrupted run's (t = 0.5)."""
    first = tmp_path / "first"
    run_scene("csm3", first, ["-T", "0.25", "-checkpoint_every", "20", "-progress", "0"])
    run_scene("csm3", first, ["-restart", str(first), "-T", "0.5", "-progress", "0"])
    restarted, whole = read_run(str(first)), histories["csm3_short"]
    for column in ("u1_probe0", "u2_probe0", "energy", "newton_iterations"):
        assert np.array_equal(restarted[column], whole[column]), column
    sa, sb = read_summary(str(first)), read_summary(runs["csm3_short"])
    for key in ("newton_iterations", "gmres_iterations"):
        assert sa[key] == sb[key], key


def test_restart_keeps_a_reference_point_off_round_coordinates(tmp_path):
    """parameters.txt records the reference node's coordinates to about 15 digits, so a
    restart takes the same node (not one 1e-6 away, outside the disk, refused): the
    restarted history equals the uninterrupted one."""
    args = ["-reference", "3,0.3", "-snapshots", "none", "-progress", "0", "-solver", "activeset"]
    first, whole = tmp_path / "first", tmp_path / "whole"
    run_scene("test1", first, args + ["-T", "1", "-checkpoint_every", "10"])
    x, y = (float(c) for c in read_parameters(str(first))["-reference"].split(","))
    assert abs(x - 2.61052385104102) < 1e-13 and abs(y - 0.171102773397962) < 1e-13
    run_scene("test1", first, ["-restart", str(first), "-T", "2", "-progress", "0"])
    run_scene("test1", whole, args + ["-T", "2"])
    assert (first / "history.csv").read_bytes() == (whole / "history.csv").read_bytes()


def test_reference_point_is_recorded(runs):
    """The *_low columns follow the reference point: on the disk the lowest node of
    Gamma_C, (0, 0); on the cantilever the scene's (10, 1)."""
    assert read_parameters(runs["test1"])["-reference"] == "0,0"
    assert read_parameters(runs["cantilever_activeset"])["-reference"] == "10,1"


def test_activeset_computes_only_the_schur_columns_it_needs(runs):
    """The active-set solver builds a column of S = C A^-1 C' only for a contact node that
    becomes active or comes near (10)'s bound: 1 column per node on Test 1's flat, level foundation
    (psi' = 0), 2 on Test 2's cosine (on the serial Cholesky factor a column is L^-1 P e_dof, a part of a
    block forward solve; docs/solvers.md); fewer than the 49 contact vertices, and 2 x 49."""
    flat, cosine = (int(read_summary(runs[k])["schur_solves"]) for k in ("test1_activeset", "test2_activeset"))
    assert 0 < flat < 49 and 0 < cosine < 2 * 49 and cosine % 2 == 0


def test_schur_complement_holds_only_the_known_columns(runs):
    """S and its blocks keep a column per known contact node only (contact/schur_blocks.idp), not one per node of
    Gamma_C: at least the known nodes' columns and at most twice as many (the width doubles from 16), fewer than
    the 49 contact vertices. On Test 1's flat foundation (the factor's columns) each known node is one of
    schur_solves; on Test 2's cosine from solves (-factorization lu, its slope blocks too) two."""
    for key, per_node in (("test1_activeset", 1), ("test2_activeset_lu", 2)):
        summary = read_summary(runs[key])
        known, held = int(summary["schur_solves"]) // per_node, int(summary["schur_columns"])
        assert 0 < known <= held <= max(16, 2 * known) and held < 49, (key, known, held)


BAD_GEOMETRY = {
    "no such Dirichlet label": ("test1", ["-dirichlet_label", "7"], "has no boundary edge with label 7 (Gamma_D"),
    "Gamma_D over Gamma_C": ("test1", ["-dirichlet_label", "1"], "Gamma_D must not overlap Gamma_C"),
    "no such traction label": ("test1", ["-traction", "0.1", "-traction_label", "7"],
                               "has no boundary edge with label 7 (Gamma_T, -traction_label); its labels are 1 2"),
    "a traction on Gamma_D": ("cantilever", ["-traction", "0.1", "-traction_label", "3"],
                              "-traction_label 3 is also -dirichlet_label: a traction on the clamped Gamma_D does nothing"),
    "reference outside": ("test1", ["-reference", "100,100"], "-reference (100, 100) is outside the body"),
    "probe outside": ("test1", ["-probes", "0,-5"], "-probes (0, -5) is outside the body"),
    "order 3": ("test1", ["-order", "3"], "-order must be an integer in [1, 2], got '3'"),
    "no such contact label": ("test1", ["-contact_label", "7", "-foundation", "none"],
                              "has no boundary edge with label 7 (Gamma_C, -contact_label); its labels are 1 2"),
    # Gamma_C on several labels (-contact_label 1,2): each once, each on the mesh, digits and commas only
    "a contact label twice": ("test1", ["-contact_label", "1,1"],
                              "-contact_label names label 1 twice: give each label of Gamma_C once"),
    "a listed contact label not on the mesh": ("test1", ["-contact_label", "1,7"],
                                               "has no boundary edge with label 7 of -contact_label 1,7 (Gamma_C); its "
                                               "labels are 1 2"),
    "a contact label list that is not one": ("test1", ["-contact_label", "1;2"],
                                             "-contact_label must be an integer in [1, 1000000000], or a list of them "
                                             "such as 1,2; got '1;2'"),
    # names what moves it, and only the plane options
    "moving clamp": ("cantilever", ["-u0y", "1", "-spin", "0.1"], "the initial state moves the clamped boundary Gamma_D "
                     "(label 3): -u0y is 1, -spin is 0.1; with Gamma_D, -u0x, -u0y, -v0x, -v0y and -spin must be 0"),
}


@pytest.mark.parametrize("case", list(BAD_GEOMETRY))
def test_bad_geometry_is_one_clear_error_and_changes_nothing(tmp_path, earlier_run, case):
    """Exit 3, one error line naming what is wrong, and the earlier run's files unchanged."""
    scene, args, message = BAD_GEOMETRY[case]
    p, changed = refused_into_copy(tmp_path, earlier_run, scene, args + ["-T", "1", "-snapshots", "none"])
    errors = error_lines(p)
    assert p.returncode == 3 and len(errors) == 1 and message in errors[0], p.stderr
    assert not changed


def test_scene_order_line_and_missing_scene_mesh(tmp_path, earlier_run):
    """A scene sets the order with a line `order = 2;` (edp/run.sh reads it before FreeFEM
    compiles the driver); a mesh that make builds from its .geo but that is not built yet
    is named with the command that builds it."""
    scene = tmp_path / "p2scene.idp"
    scene.write_text('order = 2;\nT = 0.1;\nsnapshots = "none";\n')
    out = tmp_path / "p2run"
    run_scene(str(scene), out, ["-progress", "0"])
    assert read_parameters(str(out))["-order"] == "2"
    # -order 02 is 2 for edp/run.sh as for the driver (P2 compiled, not P1)
    p = run_scene(str(scene), tmp_path / "p2run02", ["-progress", "0", "-order", "02"])
    assert "P2" in p.stdout.splitlines()[0] and read_parameters(str(tmp_path / "p2run02"))["-order"] == "2"
    geo_dir = tmp_path / "meshes"
    geo_dir.mkdir()
    shutil.copy(os.path.join(ROOT, "meshes", "ring.geo"), geo_dir / "ring.geo")
    p, changed = refused_into_copy(tmp_path, earlier_run, "test1", ["-mesh", str(geo_dir / "ring.msh"), "-T", "1"])
    errors = error_lines(p)
    assert p.returncode == 3 and len(errors) == 1 and "build it from its .geo with `make meshes`" in errors[0], p.stderr
    assert not changed


def test_csm1_static_matches_the_published_values():
    """Turek-Hron CSM1, the static case of the csm3 geometry (tests/edp/csm1.edp): the
    St Venant-Kirchhoff force of Section 3 at rest, N(x; x) = F, with Gamma_D on the
    cylinder, at P2 on meshes/csm3.msh: u(A) within 0.5% of (-7.187, -66.10) x 1e-3
    (measured -0.30% and -0.17%; -0.09% and -0.05% on the mesh refined once), with
    Newton converging in at most 10 iterations."""
    env = freefem_env()
    p = subprocess.run(["FreeFem++-nw", "-nw", "-ns", "-v", "0", "tests/edp/csm1.edp", "-mesh", "meshes/csm3.msh"],
                       cwd=ROOT, capture_output=True, text=True, env=env)
    line = [l for l in p.stdout.splitlines() if l.startswith("csm1 ")]
    assert p.returncode == 0 and line, p.stdout + p.stderr
    _, ux, uy, iterations = line[0].split()
    assert abs(float(ux) + 7.187) <= 0.005 * 7.187 and abs(float(uy) + 66.10) <= 0.005 * 66.10, line[0]
    assert int(iterations) <= 10


def test_contact_on_several_labels_adds_their_nodes_to_10(tmp_path):
    """-contact_label 1,2 imposes (10) on the disk's whole boundary (49 + 65 vertices, the two its halves share
    once: 112). Its top half never reaches the foundation in Test 1, and the active-set solver's QP has one solution, so
    the history is the one of -contact_label 1 to the bit; parameters.txt records the list as given."""
    runs = {}
    for labels in ("1", "2,1"):
        out = tmp_path / labels.replace(",", "_")
        p = run_scene("test1", out, ["-T", "30", "-solver", "activeset", "-contact_label", labels, "-progress", "0",
                                     "-snapshots", "none"])
        runs[labels] = (out, p.stdout.splitlines()[0])
    assert "49 contact vertices" in runs["1"][1] and "112 contact vertices" in runs["2,1"][1], runs
    assert (runs["1"][0] / "history.csv").read_bytes() == (runs["2,1"][0] / "history.csv").read_bytes()
    assert read_parameters(str(runs["2,1"][0]))["-contact_label"] == "2,1"
