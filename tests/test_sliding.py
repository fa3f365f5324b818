"""The exact gap (issue 36; edp/lib/contact/exact_gap.idp, docs/sliding.md): -gap exact imposes
X2 + u2 >= psi(X1 + u1, t) at every contact node, where the paper's (10) evaluates psi and psi' at the undeformed X1;
every run's history records how far its result lies from the true foundation (max_penetration_exact, below it;
max_held_off_exact, a pressed node above it)."""
import os
import sys

import numpy as np
import pytest

from conftest import ROOT, error_lines, refused_into_copy, restart_reproduces, run_scenes

sys.path.insert(0, os.path.join(ROOT, "postprocess"))
import sliding  # noqa: E402
from history import read_run, read_summary  # noqa: E402

QUIET = ["-progress", "0", "-snapshots", "none"]
COARSE = ["-mesh", os.path.join(ROOT, "meshes", "disk_coarse.msh"), "-dt", "0.4"] + QUIET
SIZE = 40.0                     # the disk's size (its diameter), meshSize
EXACT_TOL = 1e-10 * SIZE        # the exact gap's tolerance (contact/exact_gap.idp)
RUNS = {
    "bowl": ("bowl", COARSE),
    "bowl_linearised": ("bowl", COARSE + ["-gap", "linearised"]),
    "bowl_ipopt": ("bowl", COARSE + ["-T", "20", "-solver", "ipopt"]),
    "ball_bowl": ("bowl", ["-mesh", os.path.join(ROOT, "meshes", "ball.msh"), "-dt", "0.4"] + QUIET),
    "flat_exact": ("test1", ["-T", "12", "-solver", "activeset", "-gap", "exact"] + QUIET),
    "flat_linearised": ("test1", ["-T", "12", "-solver", "activeset"] + QUIET),
    "bump_exact": ("bump", ["-solver", "activeset", "-gap", "exact"] + QUIET),
    "bump_linearised": ("bump", ["-solver", "activeset"] + QUIET),
    "bump_neohookean": ("bump", ["-T", "20", "-material", "neohookean", "-gap", "exact"] + QUIET),
    "wave_exact": ("wave", ["-T", "20", "-solver", "activeset", "-gap", "exact"] + QUIET),
    "bowl_newmark": ("bowl", COARSE + ["-T", "20", "-scheme", "newmark"]),
    "bowl_np2": ("bowl", COARSE + ["-T", "4", "-np", "2"]),
    "test2_still_exact": ("test2", ["-T", "20", "-t0", "30", "-t1", "40", "-solver", "activeset", "-gap", "exact"] + QUIET),
    "bowl_outside": ("bowl", COARSE + ["-T", "20", "-contact_label", "1", "-bowl_start", "75"]),
    "test2_coulomb_exact": ("test2", ["-T", "30", "-friction", "coulomb", "-friction_coefficient", "1", "-gap", "exact"] + QUIET),
}


@pytest.fixture(scope="module")
def gap_runs(tmp_path_factory):
    dirs = run_scenes(tmp_path_factory.mktemp("sliding"), RUNS)
    return {name: read_run(d) for name, d in dirs.items()} | {"dirs": dirs}


@pytest.mark.parametrize("name", ["bowl", "ball_bowl", "flat_exact", "bump_exact", "bump_neohookean", "wave_exact",
                                  "test2_coulomb_exact", "bowl_newmark", "bowl_np2"])
def test_the_exact_gap_holds_at_every_node_and_step(gap_runs, name):
    """-gap exact: no contact node below psi(X + u, t), and no pressed one above it, beyond the stated tolerance
    (1e-10 of the body's size), at any step: linear (the active set), Neo-Hookean (Newton), 2D and 3D, fixed and
    moving foundations, with Coulomb's friction on Test 2's."""
    h = gap_runs[name]
    assert h["max_penetration_exact"].max() <= EXACT_TOL, h["max_penetration_exact"].max()
    assert h["max_held_off_exact"].max() <= EXACT_TOL, h["max_held_off_exact"].max()
    assert (h["active_nodes"] > 0).any()


