"""make accuracy's P2 study (p2.md, p2_table.csv, p2_work_precision.png/pdf): P1 and P2 on refining meshes at
one dt against P2 on the finest mesh, per time window, versus wall time."""
import os
import sys

import matplotlib.pyplot as plt
import numpy as np

from accuracy_common import (DTS, MESHES, SAMPLE, T, case_row, finished_history, measured_rows, order, sampled_until,
                             save_study)
from driver import ROOT
from history import read_summary

P2_DT = DTS[-1]                     # the h-study's dt
P2_MESHES = dict(MESHES, refine8=("meshes/disk_refine8.msh", 57393))
P2_REFERENCE = "refine8"            # P2 on it is the most accurate run
TOP = "u2_probe0"                   # u2 of the top vertex (0, 40)
P2_CASES = {                        # name: (order, mesh, dt)
    **{f"test1_P1_{m}_dt{P2_DT:g}_top": (1, m, P2_DT) for m in P2_MESHES},
    **{f"test1_P2_{m}_dt{P2_DT:g}_top": (2, m, P2_DT) for m in P2_MESHES},
    f"test1_P2_paper_dt{P2_DT / 2:g}_top": (2, "paper", P2_DT / 2),   # the time error at P2_DT, for scale
}
P2_WINDOWS = {                      # key: (label, t0, t1, column); errors over t0 < t <= t1 (t = 0.2 k)
    "fall": ("free fall, t <= 8.8, u2_low", 0.0, 8.8, "u2_low"),
    "fall_top": ("free fall, t <= 8.8, top u2", 0.0, 8.8, TOP),
    "contact": ("first contact, 8.8 < t <= 24, top u2", 8.8, 24.0, TOP),
    "flight": ("flight after it, 24 < t <= 40, u2_low", 24.0, T, "u2_low"),
    "whole": ("whole run, t <= 40, u2_low", 0.0, T, "u2_low"),
}


def window_error(h, ref, t0, t1, key):
    """max and L2-in-time of |h - ref|[key] over t0 < t <= t1 on the times t = 0.2 k."""
    d = sampled_until(h, key, t1) - sampled_until(ref, key, t1)
    t = SAMPLE * np.arange(len(d))
    d = np.abs(d[t > t0 + 1e-9])
    return d.max(), np.sqrt(SAMPLE * (d ** 2).sum() / (t1 - t0))


def nodes(run_dir, order_):
    """Nodes of the run's mesh: vertices (P1); vertices + edges (P2; edges = vertices + triangles - 1, a disk)."""
    s = read_summary(run_dir)
    v, t = int(s["vertices"]), int(s["triangles"])
    return v if order_ == 1 else 2 * v + t - 1


