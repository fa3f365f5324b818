"""The disk mesh of meshes/disk.geo against the paper (Section 4.1), and every mesh
defect refused with exit 3 and one line naming the file and the defect, before
gmshload reads it (edp/lib/body/check_mesh.awk), with an earlier run byte-identical."""
import os
import subprocess

import pytest

from conftest import ROOT, refused_into_copy, run_scene, square_mesh
from mesh_counts import msh22_counts

PAPER_MESH = os.path.join(ROOT, "meshes", "disk.msh")


def test_paper_mesh_counts():
    v, t, c, n, d = msh22_counts(PAPER_MESH)
    print(f"meshes/disk.msh: {v} vertices, {t} triangles (paper: 989, 1864)")
    assert abs(v - 989) <= 0.01 * 989 and abs(t - 1864) <= 0.01 * 1864
    assert (c, n, d) == (48, 64, 0)


def test_refined_meshes_keep_the_geometry():
    coarse = msh22_counts(os.path.join(ROOT, "meshes", "disk_coarse.msh"))
    fine = msh22_counts(os.path.join(ROOT, "meshes", "disk_fine.msh"))
    assert coarse[2:] == (24, 32, 0) and fine[2:] == (96, 128, 0)
    assert coarse[0] < 989 < fine[0]


def paper_lines():
    return open(PAPER_MESH).read().split("\n")


def first_triangle(lines):
    k = lines.index("$Elements") + 2
    while lines[k].split()[1] != "2":
        k += 1
    return k


def truncated_in(section):
    lines = paper_lines()
    k = lines.index(section) + 100
    return "\n".join(lines[:k]) + "\n"


def flipped_triangle():
    lines = paper_lines()
    k = first_triangle(lines)
    f = lines[k].split()
    f[-1], f[-2] = f[-2], f[-1]
    lines[k] = " ".join(f)
    return "\n".join(lines)


def degenerate_triangle():
    lines = paper_lines()
    k = first_triangle(lines)
    f = lines[k].split()
    f[-1] = f[-2]
    lines[k] = " ".join(f)
    return "\n".join(lines)


def binary():
    return "$MeshFormat\n2.2 1 8\n\x01\x00\x00\x00\n$EndMeshFormat\n"


def quadrangles():
    lines = paper_lines()
    k = first_triangle(lines)
    f = lines[k].split()
    lines[k] = " ".join([f[0], "3", "2", "1", "1", f[-3], f[-2], f[-1], f[-1]])
    return "\n".join(lines)


def tiny():
    """The paper's mesh scaled by 1e-5: every triangle below gmshload's 1e-8."""
    lines = paper_lines()
    k = lines.index("$Nodes") + 2
    for i in range(k, k + int(lines[k - 1])):
        f = lines[i].split()
        lines[i] = " ".join([f[0], repr(float(f[1]) * 1e-5), repr(float(f[2]) * 1e-5), f[3]])
    return "\n".join(lines)


def all_clockwise():
    """Every triangle of the paper's mesh clockwise: a body whose curve loop is drawn clockwise."""
    lines = paper_lines()
    k = lines.index("$Elements") + 2
    for i in range(k, k + int(lines[k - 1])):
        f = lines[i].split()
        if f[1] == "2":
            f[-1], f[-2] = f[-2], f[-1]
            lines[i] = " ".join(f)
    return "\n".join(lines)


def with_node(z=None, orphan=False, point=False, tetrahedron=False):
    """The paper's mesh with one change: the first node lifted to z (a non-planar, 3D mesh), an
    extra node in no triangle (orphan), that node as a gmsh Physical Point (point), or a
    tetrahedron among the elements."""
    lines = paper_lines()
    k = lines.index("$Nodes") + 1
    n = int(lines[k])
    if z is not None:
        f = lines[k + 1].split()
        lines[k + 1] = " ".join(f[:3] + [z])
    if orphan or point:
        lines[k] = str(n + 1)
        lines.insert(k + 1 + n, f"{n + 1} 100 100 0")
    e = lines.index("$Elements") + 1
    m = int(lines[e])
    if point:
        lines[e] = str(m + 1)
        lines.insert(e + 1 + m, f"{m + 1} 15 2 5 5 {n + 1}")
    if tetrahedron:
        lines[e] = str(m + 1)
        lines.insert(e + 1 + m, f"{m + 1} 4 2 1 1 1 2 3 4")
    return "\n".join(lines)


