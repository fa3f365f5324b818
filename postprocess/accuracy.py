"""`make accuracy`: what accuracy costs in time (work-precision study).

Test 1 to T = 40 (first bounce and the flight after it) over
  dt in {0.2, 0.1, 0.05, 0.025, 0.0125} x meshes {coarse, paper, fine}
  x solvers {IPOPT tol 1e-6, 1e-8, 1e-10, activeset}
(on the fine mesh only activeset at every dt and IPOPT 1e-8 at dt >= 0.05),
plus the twice-refined mesh (refine 4) with activeset at dt <= 0.05, and
Test 2 (t1 = 18) on a smaller grid. The reference solution is the finest
run (refine-4 mesh, dt = 0.0125, activeset). For each run, against it:
  - max and L2-in-time error of u2_low(t), on the times all runs share (t = 0.2 k);
  - error of the first contact interval's start and end;
  - the modified energy lost over the first bounce, and its error;
and the cost: wall and CPU seconds per run and per step, peak memory.
Observed orders: in dt on each mesh (against that mesh's dt = 0.0125 run),
in h at dt = 0.0125 (coarse, paper and fine against the refine-4 mesh).
St Venant-Kirchhoff (-material svk, paper Section 3), on the paper's mesh:
  - the model error, SVK against linear, beside the dt and h errors of the same
    case: (i) Test 1 with the paper's lambda = mu = 30 on t <= 15 only (the SVK
    body collapses at t = 16.8), u2 of the top vertex (0, 40), since u2_low is
    pinned at 0 in contact; (ii) the stiff Test 1 (lambda = mu = 300, no
    collapse) to T = 40, u2_low (it holds the rebound);
  - SVK's observed order in dt (self-convergence: dt = 0.1, 0.05, 0.025 against
    dt = 0.0125) on the spin scene (no contact: the smooth case, error of the
    lowest point's displacement vector) and on the stiff Test 1 (with an impact).
P2 against refining P1 (-order 2; p2.md): Test 1 to T = 40, activeset, at the
h-study's dt = 0.0125, with P1 and with P2 on the coarse, paper, fine, refine-4
and refine-8 meshes, the top vertex (0, 40) as a probe (-probes 0,40). Every run
against P2 on the refine-8 mesh (the most accurate run, about 13 min), on windows:
free fall (t <= 8.8, a rigid motion: round-off), the first contact (8.8 < t <= 24,
top vertex u2, since u2_low is pinned), the flight after it (u2_low) and the whole
run (u2_low, the h-study's measure); wall/CPU seconds and memory of each run;
observed orders in h (h = 1/sqrt(vertices)) per window; for each P2 run, the
cheapest P1 run as accurate. P2 on the paper's mesh at dt = 0.00625 gives the size
of the time error at dt = 0.0125. A run that fails is left out with its error line.
Per method (the methods of make methods, docs/methods.md): Test 1 to T = 40 on the paper's
mesh at dt = 0.1, 0.05, 0.025, 0.0125 (explicit Verlet: 0.01, 0.005, 0.0025), each against
the same method at a 4x smaller dt than its finest (its time error) and against the paper's
method's such run (the model difference), versus wall time; for explicit Verlet the least
wall time of a stable run, T / dt_c steps at its measured cost per step.
The Neo-Hookean body (-material neohookean, nh.md; --nh-only: that part alone, with the linear and
SVK runs it needs), on the paper's mesh: the model differences Neo-Hookean - linear and Neo-Hookean
- SVK at the same dt (0.0125 and 0.05) on the SVK study's two cases (Test 1 on t <= 15, top vertex;
the stiff Test 1 to T = 40), and Neo-Hookean - linear on Test 1 to T = 40 with the paper's body (which
the Neo-Hookean body runs through); its own dt error beside the linear one; its observed order in dt
(dt = 0.1, 0.05, 0.025 against 0.0125) on the spin scene (no contact), the stiff Test 1 and Test 1.
Writes results/accuracy/table.csv, table.md, orders.md, svk.md, nh.md, work_precision.png/pdf,
p2.md, p2_table.csv, p2_work_precision.png/pdf (--p2-only: the P2 part alone), methods.md,
methods_table.csv, methods_work_precision.png/pdf (--methods-only: that part alone).
"""
import csv
import os
import re
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import jobs  # noqa: E402
from driver import ROOT, case_row as run_case  # noqa: E402
from history import contact_intervals, read_run, read_summary  # noqa: E402
from methods import RUNNING_METHODS as METHODS  # noqa: E402 (the classical Newmark stops: not timed)

