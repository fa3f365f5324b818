"""A 3D body (issue 25): the ball of radius 20 on a flat and on a moving foundation surface, short runs
on the coarse meshes/ball.msh. The scheme is the paper's, unchanged in 3D: the mid-point scheme (1)-(2),
each step the variational inequality (4) under constraint (10), psi + psi_X1 u1 + psi_X2 u2 <= X3 + u3.
Each test states the property it checks and the equation behind it."""
import os
import shutil
import subprocess

import meshio
import numpy as np
import pytest

from conftest import ROOT, error_lines, files_of, run_scene, run_scenes
from driver import freefem_env
from golden import compare
from history import read_run

BALL = os.path.join(ROOT, "meshes", "ball.msh")
QUIET = ["-progress", "0", "-snapshots", "none"]
RUNS_3D = {
    "fall": ("ball", ["-T", "8.5", "-solver", "activeset"] + QUIET),
    "impact": ("ball", ["-T", "20", "-solver", "activeset"] + QUIET),
    "impact_ipopt": ("ball", ["-T", "14", "-tol", "1e-10"] + QUIET),
    "rest": ("ball", ["-u0z", "0", "-T", "30", "-solver", "activeset"] + QUIET),
    "moving": ("ball_moving", ["-T", "20", "-t1", "14", "-solver", "activeset", "-progress", "0", "-snapshots", "every:1"]),
    "moving_ipopt": ("ball_moving", ["-T", "14", "-t1", "14"] + QUIET),
    "spin": ("ball", ["-foundation", "none", "-fz", "0", "-u0z", "0", "-spin", "0.05", "-T", "5"] + QUIET),
    "f0": ("ball", ["-fz", "0", "-v0z", "-0.5", "-u0z", "1", "-T", "20", "-solver", "activeset"] + QUIET),
    "lumped": ("ball", ["-mass", "lumped", "-T", "14", "-solver", "activeset"] + QUIET),
    "singular": ("ball", ["-mass", "singular", "-T", "14", "-solver", "activeset"] + QUIET),
    "penalty": ("ball", ["-contact", "penalty", "-T", "14"] + QUIET),
    # the Neo-Hookean body (material/neohookean_3d.idp): a spinning, drifting free flight, and Test 1 in 3D
    "nh_spin": ("ball", ["-material", "neohookean", "-foundation", "none", "-fz", "0", "-u0z", "0", "-v0x", "0.1",
                         "-spin", "0.05", "-T", "10"] + QUIET),
    "nh_impact": ("ball", ["-material", "neohookean", "-T", "20"] + QUIET),
    # the other schemes act on vectors too: a drifting, spinning free flight
    "newmark_free": ("ball", ["-scheme", "newmark", "-foundation", "none", "-fz", "0", "-u0z", "0", "-v0x", "0.1",
                              "-spin", "0.05", "-T", "5"] + QUIET),
    "verlet_free": ("ball", ["-scheme", "verlet", "-dt", "0.01", "-foundation", "none", "-fz", "0", "-u0z", "0",
                             "-v0x", "0.1", "-spin", "0.05", "-T", "5"] + QUIET),
}


@pytest.fixture(scope="module")
def runs3d(tmp_path_factory):
    return run_scenes(tmp_path_factory.mktemp("ball"), RUNS_3D)


@pytest.fixture(scope="module")
def h3(runs3d):
    return {name: read_run(d) for name, d in runs3d.items()}


def ball_mass(out):
    """rho = 1 times the volume of the run's mesh (mesh.mesh, medit: its Vertices and Tetrahedra)."""
    lines = open(os.path.join(out, "mesh.mesh")).read().split("\n")
    k = lines.index("Vertices")
    nv = int(lines[k + 1])
    xyz = np.array([[float(v) for v in lines[k + 2 + i].split()[:3]] for i in range(nv)])
    k = lines.index("Tetrahedra")
    nt = int(lines[k + 1])
    tets = np.array([[int(v) - 1 for v in lines[k + 2 + i].split()[:4]] for i in range(nt)])
    a, b, c, d = (xyz[tets[:, i]] for i in range(4))
    return np.abs(np.einsum("ij,ij->i", b - a, np.cross(c - a, d - a))).sum() / 6