DEFECTS = {
    "truncated in $Nodes": (lambda: truncated_in("$Nodes"), "truncated in $Nodes: 98 of 989 nodes, no $EndNodes"),
    "truncated in $Elements": (lambda: truncated_in("$Elements"), "truncated in $Elements: 98 of 1976 elements, no $EndElements"),
    "binary": (binary, "binary MSH 2.2; FreeFEM's gmshload reads ASCII only"),
    "inverted triangle": (flipped_triangle, "is inverted (clockwise"),
    "degenerate triangle": (degenerate_triangle, "is degenerate (area 0)"),
    "quadrangle": (quadrangles, "has type 3; only points (15), 2-node lines (1) and 3-node triangles (2) are supported"),
    "not a mesh": (lambda: "not a mesh\n", "not a gmsh MSH file (its first line is not $MeshFormat)"),
    "MSH 4.1": (lambda: "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n", "MSH version 4.1, not 2.2"),
    "empty": (lambda: "", "the file is empty"),
    "tiny triangles": (tiny, "below the 1e-8 that FreeFEM's gmshload accepts"),
    # issue 19: before, run as the xy projection, or failing later as a singular system (exit 5)
    "non-planar": (lambda: with_node(z="0.5"), "its nodes span z from 0 to 0.5, not one plane, and it has no tetrahedra"),
    # a tetrahedron makes it a 3D mesh (issue 25), checked as one: this one is flat
    "tetrahedron": (lambda: with_node(tetrahedron=True), "tetrahedron 1977 is inverted or degenerate (volume 0)"),
    "every triangle clockwise": (all_clockwise, "every triangle is clockwise: the body's curve loop is drawn clockwise in its "
                                                 ".geo; reverse it"),
    "orphan node": (lambda: with_node(orphan=True), "node 990 (at 100, 100) is in no triangle: an orphan node"),
    "point off the body": (lambda: with_node(point=True),
                           "node 990 (at 100, 100) of the point element 1977 (a gmsh Physical Point) is in no triangle"),
}


@pytest.mark.parametrize("defect", list(DEFECTS))
def test_mesh_defect_is_one_clear_error(tmp_path, earlier_run, defect):
    make, message = DEFECTS[defect]
    bad = tmp_path / "bad.msh"
    bad.write_text(make())
    p, changed = refused_into_copy(tmp_path, earlier_run, "test1", ["-mesh", str(bad), "-T", "1"])
    errors = [line for line in p.stderr.splitlines() if line.strip()]
    assert p.returncode == 3 and len(errors) == 1, p.stderr
    assert errors[0].startswith(f"error: -mesh {bad}: ") and message in errors[0], errors[0]
    assert not changed, f"{defect}: the earlier run's files changed"


def test_mesh_without_contact_label(tmp_path, earlier_run):
    msh = square_mesh(tmp_path / "square.msh", "Physical Curve(2)={1,2,3,4};")
    p, changed = refused_into_copy(tmp_path, earlier_run, "test1", ["-mesh", str(msh)])
    assert p.returncode == 3 and p.stderr.strip() == (f"error: -mesh {msh} has no boundary edge with label 1 (Gamma_C, "
                                                      "-contact_label), and -foundation flat needs one; its labels are 2")
    assert not changed