DTS = [0.2, 0.1, 0.05, 0.025, 0.0125]
MESHES = {"coarse": ("meshes/disk_coarse.msh", 277), "paper": ("meshes/disk.msh", 989),
          "fine": ("meshes/disk_fine.msh", 3750), "refine4": ("meshes/disk_refine4.msh", 14570)}
SOLVERS = {"ipopt 1e-6": ["-solver", "ipopt", "-tol", "1e-6"], "ipopt 1e-8": ["-solver", "ipopt", "-tol", "1e-8"],
           "ipopt 1e-10": ["-solver", "ipopt", "-tol", "1e-10"], "activeset": ["-solver", "activeset"]}
T = 40.0
SAMPLE = 0.2           # every dt of the grid divides it
SVK_WINDOW = 15.0      # Test 1, lambda = mu = 30: compare up to here (SVK collapses at t = 16.8)
STIFF = ["-lambda", "300", "-mu", "300"]
SVK_DTS = [0.1, 0.05, 0.025, 0.0125]


def sampled(h):
    """u2_low at t = 0.2 k, k = 0..T/0.2 (exact grid points of every run)."""
    k = np.rint(h["t"] / SAMPLE)
    on_grid = np.abs(h["t"] - k * SAMPLE) < 1e-9
    return h["u2_low"][on_grid]


def sampled_until(h, key, t_end):
    """h[key] at t = 0.2 k, k = 0..t_end/0.2."""
    k = np.rint(h["t"] / SAMPLE)
    on_grid = (np.abs(h["t"] - k * SAMPLE) < 1e-9) & (h["t"] <= t_end + 1e-9)
    return h[key][on_grid]


def diff_until(h, ref, t_end, keys=("u2_low",)):
    """max over t <= t_end of |(h - ref)[keys]| (Euclidean over keys), and its L2 in time."""
    d = np.sqrt(sum((sampled_until(h, k, t_end) - sampled_until(ref, k, t_end)) ** 2 for k in keys))
    return d.max(), np.sqrt(SAMPLE * (d ** 2).sum() / t_end)


def run_material_cases(out, reuse, cases, part, have=None):
    """Runs each case {name: (scene, T, args)} on the paper's mesh (unless args give -mesh), into out/name;
    a case in `have` (name: run made in this invocation), or with --reuse a finished run already in out,
    is not run again (its wall_s is then nan). Returns {name: run_case's dict, or the reused history}."""
    runs = {}
    for n, (name, (scene, t_end, args)) in enumerate(cases.items()):
        if have and name in have:
            runs[name] = {"history": have[name], "wall_s": float("nan")}
            continue
        d = os.path.join(out, name)
        if reuse and os.path.exists(os.path.join(d, "summary.txt")):
            h = read_run(d)
            if abs(h["t"][-1] - t_end) < 1e-9:
                runs[name] = {"history": h, "wall_s": float("nan")}
                continue
        print(f"accuracy {part} [{n + 1}/{len(cases)}]: {name}", flush=True)
        extra = [] if "-mesh" in args else ["-mesh", MESHES["paper"][0]]
        runs[name] = run_case(out, name, scene, ["-T", f"{t_end:g}"] + extra + args)
    return runs