def test_free_fall_is_exact(h3):
    """Before the impact (t < 8.94) the ball falls freely: the mid-point scheme integrates the rigid fall
    exactly (f = (0, 0, -0.1), rho = 1): u3 = 4 - 0.05 t^2 and v3 = -0.1 t at every node, u1 = u2 = 0."""
    h = h3["fall"]
    t = h["t"]
    assert np.abs(h["u3_low"] - (4 - 0.05 * t ** 2)).max() < 1e-10
    assert np.abs(h["v3_low"] + 0.1 * t).max() < 1e-10 and np.abs(h["v3_mean"] + 0.1 * t).max() < 1e-10
    assert np.abs(h["u3_mean"] - (4 - 0.05 * t ** 2)).max() < 1e-10
    assert np.abs(h["u1_low"]).max() < 1e-10 and np.abs(h["u2_low"]).max() < 1e-10
    assert (h["active_nodes"] == 0).all() and (h["contact_force_z"] == 0).all()


def test_spinning_free_flight_keeps_the_energy(h3):
    """Without foundation and load, the mid-point scheme conserves the discrete energy of a linear body
    exactly (Section 2: (1)-(2) with f = 0 and no contact), here a ball spinning about X3 at 0.05."""
    e = h3["spin"]["energy"]
    assert e[0] > 1 and np.abs(e - e[0]).max() < 1e-12 * e[0]


def test_momentum_balance_gives_the_contact_force_in_force_units(h3, runs3d):
    """Eq. (1) against the unit vertical translation e3 (K e3 = 0): m (v3_mean^{n+1} - v3_mean^n) / dt =
    -0.1 m + contact_force_z^{n+1}, to round-off, so contact_force_z is the total vertical force on the
    body. On a ball left on the foundation under gravity its mean over the run is the weight, but for
    the momentum left at T: mean F = m g + m (v3_mean(T) - v3_mean(0)) / T."""
    for name in ("impact", "rest"):
        h = h3[name]
        m = ball_mass(runs3d[name])
        dt = h["t"][1] - h["t"][0]
        balance = m * np.diff(h["v3_mean"]) / dt - (-0.1 * m + h["contact_force_z"][1:])
        assert np.abs(balance).max() < 1e-9 * 0.1 * m, (name, np.abs(balance).max())
    h = h3["rest"]
    m = ball_mass(runs3d["rest"])
    weight = 0.1 * m
    T = h["t"][-1]
    mean = h["contact_force_z"][1:].mean()
    assert abs(mean - (weight + m * (h["v3_mean"][-1] - h["v3_mean"][0]) / T)) < 1e-9 * weight
    assert h["active_nodes"].max() > 0


def test_modified_energy_never_rises_on_a_fixed_foundation(h3):
    """Prop. 2 (w = u^n in (4)): on a fixed foundation the modified energy m^n = E^n - (f, u^n) does not
    increase from one step to the next (to the solver's round-off), through the impact and the rebound."""
    for name in ("impact", "rest", "f0", "lumped", "singular"):
        m = h3[name]["modified_energy"]
        assert np.diff(m).max() < 1e-9 * abs(m).max(), (name, np.diff(m).max())
    assert h3["impact"]["active_nodes"].max() > 0


def test_the_impact_bounces_the_ball(h3):
    """The first impact of Test 1 in 3D: contact starts at t = sqrt(80) = 8.94 (the free fall of 4), the
    foundation pushes the centre of mass back up (v3_mean > 0 after it) and the f = 0 impact loses little
    energy (the mid-point scheme with (10) is dissipative only through the contact, Prop. 2)."""
    h = h3["impact"]
    first = h["t"][np.flatnonzero(h["contact_force_z"] > 0)[0]]
    assert abs(first - np.sqrt(80)) < 0.05 + 1e-9
    assert h["v3_mean"].max() > 0.2
    e = h3["f0"]["energy"]
    assert e[-1] <= e[0] * (1 + 1e-12) and e[-1] > 0.9 * e[0]