def test_mesh_without_physical_groups_says_so(tmp_path, earlier_run):
    """A .geo without Physical groups: gmsh saves every entity, the arc's centre among them, a point
    in no triangle. Refused naming the cause (review: it was called a Physical Point off the body;
    before issue 19 the run failed later with exit 5)."""
    geo = tmp_path / "nophys.geo"
    geo.write_text("".join(part.split("Physical")[0] if "Physical" in part else part
                           for part in open(os.path.join(ROOT, "meshes", "disk.geo")).read().splitlines(True)))
    msh = tmp_path / "nophys.msh"
    subprocess.run(["gmsh", "-2", "-format", "msh22", str(geo), "-o", str(msh)], check=True, capture_output=True)
    p, changed = refused_into_copy(tmp_path, earlier_run, "test1", ["-mesh", str(msh), "-T", "1"])
    errors = [line for line in p.stderr.splitlines() if line.strip()]
    assert p.returncode == 3 and len(errors) == 1, p.stderr
    assert "is a geometric point in no physical group" in errors[0] and "add Physical Surface" in errors[0], errors[0]
    assert not changed


# ---- issue 32: what a mesh error names in 3D, and a scene's meshFile that edp/run.sh cannot read
BALL_GEO = os.path.join(ROOT, "meshes", "ball.geo")


def gmsh_file(tmp_path, name, args, geo=BALL_GEO):
    """gmsh ARGS of geo (coarse) into tmp_path/name; returns its path."""
    out = tmp_path / name
    subprocess.run(["gmsh"] + args + ["-setnumber", "refine", "0.3", geo, "-o", str(out)], check=True, capture_output=True)
    return out


@pytest.mark.parametrize("args,hint", [
    (["-3", "-format", "msh41"], "MSH version 4.1, not 2.2 (write it with gmsh -3 -format msh22)"),
    (["-2", "-format", "msh41"], "MSH version 4.1, not 2.2 (write it with gmsh -3 -format msh22)"),   # its volume unmeshed
    (["-3", "-format", "msh41", "-bin"], "binary MSH version 4.1, not 2.2 (write it with gmsh -format msh22 and without -bin: "
                                         "gmsh -2 for a plane body, -3 for a volume)"),
], ids=["3d", "3d geometry meshed -2", "3d binary"])
def test_msh41_of_a_volume_is_told_gmsh_3(tmp_path, earlier_run, args, hint):
    """A MSH 4.1 file of a geometry with volumes ($Entities counts them) is told to write it with gmsh -3:
    the hint was gmsh -2, which gives a surface mesh. A binary one, whose $Entities is not read, is told both."""
    msh = gmsh_file(tmp_path, "ball41.msh", args)
    p, changed = refused_into_copy(tmp_path, earlier_run, "test1", ["-mesh", str(msh), "-T", "1"])
    errors = [line for line in p.stderr.splitlines() if line.strip()]
    assert p.returncode == 3 and errors == [f"error: -mesh {msh}: {hint}"], p.stderr
    assert not changed


def test_msh41_of_a_plane_body_is_told_gmsh_2(tmp_path, earlier_run):
    msh = gmsh_file(tmp_path, "disk41.msh", ["-2", "-format", "msh41"], geo=os.path.join(ROOT, "meshes", "disk.geo"))
    p, changed = refused_into_copy(tmp_path, earlier_run, "test1", ["-mesh", str(msh), "-T", "1"])
    assert p.returncode == 3 and p.stderr.strip() == f"error: -mesh {msh}: MSH version 4.1, not 2.2 (write it with gmsh -2 " \
                                                     "-format msh22)", p.stderr
    assert not changed


def ball_with_node(tmp_path, physical=None):
    """The coarse ball (MSH 2.2) with an extra node at (100, 100, 100) in no tetrahedron, as a point element of
    that physical group when physical is given (0: a point saved without Physical groups)."""
    lines = open(gmsh_file(tmp_path, "ball.msh", ["-3", "-format", "msh22"])).read().splitlines()
    k = lines.index("$Nodes") + 1
    n = int(lines[k])
    lines[k] = str(n + 1)
    lines.insert(k + 1 + n, f"{n + 1} 100 100 100")
    if physical is not None:
        e = lines.index("$Elements") + 1
        m = int(lines[e])
        lines[e] = str(m + 1)
        lines.insert(e + 1 + m, f"{m + 1} 15 2 {physical} 5 {n + 1}")
    out = tmp_path / "ball_node.msh"
    out.write_text("\n".join(lines) + "\n")
    return out, n + 1


