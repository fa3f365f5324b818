"""The 3D ball's meshes (meshes/ball.geo, hertz.geo) as gmsh writes them: the lowest point
(0, 0, 0) a vertex, Gamma_C (label 1) exactly the sphere below X3 = 10, outward boundary triangles, positive
tetrahedra, and the sizes their comments state; hertz.msh resolves Hertz's contact radius at v0/c* = 1e-3
(a*/h >= 4). Reads the .msh files that make meshes builds; no FreeFEM."""
import math
import os

import numpy as np
import pytest

from conftest import ROOT

import hertz_analysis
from mesh_counts import msh22_read

R = 20.0
# mesh: (fewest, most vertices)
MESHES = {"ball.msh": (500, 1500), "hertz.msh": (10000, 13000), "hertz_coarse.msh": (300, 800)}


def load(name):
    path = os.path.join(ROOT, "meshes", name)
    if not os.path.exists(path):
        pytest.skip(f"meshes/{name} not built (make meshes)")
    nodes, elements = msh22_read(path)
    return np.array(nodes), {key: np.array(e) for key, e in elements.items()}


@pytest.mark.parametrize("name", MESHES)
def test_ball_mesh(name):
    """Vertices in the stated range; (0, 0, 0) a vertex, the lowest, on Gamma_C; label 1 triangles all at
    X3 <= 10 and label 2 at X3 >= 10, with the areas of their spherical zones (2 pi R 10, 2 pi R 30) to 5%,
    all on the sphere and oriented outward; tetrahedra positive, the ball's volume to 6% (coarse meshes cut
    the sphere short); nothing else labelled."""
    x, elements = load(name)
    fewest, most = MESHES[name]
    print(f"meshes/{name}: {len(x)} vertices, {len(elements[(4, 1)])} tetrahedra")
    assert fewest <= len(x) <= most
    assert set(elements) == {(2, 1), (2, 2), (4, 1)}
    pole = np.nonzero(np.all(x == 0, axis=1))[0]
    assert len(pole) == 1 and x[:, 2].min() == 0 and pole[0] in elements[(2, 1)]
    for label, (lo, hi), zone in ((1, (0, 10), 10), (2, (10, 40), 30)):
        tri = elements[(2, label)]
        p = x[tri]
        assert p[:, :, 2].min() >= lo and p[:, :, 2].max() <= hi
        assert np.abs(np.linalg.norm(p - [0, 0, R], axis=2) - R).max() < 1e-12
        normal = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
        assert np.all(np.einsum("ij,ij->i", normal, p.mean(axis=1) - [0, 0, R]) > 0)
        assert np.linalg.norm(normal, axis=1).sum() / 2 == pytest.approx(2 * math.pi * R * zone, rel=0.05)
    p = x[elements[(4, 1)]]
    volume = np.einsum("ij,ij->i", np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), p[:, 3] - p[:, 0]) / 6
    assert volume.min() > 0 and volume.sum() == pytest.approx(4 / 3 * math.pi * R ** 3, rel=0.06)


def test_hertz_mesh_resolves_the_contact():
    """hertz.msh's default grading gives a*/h >= 4 at v0/c* = 1e-3 (make hertz's target mesh; h the mean edge of
    Gamma_C within a* of the pole), and its triangles there are finer than those of hertz_coarse.msh."""
    load("hertz.msh"), load("hertz_coarse.msh")
    a = hertz_analysis.hertz(1e-3 * hertz_analysis.wave_speed())["a_star"]
    fine, coarse = (hertz_analysis.pole_size(os.path.join(ROOT, "meshes", m), a) for m in ("hertz.msh", "hertz_coarse.msh"))
    print(f"a* = {a:.4f}: a*/h = {a / fine:.2f} (hertz.msh), {a / coarse:.2f} (hertz_coarse.msh)")
    assert a / fine >= 4 and coarse > 2 * fine