def test_constraint_10_holds_at_every_contact_node(h3, runs3d):
    """(10) psi + psi_X1 u1 + psi_X2 u2 <= X3 + u3 at every node of Gamma_C, on the moving foundation of
    ball_moving (psi = c(t) cos(pi r / 60) - 2, lowered on [9, 14]): the history's largest violation is at
    round-off for the active set and at IPOPT's tolerance, and an independent check from the snapshots'
    nodes (run.pvd's .vtu files) with psi written here gives the same."""
    assert h3["moving"]["max_penetration"].max() < 1e-9
    assert h3["moving_ipopt"]["max_penetration"].max() < 1e-7
    out = runs3d["moving"]

    def c(t):
        return 2.0 if t < 9 else (2 * np.cos(np.pi * (t - 9) / (2 * (14 - 9))) if t < 14 else 0.0)
    worst = 0
    for t in range(0, 21):
        m = meshio.read(os.path.join(out, f"vonmises_t{t}.vtu"))
        labels = np.concatenate(m.cell_data["Label"])
        faces = m.cells_dict["triangle"][labels[len(m.cells_dict["tetra"]):] == 1]
        nodes = np.unique(faces)
        X, u = m.points[nodes].astype(float), m.point_data["displacement"][nodes]
        # (the .vtu stores X in single precision: psi and its slope are evaluated at the float32 X)
        r = np.hypot(X[:, 0], X[:, 1])
        psi = c(t) * np.cos(np.pi * r / 60) - 2
        slope = -c(t) * np.pi / 60 * np.sin(np.pi * r / 60) / np.where(r > 0, r, 1)
        gap = X[:, 2] + u[:, 2] - (psi + slope * X[:, 0] * u[:, 0] + slope * X[:, 1] * u[:, 1])
        worst = min(worst, gap.min())
    assert worst > -1e-5, worst        # (X to float32: 20 * 6e-8)


@pytest.mark.parametrize("exact,ipopt", [("impact", "impact_ipopt"), ("moving", "moving_ipopt")])
def test_activeset_and_ipopt_agree(h3, exact, ipopt):
    """The same QP (4) solved exactly (active set) and by IPOPT to tol 1e-10 give the same motion, on the flat
    foundation and on the moving one, where both slopes psi_X1, psi_X2 are non-zero and the active set's
    Schur complement uses all nine blocks (contact/active_set.idp)."""
    a, b = h3[exact], h3[ipopt]
    n = len(b["t"])
    a = {k: v[:n] for k, v in a.items()}
    assert np.abs(a["u3_low"] - b["u3_low"]).max() < 1e-5
    assert np.abs(a["energy"] - b["energy"]).max() < 1e-6 * a["energy"].max()
    assert np.abs(a["contact_force_z"] - b["contact_force_z"]).max() < 1e-6 * a["contact_force_z"].max()


def test_newmark_and_verlet_keep_the_momenta_in_free_flight(h3):
    """Newmark (the classical 1/4, 1/2) and explicit Verlet act on vectors and matrices, so they carry over:
    without contact and load both keep the linear momentum exactly (M v . e1 = m v0x at every step: K e1 = 0),
    and Newmark (1/4, 1/2) keeps the energy of a linear body, Verlet below its critical step within 1e-3."""
    for name in ("newmark_free", "verlet_free"):
        h = h3[name]
        assert np.abs(h["v1_mean"] - 0.1).max() < 1e-12 and np.abs(h["v3_mean"]).max() < 1e-12, name
        assert h["angular_momentum_3"][0] > 1e5
    e = h3["newmark_free"]["energy"]
    assert np.abs(e - e[0]).max() < 1e-10 * e[0]
    e = h3["verlet_free"]["energy"]
    assert np.abs(e - e[0]).max() < 1e-3 * e[0]


