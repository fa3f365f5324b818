"""The disk mesh of meshes/disk.geo against the paper (Section 4.1)."""
import os

from conftest import ROOT
from mesh_counts import msh22_counts


def test_paper_mesh_counts():
    v, t, c, n = msh22_counts(os.path.join(ROOT, "meshes", "disk.msh"))
    print(f"meshes/disk.msh: {v} vertices, {t} triangles (paper: 989, 1864)")
    assert abs(v - 989) <= 0.01 * 989 and abs(t - 1864) <= 0.01 * 1864
    assert (c, n) == (48, 64)


def test_refined_meshes_keep_the_geometry():
    coarse = msh22_counts(os.path.join(ROOT, "meshes", "disk_coarse.msh"))
    fine = msh22_counts(os.path.join(ROOT, "meshes", "disk_fine.msh"))
    assert coarse[2:] == (24, 32) and fine[2:] == (96, 128)
    assert coarse[0] < 989 < fine[0]