def test_the_paper_linearisation_misses_a_curved_foundation(gap_runs):
    """(10) on the bump (psi'' != 0): its history shows the error that max_penetration (against (10)'s own rows)
    cannot, a node 1e-3 of the size below the true psi, where -gap exact keeps every node on it."""
    h = gap_runs["bump_linearised"]
    assert h["max_penetration"].max() <= 1e-9
    assert h["max_penetration_exact"].max() > 1e-4 * SIZE


def test_a_flat_foundation_gives_the_same_result_under_both_gaps(gap_runs):
    """On a flat foundation (10) is exact: -gap exact (its rows rebuilt about every iterate) gives the linearised
    run's history to round-off, and its result needs no second round."""
    a, b = gap_runs["flat_exact"], gap_runs["flat_linearised"]
    for column in ("u2_low", "v2_low", "contact_force_y", "energy", "v1_mean", "v2_mean"):
        assert np.abs(a[column] - b[column]).max() <= 1e-9 * max(1.0, np.abs(b[column]).max()), column
    assert int(read_summary(gap_runs["dirs"]["flat_exact"])["exact_gap_rounds"]) == 0


def test_ipopt_imposes_the_exact_constraint_as_it_is(gap_runs):
    """-solver ipopt solves the step under the non-linear constraint psi(X + x) - x_up <= X_up itself, with its Jacobian
    and the Lagrangian's Hessian: one solve a step (no rounds), the active set's result to IPOPT's tolerance and the
    same pressed nodes, on the bowl's first 50 steps."""
    a, b = gap_runs["bowl_ipopt"], gap_runs["bowl"]
    n = len(a["t"])
    for column in ("v1_mean", "v2_mean"):
        assert np.abs(a[column] - b[column][:n]).max() <= 1e-8, column
    assert (a["active_nodes"] == b["active_nodes"][:n]).all()
    assert a["max_penetration_exact"].max() <= EXACT_TOL and a["max_held_off_exact"].max() <= 1e-9 * SIZE
    assert int(read_summary(gap_runs["dirs"]["bowl_ipopt"])["exact_gap_rounds"]) == 0


def test_the_exact_gap_on_two_processes_is_the_serial_run(gap_runs):
    """-np 2 (ffddm's solves with A to 1e-12): the bowl's first 10 steps equal the serial run's to the Krylov
    tolerance, with the same pressed nodes and the same rounds."""
    a, b = gap_runs["bowl_np2"], gap_runs["bowl"]
    n = len(a["t"])
    for column in ("v1_mean", "v2_mean", "u2_low"):
        assert np.abs(a[column] - b[column][:n]).max() <= 1e-9, column
    assert (a["active_nodes"] == b["active_nodes"][:n]).all()


def test_the_energy_guard_stays_on_where_the_true_foundation_has_not_risen(gap_runs):
    """Prop. 2's guard (watch/guards.idp) is on while the foundation has not risen under u^n. Under -gap exact that is
    psi at X + u^n, not (10)'s rows: Test 2 with its descent after T keeps the guard on (the checkpoint's 21st field)."""
    header = open(os.path.join(gap_runs["dirs"]["test2_still_exact"], "checkpoint.txt")).readline().split()
    assert header[20] == "1"


def test_the_watch_outside_gamma_c_reads_the_true_foundation(gap_runs):
    """With Gamma_C the disk's lower third, released at 75 degrees the disk meets the bowl outside it: the watch of the
    other boundary nodes (max_penetration_outside) measures them against psi(X + u), where they are, not (10)'s
    rows, and finds them 1 deep."""
    h = gap_runs["bowl_outside"]
    assert h["max_penetration_outside"].max() > 0.5