def test_singular_mass_in_3d_keeps_the_moments_and_is_tested_positive_definite(h3, runs3d):
    """The singular mass (Khenous-Laborde-Renard) in 3D keeps the ten moments of 1, X1, X2, X3 (the driver checks
    them to 1e-10) and, where the sufficient bound on its entries fails (a fifth of ball.msh's nodes are on
    Gamma_C), is accepted only on its smallest eigenvalue against the lumped mass (>= 0.01; 0.153 here): the
    run says so, free fall is still exact, and (10) holds at every contact node."""
    p = run_scene("ball", os.path.join(runs3d["singular"] + "_note"), ["-mass", "singular", "-T", "0.1"] + QUIET)
    note = [line for line in p.stdout.splitlines() if line.startswith("note: singular mass:")]
    assert len(note) == 1 and "its smallest eigenvalue against the lumped mass is 0.15" in note[0], p.stdout
    h = h3["singular"]
    t = h["t"][h["t"] < 8.9]
    assert np.abs(h["u3_mean"][:len(t)] - (4 - 0.05 * t ** 2)).max() < 1e-10
    assert h["max_penetration"].max() < 1e-9 and h["active_nodes"].max() > 0


def test_penalty_and_lumped_mass_run_in_3d(h3):
    """The penalty method and the lumped mass act on vectors and matrices, so they carry over: the
    penalty's penetration stays small (its eps = 1e-3 L/(lambda + 2 mu)), the lumped mass's (10) holds."""
    assert 0 < h3["penalty"]["max_penetration"].max() < 0.05
    assert h3["lumped"]["max_penetration"].max() < 1e-9 and h3["lumped"]["active_nodes"].max() > 0


@pytest.mark.parametrize("golden,run", [("ball", "impact"), ("ball_moving", "moving")])
def test_3d_histories_match_golden(h3, golden, run):
    """Test 1 and Test 2 in 3D (ball and ball_moving with t1 = 14, active set) to T = 20 against
    tests/golden/ball.csv and ball_moving.csv."""
    failures = compare(os.path.join(ROOT, "tests", "golden", f"{golden}.csv"), h3[run])
    assert not failures, "\n".join(failures)


def test_neohookean_spinning_free_flight_conserves_energy_and_momenta(h3):
    """Without contact and with f = 0, the Neo-Hookean mid-point scheme with Gonzalez's discrete gradient
    conserves the energy and the linear and angular momentum vectors (Section 3's property, 3D): a ball
    drifting at v0x = 0.1 and spinning about X3 at 0.05, to the Newton tolerance (1e-10)."""
    h = h3["nh_spin"]
    for column in ("energy", "angular_momentum_1", "angular_momentum_2", "angular_momentum_3"):
        scale = max(abs(h[column]).max(), h["energy"][0])
        assert np.abs(h[column] - h[column][0]).max() < 1e-10 * scale, column
    assert np.abs(h["v1_mean"] - 0.1).max() < 1e-12 and np.abs(h["v3_mean"]).max() < 1e-12
    assert h["angular_momentum_3"][0] > 1e5 and h["min_J"].min() > 0.99


def test_neohookean_ball_bounces_without_energy_gain(h3):
    """The Neo-Hookean ball's first impact: det F stays positive (min J recorded), Prop. 2 (the modified
    energy never rises on the fixed foundation, to the Newton tolerance) and (10) to round-off."""
    h = h3["nh_impact"]
    assert 0.3 < h["min_J"].min() < 1 and h["active_nodes"].max() > 0
    assert np.diff(h["modified_energy"]).max() < 1e-9 * abs(h["modified_energy"]).max()
    assert h["max_penetration"].max() < 1e-9


@pytest.mark.parametrize("seed", [1, 2])
def test_neohookean_tangent_and_energy_identity_at_a_random_state(seed):
    """tests/edp/neohookean3_unit.edp at a random state (a 1 rad rotation about (1, 1, 1) plus smooth
    fields): the consistent tangent against central differences of N (<= 1e-6), Gonzalez's identity
    N(x).(x - u^n) = W(x) - W(u^n) to round-off, N'(0) = K / 2 (the linear form), N against the gradient of
    W for a vanishing step, and a mirrored state's infinite energy, refused by N."""
    env = freefem_env()
    p = subprocess.run(["FreeFem++-nw", "-nw", "-ns", "-v", "0", "tests/edp/neohookean3_unit.edp", "-mesh", BALL,
                        "-seed", str(seed)], cwd=ROOT, capture_output=True, text=True, env=env)
    assert p.returncode == 0, p.stdout + p.stderr
    v = {line.split()[0]: line.split()[1:] for line in p.stdout.splitlines() if line.split()}
    assert float(v["tangent"][0]) <= 1e-6 and float(v["gradient"][0]) <= 1e-6
    assert float(v["identity"][0]) <= 1e-12 and float(v["linear"][0]) <= 1e-11
    assert float(v["inverted"][0]) >= 1e300 and v["inverted"][1] == "1"