def p2_study(out, reuse):
    """P1 and P2 on the mesh sequence at dt = P2_DT against P2 on P2_REFERENCE; returns the lines of p2.md."""
    path = os.path.join(out, "p2_table.csv")
    measured = measured_rows(path, reuse)
    runs, failed = {}, {}
    for n, (name, (order_, mesh, dt)) in enumerate(P2_CASES.items()):
        d = os.path.join(out, name)
        old = measured.get(name)
        h = finished_history(d, old)
        if h is not None:
            runs[name] = dict({k: float(old[k]) for k in ("wall_s", "cpu_s", "peak_MiB")}, steps=int(old["steps"]), history=h)
            continue
        print(f"accuracy p2 [{n + 1}/{len(P2_CASES)}]: {name}", flush=True)
        try:
            runs[name] = case_row(out, name, "test1", ["-T", f"{T:g}", "-dt", f"{dt:g}", "-order", str(order_), "-mesh",
                                                       os.path.join(ROOT, P2_MESHES[mesh][0]), "-solver", "activeset", "-probes", "0,40"])
        except SystemExit as e:      # case_row exits with the run's output: keep its error line, go on without the run
            lines = str(e.code).splitlines()
            failed[name] = next((x for x in lines if x.startswith("error:")), lines[-1] if lines else "failed")
            print(f"accuracy p2: {name} failed, left out: {failed[name]}", flush=True)
    with open(path, "w") as f:
        f.write("name,order,mesh,dt,wall_s,cpu_s,peak_MiB,steps\n")
        for name, r in runs.items():
            o, m, dt = P2_CASES[name]
            f.write(f"{name},{o},{m},{dt:g},{r['wall_s']:.9g},{r['cpu_s']:.9g},{r['peak_MiB']:.9g},{r['steps']}\n")
    ref_name = f"test1_P2_{P2_REFERENCE}_dt{P2_DT:g}_top"
    if ref_name not in runs:
        sys.exit(f"accuracy p2: the reference run {ref_name} failed ({failed.get(ref_name)}); no P2 study")
    ref = runs[ref_name]["history"]
    rows = []
    for name, r in runs.items():
        o, m, dt = P2_CASES[name]
        row = {"name": name, "order": o, "mesh": m, "dt": dt, "vertices": P2_MESHES[m][1],
               "nodes": nodes(os.path.join(out, name), o), "wall_s": r["wall_s"], "cpu_s": r["cpu_s"], "peak_MiB": r["peak_MiB"]}
        for key, (_, t0, t1, col) in P2_WINDOWS.items():
            row[key], row[key + "_l2"] = window_error(r["history"], ref, t0, t1, col)
        rows.append(row)
    by = {(r["order"], r["mesh"], r["dt"]): r for r in rows}
    seq = {o: [r for r in rows if r["order"] == o and r["dt"] == P2_DT and r["name"] != ref_name] for o in (1, 2)}

    md = [f"## P1 and P2 against P2 on the {P2_REFERENCE} mesh (Test 1, T = {T:g}, activeset, dt = {P2_DT:g})", "",
          "Errors against the reference, max over the window (L2 in time for the whole run). "
          "Top u2: u2 of the top vertex (0, 40).", "",
          "| elements | mesh (vertices) | nodes | wall s | CPU s | peak MiB | free fall (u2_low / top) | "
          "first contact, top | flight after, u2_low | whole run, u2_low: max / L2 |",
          "| --- | --- | ---: | ---: | ---: | ---: | --- | ---: | ---: | --- |"]
    for r in rows:
        tag = " (reference)" if r["name"] == ref_name else (f", dt = {r['dt']:g}" if r["dt"] != P2_DT else "")
        md.append(f"| P{r['order']} | {r['mesh']} ({r['vertices']}){tag} | {r['nodes']} | {r['wall_s']:.1f} | {r['cpu_s']:.1f} | "
                  f"{r['peak_MiB']:.0f} | {r['fall']:.1e} / {r['fall_top']:.1e} | {r['contact']:.2e} | "
                  f"{r['flight']:.2e} | {r['whole']:.2e} / {r['whole_l2']:.2e} |")
    for name, msg in failed.items():
        o, m, dt = P2_CASES[name]
        md.append(f"| P{o} | {m} ({P2_MESHES[m][1]}) | | failed: {msg} | | | | | | |")
    half = by.get((2, "paper", P2_DT / 2))
    if half and (2, "paper", P2_DT) in by:
        t_err = {k: window_error(runs[by[(2, "paper", P2_DT)]["name"]]["history"], runs[half["name"]]["history"], t0, t1, col)
                 for k, (_, t0, t1, col) in P2_WINDOWS.items()}
        md += ["", f"The time error at dt = {P2_DT:g} (P2, paper's mesh, dt = {P2_DT:g} against dt = {P2_DT / 2:g}), max: "
               + "; ".join(f"{P2_WINDOWS[k][0]} {t_err[k][0]:.2e}" for k in ("contact", "flight", "whole"))
               + f" (L2 whole run {t_err['whole'][1]:.2e}). Space errors below it are not resolved by this study."]

    def hs(sel):
        return [1 / np.sqrt(r["vertices"]) for r in sel]

    md += ["", f"## Observed orders in h (h = 1/sqrt(vertices); least squares over the meshes below {P2_REFERENCE}; "
           "then mesh to mesh)", "",
           "| window | P1 errors (" + ", ".join(r["mesh"] for r in seq[1]) + ") | P1 order | P1 mesh to mesh | "
           "P2 errors (" + ", ".join(r["mesh"] for r in seq[2]) + ") | P2 order | P2 mesh to mesh |",
           "| --- | --- | ---: | --- | --- | ---: | --- |"]
    for key, suffix, label in [(k, "", P2_WINDOWS[k][0]) for k in ("contact", "flight", "whole")] + \
                              [("whole", "_l2", P2_WINDOWS["whole"][0] + ", L2 in time")]:
        cells = []
        for o in (1, 2):
            errs = [r[key + suffix] for r in seq[o]]
            h = hs(seq[o])
            local = [np.log(errs[i] / errs[i + 1]) / np.log(h[i] / h[i + 1]) for i in range(len(errs) - 1)]
            cells += [", ".join(f"{e:.2e}" for e in errs), f"{order(h, errs):.2f}", ", ".join(f"{x:.2f}" for x in local)]
        md.append(f"| {label} | " + " | ".join(cells) + " |")

    md += ["", "## For each P2 run, the cheapest P1 run at least as accurate (wall seconds)", "",
           "| P2 run | its error, wall s | cheapest P1 run as accurate: error, wall s | P1 wall / P2 wall |",
           "| --- | --- | --- | ---: |"]
    for key, label in (("whole", "whole run, max"), ("whole_l2", "whole run, L2"), ("contact", "first contact, top")):
        p1 = [r for r in rows if r["order"] == 1 and r["dt"] == P2_DT]
        for r in seq[2]:
            ok = sorted((q for q in p1 if q[key] <= r[key]), key=lambda q: q["wall_s"])
            best = (f"P1 {ok[0]['mesh']}: {ok[0][key]:.2e}, {ok[0]['wall_s']:.1f} s", f"{ok[0]['wall_s'] / r['wall_s']:.1f}") \
                if ok else ("none of the P1 runs", "")
            md.append(f"| P2 {r['mesh']} ({label}) | {r[key]:.2e}, {r['wall_s']:.1f} s | {best[0]} | {best[1]} |")

    # the plot: error against wall seconds, P1 and P2, one panel per measure
    fig, axes = plt.subplots(1, 3, figsize=(16, 5))
    for ax, key, what in zip(axes, ("whole", "whole_l2", "contact"),
                             ("u2_low, max over t <= 40", "u2_low, L2 in time over t <= 40", "top u2, max over 8.8 < t <= 24")):
        for o, colour, marker in ((1, "tab:blue", "o"), (2, "tab:red", "s")):
            ax.loglog([r["wall_s"] for r in seq[o]], [r[key] for r in seq[o]], marker=marker, color=colour,
                      label=f"P{o}: " + ", ".join(r["mesh"] for r in seq[o]))
            for r in seq[o]:
                ax.annotate(r["mesh"], (r["wall_s"], r[key]), textcoords="offset points", xytext=(4, 4), fontsize=7, color=colour)
        if half and (2, "paper", P2_DT) in by:
            ax.axhline(t_err[key.replace("_l2", "")][1 if key.endswith("_l2") else 0], color="grey", linestyle=":",
                       label=f"time error at dt = {P2_DT:g} (P2 paper)")
        ax.set(xlabel=f"wall seconds (Test 1, T = {T:g}, dt = {P2_DT:g})", ylabel=f"error against P2 on {P2_REFERENCE}",
               title=what)
        ax.legend(fontsize=7)
    save_study(out, fig, "p2_work_precision", "p2.md", md)
    return md
