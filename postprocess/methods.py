"""`make methods`: the methods the paper measures itself against, side by side with its own
(docs/methods.md).

Runs Test 1 and Test 2 (t1 = 18) to T = 45 with each method of MAKE_METHODS (METHODS, then
QUADRATURE_METHODS), --jobs at a time (2), into OUT/<test>/<method>/, and writes into OUT/:
  methods_<test>_low_point.png/pdf   u2 at the lowest point (shared axes) and alpha there (small multiples)
  methods_<test>_energy.png/pdf      energy and modified energy (shared axes)
  methods_<test>_alpha_zoom.png/pdf  alpha at the lowest point on [10, 23], one panel per method
  methods_<test>_von_mises.png/pdf   von Mises stress at t = 15.25, one panel per method
  summary.md, table.csv              the table per method (columns below)
A run that the energy guard stops (exit 4, one line: its modified energy gained more than 10% of
its energy where Prop. 2 allows none; docs/errors.md) is a result of this study, not a failure: its
row says where it stopped, and its curves end there. Any other failed run stops this script with
one error line and exit status 1.
"""
import argparse
import csv
import os
import sys
import time

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import jobs  # noqa: E402
from driver import ROOT, run_case as run_driver  # noqa: E402
from history import contact_intervals, error_lines, guard_stop, read_csv, read_freefem_mesh, read_run, read_summary  # noqa: E402

T = "45"
SNAPSHOT = 15.25
# name: (label, options). The paper's method first; its QP is solved exactly (activeset). Penalty and
# Nitsche integrate their contact term with the vertex rule (the default) unless the label says gauss.
METHODS = {
    "paper": ("mid-point + constraint (the paper)", ["-solver", "activeset"]),
    "singular": ("mid-point + singular mass", ["-mass", "singular", "-solver", "activeset"]),
    "lumped": ("mid-point + lumped mass", ["-mass", "lumped", "-solver", "activeset"]),
    "penalty_1e-3": ("mid-point + penalty, eps = 1e-3", ["-contact", "penalty", "-penalty_eps", "1e-3"]),
    "penalty_1e-4": ("mid-point + penalty, eps = 1e-4", ["-contact", "penalty", "-penalty_eps", "1e-4"]),
    "nitsche_1": ("mid-point + Nitsche, theta = 1", ["-contact", "nitsche", "-nitsche_theta", "1"]),
    "nitsche_0": ("mid-point + Nitsche, theta = 0", ["-contact", "nitsche", "-nitsche_theta", "0"]),
    "nitsche_-1": ("mid-point + Nitsche, theta = -1", ["-contact", "nitsche", "-nitsche_theta", "-1"]),
    "verlet_nitsche": ("explicit Verlet + Nitsche, theta = 1, dt = 0.01 ([3])",
                       ["-scheme", "verlet", "-contact", "nitsche", "-dt", "0.01"]),
    "verlet_penalty": ("explicit Verlet + penalty 1e-3, dt = 0.01", ["-scheme", "verlet", "-contact", "penalty", "-dt", "0.01"]),
    "newmark": ("Newmark (1/4, 1/2) + constraint", ["-scheme", "newmark", "-solver", "activeset"]),
    "newmark_damped": ("Newmark (0.3025, 0.6) + constraint",
                       ["-scheme", "newmark", "-newmark_beta", "0.3025", "-newmark_gamma", "0.6", "-solver", "activeset"]),
}
# The methods that run to T on Test 1, to be timed (make bench) and converged in dt (make accuracy): all
# but the classical Newmark, which the energy guard stops in its first impact (docs/errors.md)
RUNNING_METHODS = {m: v for m, v in METHODS.items() if m != "newmark"}
# The rows of Claim 2 again with the contact term on Gauss points (-contact_quadrature gauss): the
# quadrature of penalty and Nitsche is a choice the comparison depends on (docs/methods.md). make methods
# runs them after the twelve; make accuracy and make bench keep the twelve of METHODS.
QUADRATURE_METHODS = {
    "penalty_1e-3_gauss": ("mid-point + penalty, eps = 1e-3, gauss", ["-contact", "penalty", "-penalty_eps", "1e-3",
                                                                       "-contact_quadrature", "gauss"]),
    "nitsche_1_gauss": ("mid-point + Nitsche, theta = 1, gauss", ["-contact", "nitsche", "-nitsche_theta", "1",
                                                                  "-contact_quadrature", "gauss"]),
    "verlet_nitsche_gauss": ("explicit Verlet + Nitsche, theta = 1, dt = 0.01, gauss",
                             ["-scheme", "verlet", "-contact", "nitsche", "-dt", "0.01", "-contact_quadrature", "gauss"]),
    "verlet_penalty_gauss": ("explicit Verlet + penalty 1e-3, dt = 0.01, gauss",
                             ["-scheme", "verlet", "-contact", "penalty", "-dt", "0.01", "-contact_quadrature", "gauss"]),
}
MAKE_METHODS = {**METHODS, **QUADRATURE_METHODS}
TESTS = {"test1": ("test1", [], "Test 1 (fixed foundation)"),
         "test2": ("test2", ["-t1", "18"], "Test 2, t1 = 18 (moving foundation)")}