@pytest.mark.parametrize("physical,message", [
    (None, "(at 100, 100, 100) is in no tetrahedron: an orphan node"),
    (5, "(at 100, 100, 100) of the point element {m} (a gmsh Physical Point) is in no tetrahedron"),
    (0, "(at 100, 100, 100) is a geometric point in no physical group (element {m}, e.g. an arc's centre) and in no "
        "tetrahedron: the .geo defines no Physical groups, so gmsh saved every entity; add Physical Volume and Physical "
        "Surface lines to it"),
], ids=["orphan", "physical point", "no physical groups"])
def test_3d_node_in_no_tetrahedron_is_named_in_3d(tmp_path, physical, message):
    """A node of a 3D mesh in no tetrahedron is named with its three coordinates, as in no tetrahedron, and a .geo
    without Physical groups is told to add a Physical Volume (it was told "in no triangle", "Physical Curve")."""
    msh, node = ball_with_node(tmp_path, physical)
    elements = open(msh).read().split("$Elements\n")[1].split("\n")[0]
    p = run_scene("ball", tmp_path / "out", ["-mesh", str(msh), "-T", "0.1"], check=False)
    errors = [line for line in p.stderr.splitlines() if line.strip()]
    assert p.returncode == 3 and len(errors) == 1, p.stderr
    assert errors[0].startswith(f"error: -mesh {msh}: node {node} " + message.format(m=elements)), errors[0]
    assert not (tmp_path / "out").exists()


MESHFILE_FORMS = {
    "one line with another statement": 'T = 0.1; meshFile = "meshes/ball.msh";\n',
    "through a variable": 'string m = "meshes/ball.msh";\nmeshFile = m;\nT = 0.1;\n',
    "concatenated": 'meshFile = "meshes/" + "ball.msh";\nT = 0.1;\n',
}


@pytest.mark.parametrize("form", list(MESHFILE_FORMS))
def test_scene_meshfile_in_any_form_compiles_its_dimension(tmp_path, form):
    """A scene that sets meshFile in any form runs on that mesh, compiled for its dimension: edp/run.sh reads the
    mesh as the driver does (edp/lib/run/choices.edp) before FreeFEM compiles the driver."""
    scene = tmp_path / "ball_meshfile.idp"
    scene.write_text(MESHFILE_FORMS[form] + 'snapshots = "none";\nfy = 0;\nfz = -0.1;\nu0y = 0;\nu0z = 4;\n')
    p = run_scene(str(scene), tmp_path / "out", ["-progress", "0"])
    assert p.stdout.startswith("mesh meshes/ball.msh: ") and " tetrahedra, " in p.stdout.splitlines()[0], p.stdout


def test_scene_meshfile_set_from_the_dimension_is_named(tmp_path, earlier_run):
    """A scene whose meshFile depends on the dimension compiled for: edp/run.sh reads it as for a plane body (the
    ball), and the driver, compiled for a 3D body, is given the disk; it says so in one line."""
    scene = tmp_path / "disk_meshfile.idp"
    scene.write_text('meshFile = (dimension == 2 ? "meshes/ball.msh" : "meshes/disk.msh");\nT = 0.1;\nsnapshots = "none";\n')
    p, changed = refused_into_copy(tmp_path, earlier_run, str(scene), ["-progress", "0"])
    errors = [line for line in p.stderr.splitlines() if line.strip()]
    assert p.returncode == 3 and len(errors) == 1, p.stderr
    assert errors[0].startswith("error: -mesh meshes/disk.msh has no volume elements (a plane body), but meshFile is set "
                                "in a way edp/run.sh cannot read") and "compiled for a 3D body" in errors[0], errors[0]
    assert not changed


