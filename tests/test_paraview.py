"""The ParaView time series of a run (issue 24): OUT/run.pvd and the .vtu files it lists,
read back by a real VTK reader (meshio), for every kind of run: P1 and P2, the three
materials, a fixed and a moving foundation (Test 1, Test 2), Nitsche on Gauss points,
a clamped body, a scene without foundation. Each .vtu must carry what history.csv
records at the same time, so the file a user opens in ParaView shows the run that was
computed: u at the reference point (eq. (1)-(2)'s u^n) and the contact pressure alpha of
eq. (6) there; the foundation dataset must be psi(X1, t) of foundation.csv."""
import os
import re
import xml.etree.ElementTree as ET

import meshio
import numpy as np
import pytest

from conftest import COARSE, files_of, run_scene, run_scenes
from history import read_run

EVERY = ["-snapshots", "every:2", "-progress", "0"]
SERIES_RUNS = {
    "p1_test1": ("test1", ["-T", "14", "-solver", "activeset"] + EVERY),
    "p2_test1": ("test1", ["-T", "14", "-order", "2", "-solver", "activeset", "-mesh", COARSE] + EVERY),
    "svk_test1": ("test1", ["-T", "14", "-material", "svk"] + EVERY),
    "neohookean_test1": ("test1", ["-T", "14", "-material", "neohookean"] + EVERY),
    "test2_moving": ("test2", ["-T", "20", "-t1", "18", "-solver", "activeset"] + EVERY),
    "nitsche_gauss_test2": ("test2", ["-T", "14", "-contact", "nitsche", "-contact_quadrature", "gauss"] + EVERY),
    "cantilever": ("cantilever", ["-T", "4", "-solver", "activeset"] + EVERY),
    "freeflight": ("freeflight", ["-T", "4"] + EVERY),
}


@pytest.fixture(scope="module")
def series_runs(tmp_path_factory):
    return run_scenes(tmp_path_factory.mktemp("series"), SERIES_RUNS)


def read_series(out):
    """run.pvd as [(time text, part, file)], checked to be a VTK Collection."""
    root = ET.parse(os.path.join(out, "run.pvd")).getroot()
    assert root.tag == "VTKFile" and root.get("type") == "Collection"
    return [(d.get("timestep"), int(d.get("part")), d.get("file")) for d in root.find("Collection")]


def recorded(out, key):
    """A -key value line of parameters.txt."""
    return re.search(rf"^-{key} (.*)$", open(os.path.join(out, "parameters.txt")).read(), re.M).group(1)


def body_nodes(out, order):
    """The body's nodes from mesh.msh (FreeFEM's format: nv nt nbe): its vertices for P1;
    for P2 the vertices and the edges' midpoints, nv + (3 nt + nbe) / 2."""
    nv, nt, nbe = map(int, open(os.path.join(out, "mesh.msh")).readline().split())
    return nv if order == 1 else nv + (3 * nt + nbe) // 2


