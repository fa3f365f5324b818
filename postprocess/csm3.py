"""`make csm3`: the Turek-Hron CSM3 benchmark against its published values.

Runs the csm3 scene (St Venant-Kirchhoff bar clamped to a cylinder, gravity, from rest)
to T = 5 on the default mesh, order and dt, and its convergence in the mesh (refine 0.5,
1, 2), in dt (0.01, 0.005, 0.0025) and in the order (P1 against P2), two runs at a time,
into OUT/<case>/. From the history of point A (u1_probe0, u2_probe0) it measures, as
Turek & Hron do, mean = (max + min) / 2 and amplitude = (max - min) / 2 of each
component, and the frequency from the upward crossings of the mean. Writes
OUT/summary.md (the table) and OUT/csm3.png/.pdf (u_x, u_y of A against t).
A run that fails stops this script with a one-line error and exit status 1.
"""
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import jobs  # noqa: E402
from driver import ROOT, run_case as run_driver  # noqa: E402
from history import read_run, read_summary  # noqa: E402

# Turek & Hron (2006), Table "CSM3", finest level: mean +- amplitude [frequency], x 1e-3 m
REFERENCE = {"ux": (-14.305, 14.305, 1.0995), "uy": (-63.607, 65.160, 1.0995)}

# case: (label, options); the first is the default of the scene
CASES = {
    "default": ("P2, refine 1 (60 x 4), dt 0.005 (the scene's default)", []),
    "coarse": ("P2, refine 0.5 (30 x 2), dt 0.005", ["-mesh", "meshes/csm3_coarse.msh"]),
    "fine": ("P2, refine 2 (120 x 8), dt 0.005", ["-mesh", "meshes/csm3_fine.msh"]),
    "dt0.01": ("P2, refine 1, dt 0.01", ["-dt", "0.01"]),
    "dt0.0025": ("P2, refine 1, dt 0.0025", ["-dt", "0.0025"]),
    "p1": ("P1, refine 1, dt 0.005", ["-order", "1"]),
    "p1fine": ("P1, refine 2, dt 0.005", ["-order", "1", "-mesh", "meshes/csm3_fine.msh"]),
}


class Failure(Exception):
    pass


def run_case(out, case):
    run_dir = os.path.join(out, case)
    p = run_driver("csm3", run_dir, CASES[case][1] + ["-progress", "0"], cwd=ROOT)
    if p.returncode != 0:
        line = p.last_line
        raise Failure(f"csm3 {case} failed (exit {p.returncode}): {line}")
    return case, p.wall


def oscillation(t, u):
    """Mean, amplitude and frequency of u(t): (max + min) / 2, (max - min) / 2, and
    (crossings - 1) / (time between the first and last upward crossing of the mean)."""
    mean, amplitude = (u.max() + u.min()) / 2, (u.max() - u.min()) / 2
    s = u - mean
    k = np.where((s[:-1] < 0) & (s[1:] >= 0))[0]
    crossings = t[k] - s[k] * (t[k + 1] - t[k]) / (s[k + 1] - s[k])
    frequency = (len(crossings) - 1) / (crossings[-1] - crossings[0]) if len(crossings) > 1 else float("nan")
    return mean, amplitude, frequency


def measure(run_dir):
    h = read_run(run_dir)
    t = h["t"]
    return {"ux": oscillation(t, 1e3 * h["u1_probe0"]), "uy": oscillation(t, 1e3 * h["u2_probe0"]), "t": t,
            "u": (1e3 * h["u1_probe0"], 1e3 * h["u2_probe0"])}


def percent(value, reference):
    return 100 * (value - reference) / abs(reference)


def main():
    ap = jobs.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", default="results/csm3")
    ap.add_argument("--cases", default=",".join(CASES), help="comma-separated subset of " + ",".join(CASES))
    ap.add_argument("--jobs", type=jobs.positive_int, default=2)
    jobs.add_processes_option(ap)
    a = ap.parse_args()
    jobs.use_processes(a.np)
    out = os.path.abspath(a.out)
    cases = a.cases.split(",")
    for c in cases:
        if c not in CASES:
            sys.exit(f"error: --cases: no case '{c}' (cases: {', '.join(CASES)})")
    os.makedirs(out, exist_ok=True)
    jobs.stop_on_interrupt("make csm3", out, ["summary.md", "*.png", "*.pdf"])
    wall = {}
    try:
        for case, seconds in jobs.run_parallel(lambda c: run_case(out, c), cases, a.jobs):
            wall[case] = seconds
            print(f"csm3 {case}: {seconds:.0f} s", flush=True)
    except Failure as e:
        sys.exit(f"error: {e}")

    rows = ["| case | u_x(A) mean | amplitude | frequency | u_y(A) mean | amplitude | frequency | steps | CPU s |",
            "|---|---|---|---|---|---|---|---|---|"]
    ref = REFERENCE
    rows.append(f"| Turek & Hron (2006) | {ref['ux'][0]:.3f} | {ref['ux'][1]:.3f} | {ref['ux'][2]:.4f} | "
                f"{ref['uy'][0]:.3f} | {ref['uy'][1]:.3f} | {ref['uy'][2]:.4f} | | |")
    measured = {}
    for case in cases:
        m = measure(os.path.join(out, case))
        measured[case] = m
        s = read_summary(os.path.join(out, case))
        cells = []
        for comp in ("ux", "uy"):
            for k in range(3):
                cells.append(f"{m[comp][k]:.3f} ({percent(m[comp][k], ref[comp][k]):+.1f}%)" if k < 2
                             else f"{m[comp][k]:.4f} ({percent(m[comp][k], ref[comp][k]):+.1f}%)")
        rows.append(f"| {CASES[case][0]} | " + " | ".join(cells) + f" | {s['steps']} | {float(s['cpu_seconds']):.0f} |")
    table = "\n".join(rows)
    with open(os.path.join(out, "summary.md"), "w") as f:
        f.write("# Turek-Hron CSM3: displacement of A (x 1e-3 m), mean +- amplitude and frequency (Hz) over t in [0, 5]\n\n")
        f.write("Percentages: difference from the published value, relative to it.\n\n")
        f.write(table + "\n")
    print(table)

    if "default" in measured:
        m = measured["default"]
        fig, axes = plt.subplots(2, 1, figsize=(8, 6), sharex=True)
        for ax, comp, u in zip(axes, ("ux", "uy"), m["u"]):
            ax.plot(m["t"], u, color="tab:red", lw=1, label="this suite (P2, default)")
            mean, amp, _ = ref[comp]
            for level, style in ((mean, "-"), (mean - amp, "--"), (mean + amp, "--")):
                ax.axhline(level, color="k", ls=style, lw=0.7)
            ax.set_ylabel(f"{comp[1]} displacement of A (mm)")
        axes[0].legend(loc="upper right", fontsize=8)
        axes[1].set_xlabel("t (s)")
        axes[0].set_title("CSM3: black lines are Turek & Hron's mean and mean +- amplitude")
        fig.tight_layout()
        for ext in ("png", "pdf"):
            fig.savefig(os.path.join(out, f"csm3.{ext}"), dpi=120)
    print(f"csm3: {os.path.join(a.out, 'summary.md')}")


if __name__ == "__main__":
    main()