@pytest.mark.parametrize("name, inertia", [("bowl", 1.0), ("ball_bowl", 1.0)])
def test_the_frictionless_bowl_swings_with_the_pendulum_period(gap_runs, name, inertia):
    """Frictionless in the bowl (R_b = 60, the centre at 30 degrees), the body slides without turning and its centre
    swings as a pendulum of length L = R_b - r: P = 4 sqrt(L / g) K(sin(theta0 / 2)), within 1% on the coarse disk and
    on the ball at dt = 0.4."""
    period = sliding.period_of(gap_runs[name])
    assert abs(period / sliding.pendulum_period(inertia) - 1) < 0.01, period


@pytest.mark.parametrize("name", ["bowl", "ball_bowl"])
def test_prop_2_holds_in_the_convex_bowl(gap_runs, name):
    """Prop. 2 with the exact gap: in a convex bowl the exact constraint set is convex, u^n lies in it and in every
    linearisation of it, so the modified energy cannot rise (to the solves' round-off)."""
    m = gap_runs[name]["modified_energy"]
    assert np.diff(m).max() <= 1e-9 * abs(m[0])


def test_the_closed_form_period():
    """K(sin 15 deg) = 1.598142002 (Abramowitz and Stegun, table 17.1): the closed forms' periods."""
    assert abs(sliding.elliptic_k(np.sin(np.radians(15))) - 1.598142002) < 1e-8
    assert abs(sliding.pendulum_period(1.0) - 4 * 20 * 1.598142002) < 1e-6


@pytest.mark.parametrize("extra", [[], ["-material", "neohookean", "-friction", "coulomb", "-friction_coefficient", "0.5"],
                                   ["-scheme", "newmark"]],
                         ids=["linear", "neohookean_coulomb", "newmark"])
def test_an_exact_gap_run_restarts_to_the_bit(tmp_path, extra):
    """A -gap exact run restarted at t = 10 gives the uninterrupted run's history.csv and checkpoint.txt byte for
    byte (the rows are linearised about u^n first, a function of the checkpoint's state): the linear body's rounds,
    and Newton's rows about its iterates with Coulomb's friction."""
    restart_reproduces("bowl", tmp_path, COARSE + extra + ["-checkpoint_every", "25"], 10, 20)


@pytest.mark.parametrize("args, line", [
    (["-gap", "exact", "-contact", "penalty"],
     "error: -gap exact with -contact penalty is not supported: the exact gap is imposed as a constraint, with -contact "
     "constraint; penalty's term acts on the gap of (10)"),
    (["-gap", "exact", "-contact", "nitsche"],
     "error: -gap exact with -contact nitsche is not supported: the exact gap is imposed as a constraint, with -contact "
     "constraint; nitsche's term acts on the gap of (10)"),
    (["-gap", "sideways"], "error: -gap must be linearised or exact; got 'sideways'"),
    (["-foundation", "bowl", "-bowl_radius", "20"], "error: -bowl_radius must be >= 30 (foundation.csv draws psi on [-30, 30]), got 20"),
])
def test_gap_refusals(tmp_path, earlier_run, args, line):
    """Each refusal is one line, exit 3, and the earlier run's files stay as they were."""
    p, changed = refused_into_copy(tmp_path, earlier_run, "test1", args + ["-T", "1"])
    assert p.returncode == 3 and error_lines(p) == [line], p.stderr
    assert not changed


def test_an_initial_state_below_the_bowl_is_refused(tmp_path, earlier_run):
    """-gap exact checks the initial state against the true psi: the disk lowered by 0.5 into the bowl is refused."""
    p, changed = refused_into_copy(tmp_path, earlier_run, "bowl", COARSE + ["-u0y", "5"])
    assert p.returncode == 3 and len(error_lines(p)) == 1, p.stderr
    assert error_lines(p)[0].startswith("error: the initial state penetrates the foundation psi(X + u) by "), p.stderr
    assert not changed