@pytest.mark.parametrize("name", SERIES_RUNS)
def test_series_lists_every_snapshot_once_with_its_time(series_runs, name):
    """run.pvd lists the body at every snapshot time of the run (0, 2, 4, ... up to T), once each,
    in order, and the foundation beside it exactly when the scene has one."""
    out = series_runs[name]
    entries = read_series(out)
    times = recorded(out, "snapshots").split(",")
    T = float(recorded(out, "T"))
    assert [float(t) for t in times] == [2.0 * k for k in range(int(T // 2) + 1)]
    has_foundation = os.path.exists(os.path.join(out, "foundation.csv"))
    expected = [(t, 0, f"vonmises_t{t}.vtu") for t in times]
    if has_foundation:
        expected = [e for t in times for e in ((t, 0, f"vonmises_t{t}.vtu"), (t, 1, f"foundation_t{t}.vtu"))]
    assert entries == expected
    listed = {f for _, _, f in entries}
    on_disk = {f for f in os.listdir(out) if f.endswith(".vtu")}
    assert listed == on_disk, "every .vtu of the run is in run.pvd, and nothing else"


@pytest.mark.parametrize("name", SERIES_RUNS)
def test_body_fields_equal_the_history_at_the_reference_point(series_runs, name):
    """Each body .vtu has the body's nodes (P2: vertices and midpoints), the fields a ParaView user
    needs (a 3-component displacement for Warp By Vector, von Mises, the largest strain, the contact
    pressure), and its displacement and contact pressure at the reference point are history.csv's
    u1_low, u2_low and contact_pressure_low at that time (the same u^n and alpha of eq. (6))."""
    out = series_runs[name]
    h = read_run(out)
    order = int(recorded(out, "order"))
    ref = np.array([float(c) for c in recorded(out, "reference").split(",")])
    for t, part, f in read_series(out):
        if part != 0:
            continue
        m = meshio.read(os.path.join(out, f))
        assert len(m.points) == body_nodes(out, order)
        assert {"displacement", "vonmises_vertex", "max_strain_vertex", "contact_pressure"} <= set(m.point_data)
        assert {"vonmises", "max_strain"} <= set(m.cell_data)
        disp = m.point_data["displacement"]
        assert disp.shape == (len(m.points), 3) and not disp[:, 2].any()
        for field in ("vonmises_vertex", "max_strain_vertex", "contact_pressure"):
            assert np.isfinite(m.point_data[field]).all()
        i = int(np.argmin(np.hypot(*(m.points[:, :2] - ref).T)))
        assert np.hypot(*(m.points[i, :2] - ref)) < 1e-5
        k = int(np.argmin(abs(h["t"] - float(t))))
        assert abs(h["t"][k] - float(t)) < 1e-9
        scale = max(1.0, abs(h["u2_low"]).max())
        assert abs(disp[i, 0] - h["u1_low"][k]) <= 1e-13 * scale and abs(disp[i, 1] - h["u2_low"][k]) <= 1e-13 * scale
        pressure = m.point_data["contact_pressure"]
        assert abs(pressure[i] - h["contact_pressure_low"][k]) <= 1e-12 * max(1.0, abs(h["contact_pressure_low"]).max())
        assert (pressure >= -1e-9 * max(1.0, pressure.max())).all() or "nitsche" in name or "penalty" in name


@pytest.mark.parametrize("name", [n for n in SERIES_RUNS if n != "freeflight"])
def test_foundation_dataset_is_psi_at_that_time(series_runs, name):
    """The foundation dataset at time t is the polyline X2 = psi(X1, t) (foundation.csv, written
    from the same psi), under the body and wider than it, with a zero displacement so that Warp By
    Vector on the whole series moves the body only. In Test 2 it moves down between t0 and t1."""
    out = series_runs[name]
    table = np.genfromtxt(os.path.join(out, "foundation.csv"), delimiter=",", names=True)
    below_centre = []      # psi under X1 = 0
    for t, part, f in read_series(out):
        if part != 1:
            continue
        m = meshio.read(os.path.join(out, f))
        assert list(m.cells_dict) == ["line"] and len(m.cells_dict["line"]) == len(m.points) - 1
        assert not m.point_data["displacement"].any()
        rows = table[abs(table["t"] - float(t)) < 1e-9]
        inside = (m.points[:, 0] >= rows["X1"].min()) & (m.points[:, 0] <= rows["X1"].max())
        assert inside.sum() > 10
        psi = np.interp(m.points[inside, 0], rows["X1"], rows["psi"])
        # (foundation.csv samples every 0.5: a curved psi differs from its chords by < 0.5^2 |psi''| / 8)
        assert np.abs(m.points[inside, 1] - psi).max() < 1e-3
        body = meshio.read(os.path.join(out, f"vonmises_t{t}.vtu"))
        x = body.points[:, 0] + body.point_data["displacement"][:, 0]
        assert m.points[:, 0].min() < x.min() and m.points[:, 0].max() > x.max()
        below_centre.append(m.points[np.argmin(abs(m.points[:, 0])), 1])
    if name == "test2_moving":
        assert below_centre[-1] < below_centre[0] - 1, "the foundation of Test 2 moved down"


def test_restart_leaves_one_series_equal_to_the_uninterrupted_one(tmp_path):
    """A run stopped past its last checkpoint (snapshots at 3.5 and 4 after the checkpoint at
    t = 3) and restarted to a later T lists every time once, and its run.pvd and .vtu files are
    byte-identical to those of one uninterrupted run; so is a restart into another directory."""
    args = ["-T", "4", "-snapshots", "every:0.5", "-checkpoint_every", "60", "-progress", "0"]
    first = tmp_path / "first"
    run_scene("test1", first, args)
    run_scene("test1", first, ["-restart", str(first), "-T", "6", "-snapshots", "every:0.5", "-progress", "0"])
    other = tmp_path / "other"
    run_scene("test1", other, ["-restart", str(first), "-T", "7", "-snapshots", "every:0.5", "-progress", "0"])
    straight = tmp_path / "straight"
    run_scene("test1", straight, ["-T", "6"] + args[2:])
    entries = read_series(str(first))
    assert [t for t, part, _ in entries if part == 0] == [f"{0.5 * k:g}" for k in range(13)]
    series = {f: b for f, b in files_of(straight).items() if f.endswith((".vtu", ".pvd"))}
    assert {f: b for f, b in files_of(first).items() if f.endswith((".vtu", ".pvd"))} == series
    times = [t for t, part, _ in read_series(str(other)) if part == 0]
    assert times == [f"{0.5 * k:g}" for k in range(15)] and len(set(times)) == len(times)
    assert {f for f in os.listdir(other) if f.endswith(".vtu")} == {f for _, _, f in read_series(str(other))}


def test_vtk_0_writes_no_series_and_removes_the_earlier_one(tmp_path, earlier_run):
    """-vtk 0 writes no .vtu and no run.pvd; replacing a run that had them removes them, so no
    series of another run is left beside the new one."""
    assert os.path.exists(os.path.join(earlier_run, "run.pvd"))
    out = tmp_path / "copy"
    import shutil
    shutil.copytree(earlier_run, out)
    run_scene("test1", out, ["-T", "0.5", "-vtk", "0", "-snapshots", "0", "-progress", "0"])
    assert not [f for f in os.listdir(out) if f.endswith((".vtu", ".pvd"))]


def test_a_run_restarted_with_vtk_1_can_be_restarted_again(tmp_path):
    """A run without .vtu files restarted with -vtk 1 writes them from the restart on; a later restart keeps the
    .vtu files the run wrote (its run.pvd lists them) and needs none before them (before, it was refused: 'its
    vonmises_t0.vtu is missing'). Every time of run.pvd has its files."""
    out = tmp_path / "run"
    run_scene("test1", out, ["-T", "1", "-vtk", "0", "-snapshots", "every:0.25", "-checkpoint_every", "10", "-progress", "0"])
    run_scene("test1", out, ["-restart", str(out), "-T", "2", "-vtk", "1", "-snapshots", "every:0.25"])
    run_scene("test1", out, ["-restart", str(out), "-T", "3", "-snapshots", "every:0.25"])
    times = [t for t, part, _ in read_series(str(out)) if part == 0]
    assert times == [f"{0.25 * k:g}" for k in range(5, 13)]
    assert {f for f in os.listdir(out) if f.endswith(".vtu")} == {f for _, _, f in read_series(str(out))}