COLUMNS = ["test", "method", "stopped_at", "contact_start", "contact_end", "rebound_height", "alpha_oscillation", "alpha_oscillation_005",
           "max_penetration",
           "modified_energy_change", "largest_step_gain", "wall_s", "ms_per_step"]


class Failure(Exception):
    pass


def run_one(out, test, method):
    scene, targs, _ = TESTS[test]
    run_dir = os.path.join(out, test, method)
    p = run_driver(scene, run_dir, ["-progress", "0", "-vtk", "0", "-T", T, "-snapshots", f"{SNAPSHOT:g}"] + targs + MAKE_METHODS[method][1],
                   log=os.path.join(out, test, f"{method}.log"), cwd=ROOT)
    errors = error_lines(p.stderr)
    stopped = p.returncode == 4 and guard_stop(p.stderr) is not None
    if not stopped and (p.returncode != 0 or not os.path.exists(os.path.join(run_dir, "summary.txt"))):
        err = " ".join(line.strip() for line in errors) or p.stderr.strip()
        raise Failure(f"{test}/{method} failed (exit {p.returncode}; see {test}/{method}.log): {err[:300]}")
    warnings = [line for line in p.stderr.splitlines() if line.startswith("warning: the modified energy")]
    return {"test": test, "method": method, "dir": run_dir, "wall": p.wall, "warning": warnings[0] if warnings else "",
            "stopped": errors[0] if stopped else ""}


def oscillation(t, alpha, lo=10.0, hi=23.0, width=1.0):
    """RMS of alpha minus its centred moving average over `width`, on [lo, hi]."""
    n = int(round(width / (t[1] - t[0])))
    avg = np.convolve(alpha, np.ones(n + 1) / (n + 1), mode="same")
    s = (t >= lo) & (t <= hi)
    if t[-1] < hi:                        # (a run stopped before the window's end: not measured)
        return float("nan")
    return float(np.sqrt(np.mean((alpha - avg)[s] ** 2)))


def metrics(res):
    h = read_run(res["dir"])
    t, m = h["t"], h["modified_energy"]
    first = contact_intervals(t, h["active_nodes"] > 0)
    window = (t >= 24) & (t <= 40)
    steps = len(t) - 1
    every = max(1, int(round(0.05 / (t[1] - t[0]))))
    # (a run the energy guard stopped has no summary.txt, so no CPU time: '-')
    cpu = float(read_summary(res["dir"])["cpu_seconds"]) if not res["stopped"] else float("nan")
    ended = res["stopped"] == "" or (first and t[-1] > first[0][1])     # its first impact ended before the stop
    return {"test": res["test"], "method": res["method"], "stopped_at": float(t[-1]) if res["stopped"] else float("nan"),
            "contact_start": first[0][0] if first else float("nan"),
            "contact_end": first[0][1] if first and ended else float("nan"),
            "rebound_height": float(h["u2_low"][window].max()) if window.any() else float("nan"),
            "alpha_oscillation": oscillation(t, h["contact_pressure_low"]),
            # on the paper's grid (dt = 0.05), so that a finer step does not change what is measured
            "alpha_oscillation_005": oscillation(t[::every], h["contact_pressure_low"][::every]),
            "max_penetration": float(h["max_penetration"].max()),
            "modified_energy_change": float(m[-1] - m[0]), "largest_step_gain": float(np.diff(m).max()),
            "wall_s": res["wall"], "ms_per_step": 1000 * cpu / steps}


def save(fig, out, name):
    for ext in ("png", "pdf"):
        fig.savefig(os.path.join(out, f"{name}.{ext}"), dpi=130, bbox_inches="tight")
    plt.close(fig)


def grid(n, w=3.2, h=2.4):
    cols = 4
    rows = (n + cols - 1) // cols
    fig, axes = plt.subplots(rows, cols, figsize=(w * cols, h * rows), squeeze=False, sharex=True, sharey=True)
    axes = list(axes.flat)
    for ax in axes[n:]:
        ax.axis("off")
    return fig, axes[:n]