BUMP = '''// a Gaussian bump under the ball, off its axis (scene macros: -foundation user on a 3D body)
meshFile = "meshes/ball.msh";
foundation = "user";
fy = 0;
fz = -0.1;
u0y = 0;
u0z = 4;
snapshots = "none";
macro userFoundationPsi3(X1, X2, t) (-1 + 1.5 * exp(-((X1 - 4)^2 + X2^2) / 50)) // EOM
macro userFoundationDpsiX1(X1, X2, t) (-0.06 * (X1 - 4) * exp(-((X1 - 4)^2 + X2^2) / 50)) // EOM
macro userFoundationDpsiX2(X1, X2, t) (DPSI2) // EOM
'''


def test_a_scene_foundation_surface_pushes_the_ball_away(tmp_path):
    """A scene's psi(X1, X2, t) with its gradient (-foundation user, 3D): a bump centred at X1 = 4 under the
    ball's lowest point slopes up towards +X1 there, so the contact pushes the ball towards -X1, while
    (10) holds at every contact node and the modified energy does not rise (Prop. 2, fixed foundation)."""
    scene = tmp_path / "bump3.idp"
    scene.write_text(BUMP.replace("DPSI2", "-0.06 * X2 * exp(-((X1 - 4)^2 + X2^2) / 50)"))
    out = tmp_path / "out"
    run_scene(str(scene), out, ["-T", "14", "-solver", "activeset", "-progress", "0"])
    h = read_run(str(out))
    assert h["active_nodes"].max() > 0 and h["max_penetration"].max() < 1e-9
    assert h["v1_mean"][-1] < -1e-3 and abs(h["v2_mean"][-1]) < 0.1 * abs(h["v1_mean"][-1])
    assert np.diff(h["modified_energy"]).max() < 1e-9 * abs(h["modified_energy"]).max()


@pytest.mark.parametrize("dpsi2,message", [
    ("0", "userFoundationDpsiX2 is not the derivative of userFoundationPsi3 in X2"),
    ("-0.06 * X2 * exp(-((X1 - 4)^2 + X2^2) / 50)", None),
])
def test_a_scene_foundation_surface_is_checked(tmp_path, dpsi2, message):
    """The 2D checks of a scene's psi carry over to 3D: its gradient must be that of a central difference in
    X1 and in X2 over the region Gamma_C sweeps, or the run is refused in one line (exit 3); a correct one runs."""
    scene = tmp_path / "bump3.idp"
    scene.write_text(BUMP.replace("DPSI2", dpsi2))
    p = run_scene(str(scene), tmp_path / "out", ["-T", "0.1", "-progress", "0"], check=False)
    if message is None:
        assert p.returncode == 0, p.stderr
    else:
        assert p.returncode == 3 and len(error_lines(p)) == 1 and message in error_lines(p)[0], p.stderr


def test_a_moving_scene_surface_must_be_declared_moving(tmp_path):
    """A psi(X1, X2, t) that changes with t in a scene that does not declare it moving is refused: a fixed
    foundation keeps the rows of (10) of t = 0."""
    scene = tmp_path / "sinking.idp"
    scene.write_text(BUMP.replace("DPSI2", "-0.06 * X2 * exp(-((X1 - 4)^2 + X2^2) / 50)")
                     .replace("(-1 + 1.5 * exp", "(-1 - 0.01 * t + 1.5 * exp"))
    p = run_scene(str(scene), tmp_path / "out", ["-T", "1", "-progress", "0"], check=False)
    assert p.returncode == 3 and "userFoundationPsi3 changes with t" in p.stderr and "foundationMoving = 1" in p.stderr


