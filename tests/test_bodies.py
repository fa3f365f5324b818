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


def test_the_short_bar_stops_and_the_long_one_carries_the_momentum(bars_1_2):
    """Bars L and 2L, the short one striking the long one at rest: after 2L/c = 2 the short bar is at rest and the long
    one carries all the momentum, m v0 = 0.1, so its mean velocity is v0 / 2, exactly; here within 2% of v0 (h = 0.5,
    dt = 0.05; docs/bodies.md)."""
    v0 = 0.01
    assert abs(bars_1_2["body1_v1_mean"][-1]) <= 0.02 * v0
    assert abs(bars_1_2["body2_v1_mean"][-1] - v0 / 2) <= 0.02 * v0 / 2
    assert np.abs(bars_1_2["momentum_x"] - 0.1).max() <= 1e-12 * 0.1


def test_restart_of_two_bars_is_bit_identical(tmp_path):
    """A run of two bars to t = 1.5 (mid-impact) restarted to 2.5 writes the history and checkpoint of one run to
    2.5, byte for byte."""
    restart_reproduces("bars", tmp_path, ["-progress", "0", "-checkpoint_every", "10"], 1.5, 2.5)


REFUSED = {
    "a list of the wrong length": ("bars", ["-v0x", "0.01,-0.01,0"],
                                   "-v0x 0.01,-0.01,0 gives 3 values, and -mesh meshes/bars.msh holds 2 bodies"),
    "a list on a mesh of one body": ("test1", ["-v0x", "0.1,0.2"], "-v0x 0.1,0.2 gives 2 values, and -mesh "),
    "an empty value in a list": ("bars", ["-v0x", "0.01,"], "-v0x 0.01, has an empty value"),
    "a value that is not a number": ("bars", ["-v0x", "0.01,x"], "-v0x must be a number, got 'x'"),
    "several bodies under IPOPT": ("bars", ["-solver", "ipopt"], "holds 2 bodies, and contact between bodies is not "
                                   "available with -solver ipopt yet"),
    "several bodies under Newmark": ("bars", ["-scheme", "newmark"], "with -scheme newmark: it is the mid-point"),
    "several bodies with P2": ("bars", ["-order", "2"], "with -order 2 yet"),
    "several bodies on a foundation": ("bars", ["-foundation", "flat", "-contact_label", "2"], "with a foundation yet"),
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