def plot_test(runs, test, out):
    title = TESTS[test][2]
    colors = plt.cm.tab20(np.linspace(0, 1, len(MAKE_METHODS)))
    hist = {m: read_run(runs[(test, m)]["dir"]) for m in MAKE_METHODS}
    paper = hist["paper"]
    # u2 (shared axes) and energies (shared axes)
    fig, axes = plt.subplots(1, 3, figsize=(18, 4.2))
    for c, (m, h) in zip(colors, hist.items()):
        lw = 2 if m == "paper" else 0.9
        axes[0].plot(h["t"], h["u2_low"], color=c, lw=lw, label=MAKE_METHODS[m][0])
        axes[1].plot(h["t"], h["energy"], color=c, lw=lw)
        axes[2].plot(h["t"], h["modified_energy"], color=c, lw=lw)
    axes[0].set(xlabel="t", ylabel="u2 at the lowest point", title=f"{title}: u2 at the lowest point")
    axes[1].set(xlabel="t", ylabel="energy", title="energy (Fig. 2/6, left)")
    axes[2].set(xlabel="t", ylabel="modified energy", title="modified energy (Fig. 2/6, right)")
    axes[0].legend(fontsize=6, loc="upper right")
    save(fig, out, f"methods_{test}_low_point_energy")
    # alpha: small multiples, the paper's in grey on each
    for name, lo_t, hi_t in (("alpha", 0, float(T)), ("alpha_zoom", 10, 23)):
        fig, axes = grid(len(MAKE_METHODS))
        for ax, c, (m, h) in zip(axes, colors, hist.items()):
            s = (h["t"] >= lo_t) & (h["t"] <= hi_t)
            sp = (paper["t"] >= lo_t) & (paper["t"] <= hi_t)
            if m != "paper":
                ax.plot(paper["t"][sp], paper["contact_pressure_low"][sp], color="0.75", lw=0.8)
            ax.plot(h["t"][s], h["contact_pressure_low"][s], color=c, lw=0.9)
            ax.set_title(MAKE_METHODS[m][0], fontsize=7)
        # (the scale of the runs that reached T: a run the energy guard stopped spikes before it stops)
        ymax = max(np.percentile(h["contact_pressure_low"], 99.9) for m, h in hist.items() if not runs[(test, m)]["stopped"])
        for ax, m in zip(axes, hist):
            if runs[(test, m)]["stopped"]:
                ax.text(0.5, 0.9, f"stopped by the energy guard at t = {hist[m]['t'][-1]:g}", ha="center", fontsize=6,
                        transform=ax.transAxes)
        for ax in axes:
            ax.set_ylim(-1, 1.15 * ymax)
        fig.suptitle(f"{title}: contact stress alpha at the lowest point" + (" on [10, 23]" if lo_t else "")
                     + " (grey: the paper's method)", y=1.01)
        save(fig, out, f"methods_{test}_{name}")
    # von Mises at t = 15.25
    fig, axes = grid(len(MAKE_METHODS), 3.0, 2.6)
    vmax = 0
    snaps = {}
    for m in MAKE_METHODS:
        p = os.path.join(runs[(test, m)]["dir"], f"snapshot_t{SNAPSHOT:g}.csv")
        if os.path.exists(p):            # (not for a run the energy guard stopped before)
            snaps[m] = read_csv(p)
            vmax = max(vmax, snaps[m]["vonmises"].max())
    for ax, m in zip(axes, MAKE_METHODS):
        if m not in snaps:
            ax.text(0.5, 0.5, f"stopped by the energy guard\nat t = {hist[m]['t'][-1]:g}", ha="center", va="center",
                    fontsize=7, transform=ax.transAxes)
            ax.set_title(MAKE_METHODS[m][0], fontsize=6)
            ax.axis("off")
            continue
        s = snaps[m]
        _, tri = read_freefem_mesh(os.path.join(runs[(test, m)]["dir"], "mesh.msh"))
        tp = ax.tripcolor(s["x"] + s["u1"], s["y"] + s["u2"], tri, s["vonmises"], shading="gouraud", vmin=0, vmax=vmax, cmap="jet")
        ax.set_aspect("equal")
        ax.set_title(f"{MAKE_METHODS[m][0]}\nmax {s['vonmises'].max():.1f}", fontsize=6)
        ax.set_xticks([])
        ax.set_yticks([])
    fig.colorbar(tp, ax=list(axes), shrink=0.5, label="von Mises stress", extend="max")
    fig.suptitle(f"{title}: von Mises stress at t = {SNAPSHOT:g}")
    save(fig, out, f"methods_{test}_von_mises")