def model_cases(prefix, material_args, dts):
    """The runs of svk_study and nh_study's cases for one model: Test 1 on t <= SVK_WINDOW with the top
    vertex as a probe (dt = 0.05, 0.0125) and the stiff Test 1 to T (dts)."""
    cases = {f"{prefix}_test1_T15_top_dt{dt}": ("test1", SVK_WINDOW, material_args + ["-dt", str(dt), "-probes", "0,40"])
             for dt in (0.05, 0.0125)}
    cases.update({f"{prefix}_stiff_dt{dt}": ("test1", T, STIFF + material_args + ["-dt", str(dt)]) for dt in dts})
    return cases


def order_row(label, H, prefix, t_end, keys):
    """A row of an observed-order table: self-convergence of H[prefix_dt..] against SVK_DTS[-1]."""
    ref = H[f"{prefix}_dt{SVK_DTS[-1]}"]
    errs = [diff_until(H[f"{prefix}_dt{dt}"], ref, t_end, keys) for dt in SVK_DTS[:-1]]
    mx, l2 = [e[0] for e in errs], [e[1] for e in errs]
    return (f"| {label} | {', '.join(f'{e:.2e}' for e in mx)} | {order(SVK_DTS[:-1], mx):.2f} | "
            f"{', '.join(f'{e:.2e}' for e in l2)} | {order(SVK_DTS[:-1], l2):.2f} |")


def wall_line(study, runs):
    walls = {k: r["wall_s"] for k, r in runs.items() if np.isfinite(r["wall_s"])}     # not of runs reused
    return f"Wall seconds of the {study} study's runs made now: " + ", ".join(f"{k} {v:.1f}" for k, v in walls.items())


