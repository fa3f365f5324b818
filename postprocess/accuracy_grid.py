"""make accuracy's main study (table.csv, table.md, orders.md, work_precision.png/pdf): Test 1 over dt x meshes
x solvers, and Test 2 on a smaller grid, against the finest run; the errors, the cost, and the observed
orders in dt and h."""
import os

import matplotlib.pyplot as plt
import numpy as np

from accuracy_common import (DTS, MESHES, SAMPLE, SOLVERS, T, case_row, finished_history, measured_rows, order,
                             sampled)
from history import contact_intervals


def first_bounce(h):
    start, end = contact_intervals(h["t"], h["active_nodes"] > 0)[0]
    m = h["modified_energy"]
    lost = np.interp(start - 1e-9, h["t"], m) - np.interp(end + 1e-9, h["t"], m)
    return start, end, lost


def errors(h, ref):
    e = sampled(h) - sampled(ref)
    s, e_, lost = first_bounce(h)
    rs, re, rlost = first_bounce(ref)
    return {"err_max": np.abs(e).max(), "err_l2": np.sqrt(SAMPLE * (e ** 2).sum() / T),
            "contact_start": s, "contact_end": e_, "err_start": abs(s - rs), "err_end": abs(e_ - re),
            "energy_lost": lost, "err_energy_lost": abs(lost - rlost)}


def in_grid(mesh, solver, dt):
    """Every setting on the coarse and paper meshes. On the fine mesh, where an IPOPT
    step costs 80 ms, the active-set solver at every dt and IPOPT 1e-8 at dt >= 0.05;
    on the refine-4 mesh, the reference, the active-set solver at dt <= 0.05."""
    if mesh == "fine":
        return solver == "activeset" or (solver == "ipopt 1e-8" and dt >= 0.05)
    if mesh == "refine4":
        return solver == "activeset" and dt <= 0.05
    return True


