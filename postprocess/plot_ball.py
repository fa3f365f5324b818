"""The analogues of the paper's Figs. 1-3 and 5-6 for the 3D ball (`make ball`, docs/3d.md), PNG and PDF.

ball_fig1/ball_fig5: u3 and the contact stress at the lowest point (0, 0, 0), Test 1 and Test 2 in 3D;
ball_fig2/ball_fig6: the energy and the modified energy; ball_fig3: von Mises on the cut plane X2 = 0 at the
paper's snapshot times (the vertices within a thin slab about the plane, deformed, drawn by a Delaunay
triangulation of (X1 + u1, X3 + u3)), with the foundation, and below each the contact zone seen from
below: Gamma_C's nodes in (X1, X2), coloured by the contact pressure alpha (grey where it is 0).
"""
import glob
import os
import re
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.tri as mtri  # noqa: E402
import meshio  # noqa: E402
import numpy as np  # noqa: E402

from history import read_csv, read_run  # noqa: E402
from plot_paper import figure_options, plot_energy, plot_low_point, save  # noqa: E402


def snapshot_times(run_dir):
    return sorted(float(re.search(r"vonmises_t(.*)\.vtu", p).group(1))
                  for p in glob.glob(os.path.join(run_dir, "vonmises_t*.vtu")))


def plot_cut_and_contact(run_dir, out, name, title):
    times = snapshot_times(run_dir)
    if not times:
        return
    snaps = []
    for t in times:
        m = meshio.vtu.read(os.path.join(run_dir, f"vonmises_t{t:g}.vtu"))
        labels = np.concatenate(m.cell_data["Label"])
        faces = m.cells_dict["triangle"][labels[len(m.cells_dict["tetra"]):] == 1]
        snaps.append((t, m, np.unique(faces)))
    for _, m, _ in snaps:          # (meshio reads a scalar point field as a column)
        for field in ("vonmises_vertex", "contact_pressure"):
            m.point_data[field] = np.ravel(m.point_data[field])
    vmax = max(m.point_data["vonmises_vertex"].max() for _, m, _ in snaps)
    pmax = max(m.point_data["contact_pressure"].max() for _, m, _ in snaps) or 1
    foundation = read_csv(os.path.join(run_dir, "foundation.csv"))
    fig, axes = plt.subplots(2, len(snaps), figsize=(3.2 * len(snaps), 6.4), squeeze=False,
                             gridspec_kw={"height_ratios": [1.3, 1]})
    for k, (t, m, contact) in enumerate(snaps):
        X, u = m.points.astype(float), m.point_data["displacement"]
        # the slab |X2| < half the typical edge length about the plane X2 = 0
        edge = np.cbrt(4 * np.pi * 20 ** 3 / 3 / max(1, len(m.cells_dict["tetra"]))) * 1.2
        slab = np.abs(X[:, 1]) < 0.5 * edge
        ax = axes[0, k]
        tri = mtri.Triangulation(X[slab, 0] + u[slab, 0], X[slab, 2] + u[slab, 2])
        cut = ax.tripcolor(tri, m.point_data["vonmises_vertex"][slab], shading="gouraud", vmin=0, vmax=vmax, cmap="jet")
        ft = foundation["t"]
        sel = ft == ft[np.argmin(np.abs(ft - t))]
        ax.plot(foundation["X1"][sel], foundation["psi"][sel], "k-", lw=1.5)
        ax.set(xlim=(-25, 25), ylim=(-4, 42), aspect="equal", title=f"t = {t:g}")
        ax.axis("off")
        ax = axes[1, k]
        p = m.point_data["contact_pressure"][contact]
        on = p > 1e-6             # (active: as history.csv counts them; IPOPT leaves ~tol on the others)
        ax.scatter(X[contact[~on], 0], X[contact[~on], 1], s=4, c="0.8")
        zone = ax.scatter(X[contact[on], 0], X[contact[on], 1], s=10, c=p[on], vmin=0, vmax=pmax, cmap="viridis")
        ax.set(xlim=(-18, 18), ylim=(-18, 18), aspect="equal", title="from below", xlabel="X1")
        ax.tick_params(labelsize=7)
    fig.colorbar(cut, ax=axes[0, :], shrink=0.8, label="von Mises (cut X2 = 0)")
    fig.colorbar(zone, ax=axes[1, :], shrink=0.8, label="contact pressure alpha")
    fig.suptitle(title)
    save(fig, out, name)


def main(argv=None):
    a, ball = figure_options(argv, __doc__, "ball", "ball")
    h1 = read_run(ball)
    lowest = "(0, 0, 0)"
    plot_low_point([("ball, mid-point + active set", h1)], None, a.out, "ball_fig1_low_point", "Test 1 in 3D", "u3",
                   lowest)
    plot_energy([("ball, mid-point + active set", h1)], None, a.out, "ball_fig2_energy", "Test 1 in 3D")
    plot_cut_and_contact(ball, a.out, "ball_fig3_von_mises", "Test 1 in 3D: von Mises on the plane X2 = 0, and the "
                         "contact zone")
    runs = [("fixed foundation (ball)", h1)]
    dirs = sorted(glob.glob(os.path.join(a.results, "ball_moving_t1_*")), key=lambda d: float(d.rsplit("_", 1)[1]))
    runs += [(f"moving, t1 = {d.rsplit('_', 1)[1]}", read_run(d)) for d in dirs]
    if dirs:
        plot_low_point(runs, None, a.out, "ball_fig5_low_point", "Test 2 in 3D", "u3", lowest)
        plot_energy(runs, None, a.out, "ball_fig6_energy", "Test 2 in 3D")
    print(f"ball figures written to {a.out}/")
    return 0


if __name__ == "__main__":
    sys.exit(main())
