"""Draw the paper's Figs. 1-7 from the runs of `make test1 test2` (PNG and PDF).

Fig. 1/5: u2 and contact stress at the lowest point; Fig. 2/6: energy and
modified energy; Fig. 3/7: von Mises at the six snapshot times; Fig. 4: the
foundation psi(., t). Test 1 is overlaid with the independent GetFEM
reference (../shared/reference), which agrees to engineering accuracy only.
"""
import argparse
import glob
import os
import re
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import jobs  # noqa: E402
from history import read_csv, read_freefem_mesh, read_run  # noqa: E402


def save(fig, out, name):
    for ext in ("png", "pdf"):
        fig.savefig(os.path.join(out, f"{name}.{ext}"), dpi=150, bbox_inches="tight")
    plt.close(fig)


def plot_low_point(runs, reference, out, name, title, vertical="u2", lowest="(0, 0)"):
    """u_vertical and alpha at the lowest point (vertical: u2 of the disk, u3 of a 3D ball)."""
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(12, 4))
    for label, h in runs:
        ax1.plot(h["t"], h[f"{vertical}_low"], label=label)
        ax2.plot(h["t"], h["contact_pressure_low"], label=label, lw=0.8)
    if reference is not None:
        ax1.plot(reference["t"], reference["u2_low"], "k--", lw=0.8, label="GetFEM reference (Verlet-Nitsche)")
    ax1.set(xlabel="t", ylabel=f"{vertical} at {lowest}", title=f"{title}: vertical displacement at the lowest point")
    ax2.set(xlabel="t", ylabel=f"contact stress alpha at {lowest}", title=f"{title}: contact stress at the lowest point")
    ax1.legend(fontsize=8)
    ax2.legend(fontsize=8)
    save(fig, out, name)


def plot_energy(runs, reference, out, name, title):
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(12, 4))
    for label, h in runs:
        ax1.plot(h["t"], h["energy"], label=label)
        ax2.plot(h["t"], h["modified_energy"], label=label)
    if reference is not None:
        ax2.plot(reference["t"], reference["modified_energy"], "k--", lw=0.8, label="GetFEM reference")
    ax1.set(xlabel="t", ylabel="energy", title=f"{title}: discrete energy")
    ax2.set(xlabel="t", ylabel="modified energy", title=f"{title}: modified energy")
    ax1.legend(fontsize=8)
    ax2.legend(fontsize=8)
    save(fig, out, name)


def plot_von_mises(run_dir, out, name, title):
    files = sorted(glob.glob(os.path.join(run_dir, "snapshot_t*.csv")),
                   key=lambda p: float(re.search(r"snapshot_t(.*)\.csv", p).group(1)))
    if not files:
        return
    xy, tri = read_freefem_mesh(os.path.join(run_dir, "mesh.msh"))
    snaps = [(float(re.search(r"snapshot_t(.*)\.csv", p).group(1)), read_csv(p)) for p in files]
    vmax = max(s["vonmises"].max() for _, s in snaps)
    foundation = read_csv(os.path.join(run_dir, "foundation.csv")) if os.path.exists(
        os.path.join(run_dir, "foundation.csv")) else None
    ncol = 3
    nrow = (len(snaps) + ncol - 1) // ncol
    fig, axes = plt.subplots(nrow, ncol, figsize=(4 * ncol, 4 * nrow), squeeze=False)
    for ax, (t, s) in zip(axes.flat, snaps):
        x, y = s["x"] + s["u1"], s["y"] + s["u2"]
        tp = ax.tripcolor(x, y, tri, s["vonmises"], shading="gouraud", vmin=0, vmax=vmax, cmap="jet")
        if foundation is not None and "psi" in foundation:
            ft = foundation["t"]
            tk = ft[np.argmin(np.abs(ft - t))]
            sel = ft == tk
            ax.plot(foundation["X1"][sel], foundation["psi"][sel], "k-", lw=1.5)
        ax.set_aspect("equal")
        ax.set_xlim(-25, 25)
        ax.set_ylim(-4, 42)
        ax.set_title(f"Time: {t:.2f}")
        ax.axis("off")
    for ax in list(axes.flat)[len(snaps):]:
        ax.axis("off")
    fig.colorbar(tp, ax=axes, shrink=0.6, label="von Mises stress")
    fig.suptitle(title)
    save(fig, out, name)


def plot_foundation(run_dir, out, name):
    f = read_csv(os.path.join(run_dir, "foundation.csv"))
    fig, ax = plt.subplots(figsize=(7, 3.5))
    for tk in np.unique(f["t"]):
        sel = f["t"] == tk
        ax.plot(f["X1"][sel], f["psi"][sel], label=f"t = {tk:g}")
    ax.set(xlabel="X1", ylabel="psi(X1, t)", title="Test 2: the foundation psi(., t)")
    ax.legend(fontsize=8)
    save(fig, out, name)


def figure_options(argv, doc, run, target, reference=False):
    """The options of a figure script (--results, --out, --reference if asked) and RESULTS/run, the run it
    draws first: a bad option is one `error:` line and exit 2, results without that run's history.csv one
    line naming it and exit 3 (before --out is created)."""
    p = jobs.ArgumentParser(description=doc, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--results", default="results", type=jobs.path, help=f"the runs of make {target} (default results)")
    if reference:
        p.add_argument("--reference", type=jobs.path, help="the GetFEM reference of Test 1 (a CSV), if it exists")
    p.add_argument("--out", default="results/figures", type=jobs.path, help="the figures (default results/figures)")
    a = p.parse_args(argv)
    run_dir = os.path.join(a.results, run)
    if not os.path.isfile(os.path.join(run_dir, "history.csv")):
        print(f"error: {p.prog}: {run_dir} has no history.csv: run make {target} first", file=sys.stderr)
        sys.exit(3)
    os.makedirs(a.out, exist_ok=True)
    return a, run_dir


def main(argv=None):
    a, test1 = figure_options(argv, __doc__, "test1", "test1 test2", reference=True)
    ref = read_csv(a.reference) if a.reference and os.path.exists(a.reference) else None
    h1 = read_run(test1)
    plot_low_point([("Test 1, mid-point + IPOPT", h1)], ref, a.out, "fig1_test1_low_point", "Test 1")
    plot_energy([("Test 1, mid-point + IPOPT", h1)], ref, a.out, "fig2_test1_energy", "Test 1")
    plot_von_mises(test1, a.out, "fig3_test1_von_mises", "Test 1: von Mises stress at the first bounce")
    runs2 = [("fixed foundation (Test 1)", h1)]
    dirs2 = sorted(glob.glob(os.path.join(a.results, "test2_t1_*")), key=lambda d: float(d.rsplit("_", 1)[1]))
    for d in dirs2:
        runs2.append((f"moving, t1 = {d.rsplit('_', 1)[1]}", read_run(d)))
    if dirs2:
        plot_foundation(dirs2[0], a.out, "fig4_test2_foundation")
        plot_low_point(runs2, None, a.out, "fig5_test2_low_point", "Test 2")
        plot_energy(runs2, None, a.out, "fig6_test2_energy", "Test 2")
        plot_von_mises(dirs2[0], a.out, "fig7_test2_von_mises",
                       f"Test 2 (t1 = {dirs2[0].rsplit('_', 1)[1]}): von Mises stress at the first bounce")
    print(f"figures written to {a.out}/")
    return 0


if __name__ == "__main__":
    sys.exit(main())