def grid_study(out, reuse, quick):
    """The grid's runs, its tables and its figure (quick: a small grid); returns the lines of table.md and
    orders.md and the finest mesh."""
    dts = DTS[1:4] if quick else DTS
    meshes = {k: v for k, v in MESHES.items() if not quick or k in ("coarse", "paper")}
    solvers = {k: v for k, v in SOLVERS.items() if not quick or k in ("ipopt 1e-8", "activeset")}
    runs = {}
    grid = [("test1", m, dt, s) for m in meshes for s in solvers for dt in dts if in_grid(m, s, dt)]
    grid += [("test2", "paper", dt, s) for s in ("ipopt 1e-8", "activeset") for dt in (0.1, 0.05, 0.025, 0.0125)
             if not quick or dt in dts]
    measured = measured_rows(os.path.join(out, "table.csv"), reuse,
                             key=lambda row: (row["test"], row["mesh"], float(row["dt"]), row["solver"]))
    for n, (test, mesh, dt, solver) in enumerate(grid):
        name = f"{test}_{mesh}_dt{dt}_{solver.replace(' ', '')}"
        old = measured.get((test, mesh, dt, solver))
        h = finished_history(os.path.join(out, name), old)
        if h is not None:
            runs[(test, mesh, dt, solver)] = dict({k: float(old[k]) for k in ("wall_s", "cpu_s", "ms_per_step", "peak_MiB")},
                                                  steps=int(old["steps"]), qp_steps=int(old["qp_steps"]), history=h)
            continue
        print(f"accuracy [{n + 1}/{len(grid)}]: {name}", flush=True)
        args = ["-T", str(T), "-dt", str(dt), "-mesh", meshes[mesh][0]] + solvers[solver]
        if test == "test2":
            args += ["-t1", "18"]
        runs[(test, mesh, dt, solver)] = case_row(out, name, test, args)
    finest_mesh = list(meshes)[-1]
    rows = []
    for (test, mesh, dt, solver), r in runs.items():
        ref = runs[(test, finest_mesh if test == "test1" else "paper", dts[-1], "activeset")]["history"]
        row = {"test": test, "mesh": mesh, "vertices": meshes[mesh][1], "dt": dt, "solver": solver,
               "wall_s": r["wall_s"], "cpu_s": r["cpu_s"], "ms_per_step": r["ms_per_step"],
               "peak_MiB": r["peak_MiB"], "steps": r["steps"], "qp_steps": r["qp_steps"]}
        row.update(errors(r["history"], ref))
        rows.append(row)
    keys = list(rows[0])
    with open(os.path.join(out, "table.csv"), "w") as f:
        f.write(",".join(keys) + "\n")
        for row in rows:
            f.write(",".join(f"{row[k]:.6g}" if isinstance(row[k], float) else str(row[k]) for k in keys) + "\n")
    md = ["| test | mesh | dt | solver | wall s | ms/step | peak MiB | max err u2 | L2 err u2 | err contact start / end | energy lost (err) |",
          "| --- | --- | ---: | --- | ---: | ---: | ---: | ---: | ---: | --- | --- |"]
    for r in rows:
        md.append(f"| {r['test']} | {r['mesh']} | {r['dt']} | {r['solver']} | {r['wall_s']:.1f} | {r['ms_per_step']:.2f} | "
                  f"{r['peak_MiB']:.0f} | {r['err_max']:.2e} | {r['err_l2']:.2e} | {r['err_start']:.2f} / {r['err_end']:.2f} | "
                  f"{r['energy_lost']:.3f} ({r['err_energy_lost']:.3f}) |")
    with open(os.path.join(out, "table.md"), "w") as f:
        f.write("\n".join(md) + "\n")

    # observed orders: dt on each mesh against its own finest dt; h at the finest dt against the finest mesh
    orders = ["| what | errors of u2_low (max over t unless said) | observed order |", "| --- | --- | ---: |"]
    for mesh in meshes:
        own = runs[("test1", mesh, dts[-1], "activeset")]["history"]
        coarser = [dt for dt in dts[:-1] if ("test1", mesh, dt, "activeset") in runs]
        errs = [np.abs(sampled(runs[("test1", mesh, dt, "activeset")]["history"]) - sampled(own)).max() for dt in coarser]
        orders.append(f"| dt, {mesh} mesh (dt = {', '.join(map(str, coarser))}) | "
                      f"{', '.join(f'{e:.2e}' for e in errs)} | {order(coarser, errs):.2f} |")
    hs = [1 / np.sqrt(meshes[m][1]) for m in list(meshes)[:-1]]
    diffs = [sampled(runs[("test1", m, dts[-1], "activeset")]["history"])
             - sampled(runs[("test1", finest_mesh, dts[-1], "activeset")]["history"]) for m in list(meshes)[:-1]]
    for norm, errs in (("max", [np.abs(d).max() for d in diffs]),
                       ("L2 in time", [np.sqrt(SAMPLE * (d ** 2).sum() / T) for d in diffs])):
        orders.append(f"| h, dt = {dts[-1]}, {norm} ({', '.join(list(meshes)[:-1])} against {finest_mesh}) | "
                      f"{', '.join(f'{e:.2e}' for e in errs)} | {order(hs, errs):.2f} |")
    with open(os.path.join(out, "orders.md"), "w") as f:
        f.write("\n".join(orders) + "\n")

    # colour = mesh, marker and line = solver; max and L2-in-time error side by side
    fig, axes = plt.subplots(1, 2, figsize=(12, 5), sharex=True)
    colours = dict(zip(MESHES, ("tab:red", "tab:blue", "tab:green", "black")))
    styles = {"ipopt 1e-6": ("v", ":"), "ipopt 1e-8": ("s", "--"), "ipopt 1e-10": ("^", "-."), "activeset": ("o", "-")}
    for ax, key, what in zip(axes, ("err_max", "err_l2"), ("max over t", "L2 in time")):
        for mesh in meshes:
            for solver in solvers:
                sel = [r for r in rows if r["test"] == "test1" and r["mesh"] == mesh and r["solver"] == solver and r[key] > 0]
                if sel:
                    marker, line = styles[solver]
                    ax.loglog([r["wall_s"] for r in sel], [r[key] for r in sel], marker=marker, linestyle=line,
                              color=colours[mesh], label=f"{mesh} ({meshes[mesh][1]}), {solver}")
        ax.set(xlabel="wall seconds (Test 1, T = 40)", ylabel=f"error of u2_low ({what}) against the finest run",
               title=f"Work-precision, Test 1: {what}")
    axes[0].legend(fontsize=7)
    for ext in ("png", "pdf"):
        fig.savefig(os.path.join(out, f"work_precision.{ext}"), dpi=150, bbox_inches="tight")
    plt.close(fig)
    return md, orders, finest_mesh