@pytest.mark.parametrize("mesh", ["meshes", ""], ids=["a directory", "empty"])
def test_a_mesh_that_is_a_directory_is_named(tmp_path, earlier_run, mesh):
    """-mesh naming a directory (an empty -mesh is the caller's directory) is refused in one line naming it, exit 3,
    the earlier run byte-identical (awk's own read error used to end the run with exit 3 and no line)."""
    p, changed = refused_into_copy(tmp_path, earlier_run, "test1", ["-mesh", mesh, "-T", "0.1", "-progress", "0"],
                                   cwd=ROOT)
    errors = [line for line in p.stderr.splitlines() if line.strip()]
    assert p.returncode == 3 and len(errors) == 1, p.stderr
    assert errors[0].startswith(f"error: -mesh '{mesh}' names a directory (") and errors[0].endswith("), not a mesh file")
    assert not changed



# two squares side by side (x in [0, 2]): one Physical Surface each, sharing the nodes of their common edge (two bodies
# glued there), or apart (x in [0, 1] and [2, 3]) in one Physical Surface (one body in two pieces)
TWO_BODIES = {
    "two labels": ("Point(1)={0,0,0,0.5};Point(2)={1,0,0,0.5};Point(3)={2,0,0,0.5};Point(4)={2,1,0,0.5};"
                   "Point(5)={1,1,0,0.5};Point(6)={0,1,0,0.5};Line(1)={1,2};Line(2)={2,3};Line(3)={3,4};Line(4)={4,5};"
                   "Line(5)={5,6};Line(6)={6,1};Line(7)={2,5};Curve Loop(1)={1,7,5,6};Plane Surface(1)={1};"
                   "Curve Loop(2)={2,3,4,-7};Plane Surface(2)={2};Physical Surface(1)={1};Physical Surface(2)={2};"
                   "Physical Curve(1)={1,2};Physical Curve(2)={3,4,5,6};",
                   "is in the triangles of two bodies, Physical Surface labels 1 and 2: each body needs its own nodes"),
    "two pieces": ("Point(1)={0,0,0,0.5};Point(2)={1,0,0,0.5};Point(3)={1,1,0,0.5};Point(4)={0,1,0,0.5};"
                   "Point(5)={2,0,0,0.5};Point(6)={3,0,0,0.5};Point(7)={3,1,0,0.5};Point(8)={2,1,0,0.5};"
                   "Line(1)={1,2};Line(2)={2,3};Line(3)={3,4};Line(4)={4,1};Line(5)={5,6};Line(6)={6,7};Line(7)={7,8};"
                   "Line(8)={8,5};Curve Loop(1)={1,2,3,4};Plane Surface(1)={1};Curve Loop(2)={5,6,7,8};"
                   "Plane Surface(2)={2};Physical Surface(1)={1,2};Physical Curve(1)={1,5};Physical Curve(2)={2,3,4,6,7,8};",
                   "the body of Physical Surface label 1 is 2 pieces that share no node, one at ("),
}


@pytest.mark.parametrize("kind", list(TWO_BODIES))
def test_glued_bodies_and_a_body_in_pieces_are_refused(tmp_path, earlier_run, kind):
    """Each Physical Surface label is one body (docs/bodies.md): two bodies that share nodes (which would run glued
    there) and one label whose triangles form two pieces (which would pass through each other: contact is between
    bodies) are refused in one line, exit 3, before anything changes."""
    geo_text, message = TWO_BODIES[kind]
    geo = tmp_path / "two.geo"
    geo.write_text(geo_text + "\n")
    msh = tmp_path / "two.msh"
    subprocess.run(["gmsh", "-2", "-format", "msh22", str(geo), "-o", str(msh)], check=True, capture_output=True)
    p, changed = refused_into_copy(tmp_path, earlier_run, "test1", ["-mesh", str(msh), "-T", "1"])
    errors = [line for line in p.stderr.splitlines() if line.strip()]
    assert p.returncode == 3 and len(errors) == 1 and message in errors[0], p.stderr
    assert not changed