REFUSED = [
    (["-material", "svk"], "-material svk is not supported on a 3D body yet"),
    (["-material", "neohookean", "-newton_precond", "step"], "-newton_precond step is not supported on a 3D body"),
    (["-order", "2"], "-order 2 is not supported on a 3D body"),
    (["-contact", "nitsche"], "-contact nitsche is not supported on a 3D body"),
    (["-contact", "penalty", "-contact_quadrature", "gauss"], "-contact_quadrature gauss is not supported on a 3D body"),
    (["-foundation", "user"], "-foundation user on a 3D body needs the scene to define macros userFoundationPsi3"),
    (["-probes", "0,0"], "-probes must be x,y,z triples on a 3D body, got 2 numbers"),
    (["-reference", "0,0"], "-reference must be one x,y,z triple on a 3D body (or auto), got 2 numbers"),
    (["-probes", "0,0,50"], "-probes (0, 0, 50) is outside the body"),
    (["-u0z", "-1"], "the initial state penetrates the foundation by 1 at the vertex"),
    # a clamped ball: the line names u0z and v0z, which move it (issue 32: it named only u0x, u0y, v0x, v0y, spin)
    (["-dirichlet_label", "2"], "the initial state moves the clamped boundary Gamma_D (label 2): -u0z is 4; with Gamma_D, "
                                "-u0x, -u0y, -u0z, -v0x, -v0y, -v0z and -spin must be 0"),
    (["-dirichlet_label", "2", "-u0z", "0", "-v0z", "0.5"], "Gamma_D (label 2): -v0z is 0.5; with Gamma_D"),
]


@pytest.fixture(scope="module")
def earlier_ball(tmp_path_factory):
    out = tmp_path_factory.mktemp("earlier3d") / "run"
    run_scene("ball", out, ["-T", "0.5", "-snapshots", "0,0.25", "-checkpoint_every", "5", "-progress", "0"])
    return str(out)


@pytest.mark.parametrize("args,message", REFUSED, ids=[" ".join(a) for a, _ in REFUSED])
def test_3d_refusals_are_one_line_and_change_nothing(tmp_path, earlier_ball, args, message):
    """What 3D does not support (yet), and bad 3D input, is one error line with exit 3, and the earlier
    run in the directory stays byte-identical."""
    out = tmp_path / "copy"
    shutil.copytree(earlier_ball, out)
    before = files_of(out)
    p = run_scene("ball", out, args + ["-T", "1", "-progress", "0"], check=False)
    assert p.returncode == 3, p.stderr
    assert len(error_lines(p)) == 1 and message in error_lines(p)[0], p.stderr
    assert files_of(out) == before


@pytest.mark.parametrize("psi,message", [
    # the example: finite over Gamma_C's extent widened by a quarter (|X1| <= 26), NaN beyond |X1| = 27:
    # foundation.csv (X1 in [-30, 30], X2 = 0) had 24 -nan rows and every foundation_t*.vtu NaN coordinates, exit 0
    ("sqrt(27 - abs(X1))", "error: userFoundationPsi3 is not finite at (X1, X2) = (-30, 0), t = 0, where foundation.csv "
                           "draws it (X1 in [-30, 30]): it gives -nan"),
    # NaN beyond |X2| = 27 only: not on foundation.csv's line X2 = 0, but on the foundation_t*.vtu surface under the ball
    ("sqrt(27 - abs(X2))", "error: userFoundationPsi3 is not finite at (X1, X2) = (-29.966, -29.966), t = 0, where "
                           "foundation_t0.vtu would draw it under the body where it is at t = 0 (its horizontal extent "
                           "widened by a quarter on each side): it gives -nan"),
], ids=["foundation.csv", "foundation vtu"])
def test_a_scene_surface_not_finite_where_it_is_written_is_refused(tmp_path, earlier_ball, psi, message):
    """Issue 32: a scene's psi(X1, X2, t) must be finite wherever the suite writes it, not only over the region
    Gamma_C sweeps: refused before the first step, exit 3, one line naming psi and the point, the earlier run
    byte-identical."""
    scene = tmp_path / "nan3.idp"
    scene.write_text(BUMP.replace("DPSI2", "0").replace("(-1 + 1.5 * exp(-((X1 - 4)^2 + X2^2) / 50))", f"(-1 + 0 * {psi})")
                     .replace("(-0.06 * (X1 - 4) * exp(-((X1 - 4)^2 + X2^2) / 50))", "0")
                     .replace('snapshots = "none";', 'snapshots = "0,0.5";'))
    out = tmp_path / "copy"
    shutil.copytree(earlier_ball, out)
    before = files_of(out)
    p = run_scene(str(scene), out, ["-T", "1", "-progress", "0"], check=False)
    assert p.returncode == 3 and error_lines(p) == [message + "; a foundation must be finite wherever the suite writes it"], \
        p.stderr
    assert files_of(out) == before


