"""make accuracy's per-method study (methods.md, methods_table.csv, methods_work_precision.png/pdf): each method
of make methods at several dt, its time error and its difference from the paper's method, versus wall time."""
import os
import re

import matplotlib.pyplot as plt
import numpy as np

from accuracy_common import MESHES, SAMPLE, T, case_row, finished_history, measured_rows, order, sampled, save_study
from methods import RUNNING_METHODS as METHODS  # (the classical Newmark stops: not timed)

M_DTS = [0.1, 0.05, 0.025, 0.0125]          # implicit schemes; reference dt = M_DTS[-1] / 4
V_DTS = [0.01, 0.005, 0.0025]                # explicit Verlet (its critical step is about 0.02); reference V_DTS[-1] / 4
CRITICAL_RE = re.compile(r"critical step ([0-9.eE+-]+)")


def method_dts(name):
    dts = V_DTS if name.startswith("verlet") else M_DTS
    return dts + [dts[-1] / 4]


def methods_study(out, reuse):
    """Each method of make methods at several dt: its error against its own time-converged run (the
    time error) and against the paper's method's (the model difference), versus wall time; for explicit
    Verlet, the least wall time any stable run can take (T / dt_c steps). Returns the lines of methods.md."""
    path = os.path.join(out, "methods_table.csv")
    measured = measured_rows(path, reuse)
    runs, critical = {}, {}
    cases = [(m, dt) for m in METHODS for dt in method_dts(m)]
    for n, (m, dt) in enumerate(cases):
        name = f"method_{m}_dt{dt:g}"
        old = measured.get(name)
        h = finished_history(os.path.join(out, name), old)
        if h is not None:
            runs[(m, dt)] = dict(wall_s=float(old["wall_s"]), steps=int(old["steps"]), history=h)
            if old["critical_dt"]:
                critical[m] = float(old["critical_dt"])
            continue
        print(f"accuracy methods [{n + 1}/{len(cases)}]: {name}", flush=True)
        args = list(METHODS[m][1])
        if "-dt" in args:                    # the method's own dt is replaced by the study's
            del args[args.index("-dt"):args.index("-dt") + 2]
        runs[(m, dt)] = case_row(out, name, "test1", ["-T", f"{T:g}", "-dt", f"{dt:g}", "-mesh", MESHES["paper"][0]] + args,
                                 allow_stop=True)
        found = CRITICAL_RE.search(runs[(m, dt)]["log"])
        if found:
            critical[m] = float(found.group(1))
    with open(path, "w") as f:
        f.write("name,method,dt,wall_s,steps,critical_dt,stopped_at\n")
        for (m, dt), r in runs.items():
            stop = f"{r['history']['t'][-1]:g}" if r.get("stopped") else ""
            f.write(f"method_{m}_dt{dt:g},{m},{dt:g},{r['wall_s']:.9g},{r['steps']},{critical.get(m, '')},{stop}\n")
    # a run the energy guard stopped has no error to measure; nor has a method whose reference it is
    stopped = {key: r for key, r in runs.items() if r.get("stopped")}
    paper_ref = runs[("paper", method_dts("paper")[-1])]["history"]
    rows = []
    for (m, dt), r in runs.items():
        ref_dt = method_dts(m)[-1]
        if dt == ref_dt or (m, dt) in stopped or (m, ref_dt) in stopped:
            continue
        own = sampled(r["history"]) - sampled(runs[(m, ref_dt)]["history"])
        model = sampled(r["history"]) - sampled(paper_ref)
        rows.append({"method": m, "dt": dt, "wall_s": r["wall_s"], "steps": r["steps"],
                     "time_err": np.abs(own).max(), "time_err_l2": np.sqrt(SAMPLE * (own ** 2).sum() / T),
                     "model_diff": np.abs(model).max(), "model_diff_l2": np.sqrt(SAMPLE * (model ** 2).sum() / T)})
    md = [f"## Per method: the time error and the difference from the paper's method (Test 1, T = {T:g}, paper's mesh)", "",
          "Errors of u2_low, max over t = 0.2 k (L2 in time in brackets). Time error: against the same method at dt / 4 "
          f"of its finest dt (implicit schemes: dt = {M_DTS[-1] / 4:g}; explicit Verlet: dt = {V_DTS[-1] / 4:g}). "
          f"Difference from the paper: against mid-point + constraint at dt = {method_dts('paper')[-1]:g}.", "",
          "| method | dt | wall s | time error | observed order | difference from the paper |",
          "| --- | ---: | ---: | --- | ---: | --- |"]
    for m in METHODS:
        sel = [r for r in rows if r["method"] == m]
        ordr = order([r["dt"] for r in sel], [r["time_err"] for r in sel])
        for i, r in enumerate(sel):
            md.append(f"| {METHODS[m][0] if i == 0 else ''} | {r['dt']:g} | {r['wall_s']:.1f} | {r['time_err']:.2e} "
                      f"({r['time_err_l2']:.1e}) | {f'{ordr:.2f}' if i == 0 else ''} | {r['model_diff']:.2e} ({r['model_diff_l2']:.1e}) |")
    if stopped:
        md += ["", "Stopped by the energy guard (their modified energy gained more than 10% of the run's energy on the "
               "fixed foundation: docs/errors.md); no error is measured for them, nor for any run of a method whose "
               "reference run stopped:", "", "| method | dt | stopped at t | wall s |", "| --- | ---: | ---: | ---: |"]
        md += [f"| {METHODS[m][0]} | {dt:g} | {r['history']['t'][-1]:g} | {r['wall_s']:.1f} |" for (m, dt), r in stopped.items()]
    least = {}
    for m, dt_c in critical.items():       # explicit: T / dt_c steps at the measured cost per step, plus the set-up
        # wall = set-up + per_step x steps, fitted by least squares to the method's runs (4 dt)
        steps = [runs[(m, dt)]["steps"] for dt in method_dts(m)]
        per_step, setup = np.polyfit(steps, [runs[(m, dt)]["wall_s"] for dt in method_dts(m)], 1)
        least[m] = (dt_c, setup + per_step * T / dt_c, per_step)
    md += ["", "Explicit Verlet's cost is bounded below by its critical step dt_c (computed by the run): no stable run "
           "takes fewer than T / dt_c steps. Its least wall time, from its measured cost per step and set-up:", "",
           "| method | dt_c | ms per step | least wall s (T / dt_c steps) | wall s of the paper's method at dt = 0.1 |",
           "| --- | ---: | ---: | ---: | ---: |"]
    for m, (dt_c, wall, per_step) in least.items():
        md.append(f"| {METHODS[m][0]} | {dt_c:.4g} | {1000 * per_step:.2f} | {wall:.2f} | {runs[('paper', 0.1)]['wall_s']:.2f} |")

    fig, axes = plt.subplots(1, 2, figsize=(15, 6), sharex=True)
    cmap = plt.get_cmap("tab20")
    for ax, key, what in zip(axes, ("time_err", "model_diff"),
                             ("time error (against the same method at a 4x smaller dt)",
                              f"difference from the paper's method (dt = {method_dts('paper')[-1]:g})")):
        for i, m in enumerate(METHODS):
            sel = [r for r in rows if r["method"] == m and r[key] > 0]
            explicit = m in least
            ax.loglog([r["wall_s"] for r in sel], [r[key] for r in sel], marker="s" if explicit else "o",
                      linestyle="--" if explicit else "-", color=cmap(i), label=METHODS[m][0])
            if explicit:
                ax.axvline(least[m][1], color=cmap(i), linestyle=":", linewidth=1)
        ax.set(xlabel=f"wall seconds (Test 1, T = {T:g}, paper's mesh)", ylabel="max error of u2_low", title=what)
    for m, (dt_c, wall, _) in least.items():
        axes[0].annotate(f"least cost at dt_c = {dt_c:.3g}", (wall, axes[0].get_ylim()[0]), rotation=90, fontsize=7,
                         xytext=(2, 4), textcoords="offset points", va="bottom")
    handles, labels = axes[0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=4, fontsize=8, bbox_to_anchor=(0.5, -0.12))
    save_study(out, fig, "methods_work_precision", "methods.md", md)
    return md