def svk_study(out, reuse, finest_mesh):
    """Model error (SVK against linear) and SVK's observed order in dt; returns the lines of svk.md."""
    paper = MESHES["paper"][0]
    cases = {}      # key: (scene, T, args)
    # Test 1 on t <= 15: u2_low is pinned at 0 in contact, so compare the top vertex (0, 40) (probe 0)
    for dt in (0.05, 0.0125):
        for model, extra in (("svk", ["-material", "svk"]), ("linear", ["-solver", "activeset"])):
            cases[f"{model}_test1_T15_top_dt{dt}"] = ("test1", SVK_WINDOW, extra + ["-dt", str(dt), "-probes", "0,40"])
    cases["linear_test1_T15_top_refine4_dt0.0125"] = ("test1", SVK_WINDOW, ["-solver", "activeset", "-dt", "0.0125",
                                                                           "-probes", "0,40", "-mesh", MESHES["refine4"][0]])
    for dt in (0.05, 0.0125):
        cases[f"linear_stiff_dt{dt}"] = ("test1", T, STIFF + ["-solver", "activeset", "-dt", str(dt)])
    cases["linear_stiff_refine4_dt0.0125"] = ("test1", T, STIFF + ["-solver", "activeset", "-dt", "0.0125",
                                                                   "-mesh", MESHES["refine4"][0]])
    for dt in SVK_DTS:
        cases[f"svk_stiff_dt{dt}"] = ("test1", T, STIFF + ["-material", "svk", "-dt", str(dt)])
        cases[f"svk_spin_dt{dt}"] = ("spin", 30.0, ["-material", "svk", "-dt", str(dt)])
    runs = run_material_cases(out, reuse, cases, "svk")
    H = {k: r["history"] for k, r in runs.items()}
    top = ("u2_probe0",)

    def row(what, pair, t_end, keys=("u2_low",)):
        mx, l2 = diff_until(*pair, t_end, keys)
        return f"| {what} | {mx:.3g} | {l2:.3g} |"

    md = ["## Model error: SVK against linear, beside the discretisation errors (paper's mesh)", "",
          "| what | max error | L2-in-time error |", "| --- | ---: | ---: |",
          row(f"Test 1 (lambda = mu = 30), t <= {SVK_WINDOW:g}, u2 of the top (0, 40): model, SVK - linear, dt = 0.0125",
              (H["svk_test1_T15_top_dt0.0125"], H["linear_test1_T15_top_dt0.0125"]), SVK_WINDOW, top),
          row(f"Test 1, t <= {SVK_WINDOW:g}, top: model, SVK - linear, dt = 0.05",
              (H["svk_test1_T15_top_dt0.05"], H["linear_test1_T15_top_dt0.05"]), SVK_WINDOW, top),
          row(f"Test 1, t <= {SVK_WINDOW:g}, top: dt error, linear dt = 0.05 - dt = 0.0125",
              (H["linear_test1_T15_top_dt0.05"], H["linear_test1_T15_top_dt0.0125"]), SVK_WINDOW, top),
          row(f"Test 1, t <= {SVK_WINDOW:g}, top: dt error, SVK dt = 0.05 - dt = 0.0125",
              (H["svk_test1_T15_top_dt0.05"], H["svk_test1_T15_top_dt0.0125"]), SVK_WINDOW, top),
          row(f"Test 1, t <= {SVK_WINDOW:g}, top: h error, linear paper mesh - {finest_mesh}, dt = 0.0125",
              (H["linear_test1_T15_top_dt0.0125"], H["linear_test1_T15_top_refine4_dt0.0125"]), SVK_WINDOW, top),
          row(f"stiff Test 1 (lambda = mu = 300), t <= {T:g}: model, SVK - linear, dt = 0.0125",
              (H["svk_stiff_dt0.0125"], H["linear_stiff_dt0.0125"]), T),
          row(f"stiff Test 1, t <= {T:g}: model, SVK - linear, dt = 0.05",
              (H["svk_stiff_dt0.05"], H["linear_stiff_dt0.05"]), T),
          row(f"stiff Test 1, t <= {T:g}: dt error, linear dt = 0.05 - dt = 0.0125",
              (H["linear_stiff_dt0.05"], H["linear_stiff_dt0.0125"]), T),
          row(f"stiff Test 1, t <= {T:g}: dt error, SVK dt = 0.05 - dt = 0.0125",
              (H["svk_stiff_dt0.05"], H["svk_stiff_dt0.0125"]), T),
          row(f"stiff Test 1, t <= {T:g}: h error, linear paper mesh - {finest_mesh}, dt = 0.0125",
              (H["linear_stiff_dt0.0125"], H["linear_stiff_refine4_dt0.0125"]), T),
          "", "## SVK's observed order in dt (self-convergence against dt = 0.0125, paper's mesh)", "",
          "| case | errors at dt = " + ", ".join(map(str, SVK_DTS[:-1])) + " (max over t) | observed order | "
          "L2-in-time errors | observed order (L2) |", "| --- | --- | ---: | --- | ---: |"]
    for label, prefix, t_end, keys in (
            ("spin (no contact, f = 0), T = 30, |u_low| (both components)", "svk_spin", 30.0, ("u1_low", "u2_low")),
            ("stiff Test 1 (contact from t = 8.95 to 14.2 and from 31.75), T = 40, u2_low", "svk_stiff", T, ("u2_low",))):
        md.append(order_row(label, H, prefix, t_end, keys))
    md += ["", wall_line("SVK", runs)]
    return md, H