def fmt(v, spec):
    return "-" if v != v else format(v, spec)


def write_summary(rows, runs, out, wall, jobs):
    with open(os.path.join(out, "table.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=COLUMNS)
        w.writeheader()
        for r in rows:
            w.writerow({k: (f"{r[k]:.6g}" if isinstance(r[k], float) else r[k]) for k in COLUMNS})
    L = ["# make methods: the methods of the paper's references beside its own", "",
         f"Written by postprocess/methods.py ({len(rows)} runs to T = {T}, {wall:.0f} s wall, {jobs} at a time). "
         "First impact = the first contact interval of the lowest point's neighbourhood (any node active). "
         "Rebound = max u2 at the lowest point on [24, 40]. alpha osc. = RMS of the contact stress at the lowest point "
         "minus its centred moving average over 1.0, on [10, 23], at every step of the run; (0.05 grid) the same on the "
         "paper's step times only (every 5th step at dt = 0.01), so that methods with different dt compare. Energy change = modified energy at the end minus at 0; "
         "largest gain = the largest one-step rise of the modified energy. ms/step = CPU time per step "
         f"({jobs} runs at a time). A run the energy guard stopped (its modified energy gained more than 10% of its energy "
         "where Prop. 2 allows none: docs/errors.md) is marked with the time it stopped, its line below the table; "
         "'-' is a value it did not reach.", ""]
    for test in TESTS:
        L += [f"## {TESTS[test][2]}", "",
              "| method | first impact | rebound | alpha osc. | alpha osc. (0.05 grid) | max penetration | energy change | "
              "largest gain | wall s | ms/step |",
              "| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |"]
        for r in rows:
            if r["test"] != test:
                continue
            label = MAKE_METHODS[r['method']][0]
            if r["stopped_at"] == r["stopped_at"]:
                label += f" (**stopped at t = {r['stopped_at']:g}**)"
            L.append(f"| {label} | [{fmt(r['contact_start'], 'g')}, {fmt(r['contact_end'], 'g')}] | "
                     f"{fmt(r['rebound_height'], '.3f')} | {fmt(r['alpha_oscillation'], '.3f')} | "
                     f"{fmt(r['alpha_oscillation_005'], '.3f')} | "
                     f"{r['max_penetration']:.2g} | "
                     f"{r['modified_energy_change']:.4g} | {r['largest_step_gain']:.2g} | {r['wall_s']:.1f} | "
                     f"{fmt(r['ms_per_step'], '.2f')} |")
        warned = [(m, runs[(test, m)]["warning"] or runs[(test, m)]["stopped"]) for m in MAKE_METHODS
                  if runs[(test, m)]["warning"] or runs[(test, m)]["stopped"]]
        for m, w in warned:
            L += ["", f"{MAKE_METHODS[m][0]}: `{w}`"]
        L.append("")
    with open(os.path.join(out, "summary.md"), "w") as f:
        f.write("\n".join(L))
    return "\n".join(L)


def main():
    p = jobs.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--out", default=os.path.join(ROOT, "results", "methods"))
    p.add_argument("--jobs", type=jobs.positive_int, default=2)
    jobs.add_processes_option(p)
    a = p.parse_args()
    jobs.use_processes(a.np)
    out = os.path.abspath(a.out)
    for test in TESTS:
        os.makedirs(os.path.join(out, test), exist_ok=True)
    # nothing stale that looks current, should this run fail or be stopped
    jobs.stop_on_interrupt("make methods", out, ["summary.md", "table.csv", "*.png", "*.pdf"])
    t0 = time.perf_counter()
    runs = {}
    try:
        for res in jobs.run_parallel(lambda tm: run_one(out, *tm), [(t, m) for t in TESTS for m in MAKE_METHODS], a.jobs):
            print(f"methods: {res['test']}/{res['method']} ({res['wall']:.1f} s)", flush=True)
            runs[(res["test"], res["method"])] = res
    except Failure as e:
        print(f"error: make methods: {e}", file=sys.stderr)
        sys.exit(1)
    wall = time.perf_counter() - t0
    rows = [metrics(runs[(t, m)]) for t in TESTS for m in MAKE_METHODS]
    for test in TESTS:
        plot_test(runs, test, out)
    print(write_summary(rows, runs, out, wall, a.jobs))
    print(f"figures, table.csv and summary.md written to {out}/")


if __name__ == "__main__":
    main()
