"""What the studies of make accuracy share (postprocess/accuracy.py): the grid of dt and meshes, Test 1's
horizon, the times all runs share (t = 0.2 k), the errors and observed orders measured on them, and the
runs (driver.case_row) made or reused from an earlier --out."""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from driver import case_row  # noqa: E402
from history import read_run  # noqa: E402

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
    is not run again (its wall_s is then nan). Returns {name: case_row's dict, or the reused history}."""
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
        runs[name] = case_row(out, name, scene, ["-T", f"{t_end:g}"] + extra + args)
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


def order(xs, ys):
    """Least-squares slope of log(y) against log(x)."""
    xs, ys = np.array(xs), np.array(ys)
    keep = ys > 0
    return np.polyfit(np.log(xs[keep]), np.log(ys[keep]), 1)[0] if keep.sum() >= 2 else float("nan")


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