def test_3d_restart_continues_the_same_history(tmp_path):
    """A 3D run restarted from its checkpoint gives the uninterrupted history, bit for bit."""
    args = ["-T", "10", "-solver", "activeset", "-checkpoint_every", "100"] + QUIET
    first = tmp_path / "first"
    run_scene("ball", first, args)
    run_scene("ball", first, ["-restart", str(first), "-T", "12"] + QUIET[:2])
    straight = tmp_path / "straight"
    run_scene("ball", straight, ["-T", "12"] + args[2:])
    assert open(first / "history.csv").read() == open(straight / "history.csv").read()


def test_3d_restart_on_another_mesh_names_its_tetrahedra(tmp_path, earlier_ball):
    """A 3D restart on another mesh is refused naming the cells as tetrahedra (it said "triangles"), and the
    run it would continue stays byte-identical."""
    before = files_of(earlier_ball)
    p = run_scene("ball", tmp_path / "out", ["-restart", earlier_ball, "-mesh", os.path.join(ROOT, "meshes", "hertz_coarse.msh"),
                                             "-T", "1", "-progress", "0"], check=False)
    assert p.returncode == 3 and error_lines(p) == [
        f"error: -restart {earlier_ball}: its checkpoint is for a mesh with 667 vertices and 2674 tetrahedra; -mesh "
        f"{ROOT}/meshes/hertz_coarse.msh has 534 and 2215"], p.stderr
    assert files_of(earlier_ball) == before and not (tmp_path / "out").exists()


def test_a_3d_scene_on_a_plane_mesh_says_what_does_not_apply(tmp_path):
    """Issue 32, item 10. `ball -mesh meshes/disk.msh` ran with no gravity and no lift (the scene's fz and
    u0z apply to a 3D body only), exit 0, and printed no word: the warning came only for -fz given on the
    command line. Now one warning line names every 3D setting that does not apply, with its value and
    where it came from (the scene or the command line), and what the plane run takes instead."""
    disk = os.path.join(ROOT, "meshes", "disk.msh")
    plane = (f"apply to a 3D body, where X3 is vertical, and -mesh {disk} is plane, where X2 is vertical; the run goes on "
             "with what applies to a plane body: ")
    p = run_scene("ball", tmp_path / "scene", ["-mesh", disk, "-T", "0.1"] + QUIET)
    warnings = [line for line in p.stderr.splitlines() if line.startswith("warning:")]
    assert warnings == ["warning: -fz -0.1 and -u0z 4 (from the scene ball) have no effect: they " + plane
                        + "f = (fx, fy) = (0, 0), u0 = (u0x, u0y) = (0, 0), v0 = (v0x, v0y) = (0, 0)"], p.stderr
    q = run_scene("ball", tmp_path / "both", ["-mesh", disk, "-T", "0.1", "-fy", "-0.1", "-u0y", "4", "-v0z", "-3"] + QUIET)
    warnings = [line for line in q.stderr.splitlines() if line.startswith("warning:")]
    assert warnings == ["warning: -fz -0.1 and -u0z 4 (from the scene ball) and -v0z -3 (from the command line) have no "
                        "effect: they " + plane + "f = (fx, fy) = (0, -0.1), u0 = (u0x, u0y) = (0, 4), v0 = (v0x, v0y) = (0, 0)"]
    r = run_scene("test1", tmp_path / "one", ["-T", "0.1", "-v0z", "1"] + QUIET)
    warnings = [line for line in r.stderr.splitlines() if line.startswith("warning:")]
    assert len(warnings) == 1 and warnings[0].startswith("warning: -v0z 1 (from the command line) has no effect: it applies to a 3D body")