def nh_study(out, reuse, have=None):
    """The Neo-Hookean body (-material neohookean) on the paper's mesh: the model differences
    Neo-Hookean - linear and Neo-Hookean - SVK (at the same dt and mesh) on the cases of svk_study,
    where SVK does not collapse, and on Test 1 to T = 40 with the paper's body (which the Neo-Hookean
    body runs through, linear beside it); its observed order in dt (self-convergence against
    dt = 0.0125) on the spin scene, the stiff Test 1 and Test 1. `have`: svk_study's histories (not run
    again). Returns the lines of nh.md."""
    nh = ["-material", "neohookean"]
    cases = model_cases("nh", nh, SVK_DTS)
    cases.update(model_cases("svk", ["-material", "svk"], (0.05, 0.0125)))
    cases.update(model_cases("linear", ["-solver", "activeset"], (0.05, 0.0125)))
    for dt in SVK_DTS:
        cases[f"nh_test1_dt{dt}"] = ("test1", T, nh + ["-dt", str(dt), "-probes", "0,40"])
        cases[f"nh_spin_dt{dt}"] = ("spin", 30.0, nh + ["-dt", str(dt)])
    for dt in (0.05, 0.0125):
        cases[f"linear_test1_dt{dt}"] = ("test1", T, ["-solver", "activeset", "-dt", str(dt), "-probes", "0,40"])
    runs = run_material_cases(out, reuse, cases, "neohookean", have)
    H = {k: r["history"] for k, r in runs.items()}
    top = ("u2_probe0",)
    rows = []
    for label, case, t_end, keys in (
            (f"Test 1 (lambda = mu = 30), t <= {SVK_WINDOW:g}, u2 of the top (0, 40)", "test1_T15_top", SVK_WINDOW, top),
            (f"Test 1 (lambda = mu = 30), t <= {T:g}, u2_low (SVK collapses at 16.8)", "test1", T, ("u2_low",)),
            (f"Test 1 (lambda = mu = 30), t <= {T:g}, u2 of the top (0, 40)", "test1", T, top),
            (f"stiff Test 1 (lambda = mu = 300), t <= {T:g}, u2_low", "stiff", T, ("u2_low",))):
        pairs = [(f"model, NH - {b}, dt = {dt:g}", f"nh_{case}_dt{dt}", f"{b}_{case}_dt{dt}")
                 for b in ("linear", "svk") for dt in (0.0125, 0.05)]
        pairs += [(f"dt error, {a} dt = 0.05 - dt = 0.0125", f"{a}_{case}_dt0.05", f"{a}_{case}_dt0.0125")
                  for a in ("nh", "linear")]
        for what, x, y in pairs:
            if x in H and y in H:        # (no SVK on Test 1 to T = 40: it collapses at t = 16.8)
                mx, l2 = diff_until(H[x], H[y], t_end, keys)
                rows.append(f"| {label} | {what.replace('nh ', 'NH ')} | {mx:.3g} | {l2:.3g} |")
    md = ["## Model differences: Neo-Hookean (NH) against linear and against SVK (paper's mesh)", "",
          "| case | what | max difference | L2-in-time difference |", "| --- | --- | ---: | ---: |"] + rows
    md += ["", "## Neo-Hookean's observed order in dt (self-convergence against dt = 0.0125, paper's mesh)", "",
           "| case | errors at dt = " + ", ".join(map(str, SVK_DTS[:-1])) + " (max over t) | observed order | "
           "L2-in-time errors | observed order (L2) |", "| --- | --- | ---: | --- | ---: |"]
    for label, prefix, t_end, keys in (
            ("spin (no contact, f = 0), T = 30, |u_low| (both components)", "nh_spin", 30.0, ("u1_low", "u2_low")),
            ("stiff Test 1 (lambda = mu = 300), T = 40, u2_low", "nh_stiff", T, ("u2_low",)),
            ("Test 1 (lambda = mu = 30), T = 40, u2_low", "nh_test1", T, ("u2_low",)),
            ("Test 1 (lambda = mu = 30), T = 40, u2 of the top (0, 40)", "nh_test1", T, top)):
        md.append(order_row(label, H, prefix, t_end, keys))
    intervals = {k: contact_intervals(H[k]["t"], H[k]["active_nodes"] > 0) for k in ("nh_test1_dt0.0125", "linear_test1_dt0.0125",
                                                                                    "nh_stiff_dt0.0125", "linear_stiff_dt0.0125")}
    md += ["", "Contact intervals at dt = 0.0125: " + "; ".join(
        f"{k.replace('_dt0.0125', '')} " + ", ".join(f"[{a:g}, {b:g}]" for a, b in v) for k, v in intervals.items()),
        "", wall_line("Neo-Hookean", runs)]
    with open(os.path.join(out, "nh.md"), "w") as f:
        f.write("\n".join(md) + "\n")
    return md


# ---- P2 against refining P1 (p2.md)
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


def measured_rows(path, reuse, key=lambda row: row["name"]):
    """The rows of an earlier run's table (--reuse), by key; {} without --reuse or the table."""
    if not (reuse and os.path.exists(path)):
        return {}
    with open(path) as f:
        return {key(row): row for row in csv.DictReader(f)}


def finished_history(d, old):
    """The history in d when it is the finished run that the table row `old` measured, else None."""
    if not old or not os.path.exists(os.path.join(d, "summary.txt")):
        return None
    h = read_run(d)
    return h if abs(h["t"][-1] - T) < 1e-9 and len(h["t"]) - 1 == int(old["steps"]) else None


def save_study(out, fig, figure_stem, md_name, md):
    """The study's figure as PNG and PDF, and its lines as md_name, into out."""
    for ext in ("png", "pdf"):
        fig.savefig(os.path.join(out, f"{figure_stem}.{ext}"), dpi=150, bbox_inches="tight")
    plt.close(fig)
    with open(os.path.join(out, md_name), "w") as f:
        f.write("\n".join(md) + "\n")


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
            runs[name] = run_case(out, name, "test1", ["-T", f"{T:g}", "-dt", f"{dt:g}", "-order", str(order_), "-mesh",
                                                       os.path.join(ROOT, P2_MESHES[mesh][0]), "-solver", "activeset", "-probes", "0,40"])
        except SystemExit as e:      # run_case exits with the run's output: keep its error line, go on without the run
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


# ---- per method (methods.md): the methods of docs/methods.md on Test 1, the paper's mesh
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
        runs[(m, dt)] = run_case(out, name, "test1", ["-T", f"{T:g}", "-dt", f"{dt:g}", "-mesh", MESHES["paper"][0]] + args,
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


def order(xs, ys):
    """Least-squares slope of log(y) against log(x)."""
    xs, ys = np.array(xs), np.array(ys)
    keep = ys > 0
    return np.polyfit(np.log(xs[keep]), np.log(ys[keep]), 1)[0] if keep.sum() >= 2 else float("nan")


def in_grid(mesh, solver, dt):
    """Every setting on the coarse and paper meshes. On the fine mesh, where an IPOPT
    step costs 80 ms, the active-set solver at every dt and IPOPT 1e-8 at dt >= 0.05;
    on the refine-4 mesh, the reference, the active-set solver at dt <= 0.05."""
    if mesh == "fine":
        return solver == "activeset" or (solver == "ipopt 1e-8" and dt >= 0.05)
    if mesh == "refine4":
        return solver == "activeset" and dt <= 0.05
    return True


def main():
    p = jobs.ArgumentParser(description=__doc__)
    p.add_argument("--out", default=os.path.join(ROOT, "results", "accuracy"))
    p.add_argument("--quick", action="store_true", help="a small grid, to try the script")
    p.add_argument("--reuse", action="store_true",
                   help="rebuild the tables and the plot from the runs and costs already in --out, running only what is missing")
    p.add_argument("--p2-only", action="store_true", help="run only the P2-against-P1 part (p2.md)")
    p.add_argument("--methods-only", action="store_true", help="run only the per-method part (methods.md)")
    p.add_argument("--nh-only", action="store_true", help="run only the Neo-Hookean part (nh.md), with the linear "
                   "and SVK runs it compares with")
    jobs.add_processes_option(p)
    a = p.parse_args()
    jobs.use_processes(a.np)
    os.makedirs(a.out, exist_ok=True)
    # what this invocation rewrites (--quick: only the main tables and figure)
    if a.p2_only or a.methods_only:
        part = "p2" if a.p2_only else "methods"
        stale = [f"{part}.md", f"{part}_work_precision.png", f"{part}_work_precision.pdf"]
    elif a.nh_only:
        stale = ["nh.md"]
    elif a.quick:
        stale = ["table.md", "orders.md", "work_precision.png", "work_precision.pdf"]
    else:
        stale = ["*.md", "*work_precision.png", "*work_precision.pdf"]
    jobs.stop_on_interrupt("make accuracy", a.out, stale)
    if a.p2_only:
        print("\n".join(p2_study(a.out, a.reuse)))
        print(f"written to {a.out}/")
        return
    if a.methods_only:
        print("\n".join(methods_study(a.out, a.reuse)))
        print(f"written to {a.out}/")
        return
    if a.nh_only:
        print("\n".join(nh_study(a.out, a.reuse)))
        print(f"written to {a.out}/")
        return
    dts = DTS[1:4] if a.quick else DTS
    meshes = {k: v for k, v in MESHES.items() if not a.quick or k in ("coarse", "paper")}
    solvers = {k: v for k, v in SOLVERS.items() if not a.quick or k in ("ipopt 1e-8", "activeset")}
    runs = {}
    grid = [("test1", m, dt, s) for m in meshes for s in solvers for dt in dts if in_grid(m, s, dt)]
    grid += [("test2", "paper", dt, s) for s in ("ipopt 1e-8", "activeset") for dt in (0.1, 0.05, 0.025, 0.0125)
             if not a.quick or dt in dts]
    measured = measured_rows(os.path.join(a.out, "table.csv"), a.reuse,
                             key=lambda row: (row["test"], row["mesh"], float(row["dt"]), row["solver"]))
    for n, (test, mesh, dt, solver) in enumerate(grid):
        name = f"{test}_{mesh}_dt{dt}_{solver.replace(' ', '')}"
        old = measured.get((test, mesh, dt, solver))
        h = finished_history(os.path.join(a.out, name), old)
        if h is not None:
            runs[(test, mesh, dt, solver)] = dict({k: float(old[k]) for k in ("wall_s", "cpu_s", "ms_per_step", "peak_MiB")},
                                                  steps=int(old["steps"]), qp_steps=int(old["qp_steps"]), history=h)
            continue
        print(f"accuracy [{n + 1}/{len(grid)}]: {name}", flush=True)
        args = ["-T", str(T), "-dt", str(dt), "-mesh", meshes[mesh][0]] + solvers[solver]
        if test == "test2":
            args += ["-t1", "18"]
        runs[(test, mesh, dt, solver)] = run_case(a.out, name, test, args)
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
    with open(os.path.join(a.out, "table.csv"), "w") as f:
        f.write(",".join(keys) + "\n")
        for row in rows:
            f.write(",".join(f"{row[k]:.6g}" if isinstance(row[k], float) else str(row[k]) for k in keys) + "\n")
    md = ["| test | mesh | dt | solver | wall s | ms/step | peak MiB | max err u2 | L2 err u2 | err contact start / end | energy lost (err) |",
          "| --- | --- | ---: | --- | ---: | ---: | ---: | ---: | ---: | --- | --- |"]
    for r in rows:
        md.append(f"| {r['test']} | {r['mesh']} | {r['dt']} | {r['solver']} | {r['wall_s']:.1f} | {r['ms_per_step']:.2f} | "
                  f"{r['peak_MiB']:.0f} | {r['err_max']:.2e} | {r['err_l2']:.2e} | {r['err_start']:.2f} / {r['err_end']:.2f} | "
                  f"{r['energy_lost']:.3f} ({r['err_energy_lost']:.3f}) |")
    with open(os.path.join(a.out, "table.md"), "w") as f:
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
    with open(os.path.join(a.out, "orders.md"), "w") as f:
        f.write("\n".join(orders) + "\n")
    svk_md = []
    if not a.quick:
        svk_md, svk_histories = svk_study(a.out, a.reuse, finest_mesh)
        with open(os.path.join(a.out, "svk.md"), "w") as f:
            f.write("\n".join(svk_md) + "\n")
        svk_md += [""] + nh_study(a.out, a.reuse, svk_histories)
        p2_md = p2_study(a.out, a.reuse)
        p2_md += [""] + methods_study(a.out, a.reuse)

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
        fig.savefig(os.path.join(a.out, f"work_precision.{ext}"), dpi=150, bbox_inches="tight")
    print("\n".join(md))
    print()
    print("\n".join(orders))
    print()
    print("\n".join(svk_md))
    if not a.quick:
        print()
        print("\n".join(p2_md))
    print(f"written to {a.out}/")


if __name__ == "__main__":
    main()
