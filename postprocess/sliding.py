"""`make sliding`: the exact gap against closed forms, and the paper's linearisation (10) on its own tests (docs/sliding.md).

The bowl scene (edp/scenes/bowl.idp): a body of radius r = 20 released at rest in a circular bowl of radius
R_b = 60 (3D: spherical), touching it with its centre at theta0 = 30 degrees from the bottom, g = 0.1. Its centre of
mass swings as a pendulum of length L = R_b - r, with the period, exact at any amplitude (K the complete elliptic
integral of the first kind):
  frictionless   the body slides without turning:      P = 4 sqrt(L / g) K(sin(theta0 / 2));
  rolling        Coulomb's F = 0.5, enough to stick:    P = 4 sqrt(c L / g) K(sin(theta0 / 2)), c = 1 + I / (m r^2):
                 3/2 for the disk, 7/5 for the ball.
The frictionless bodies are the scene's stiff linear ones (lambda = mu = 3000); the rolling ones are stiff
Neo-Hookean (a linear body cannot turn without straining: docs/friction.md). Each runs with -gap exact and, beside
it, with the paper's -gap linearised. The period is read from the turning points of the centre's horizontal
position: each is the vertex of the least-squares parabola through the 10 time units on either side of a sign change
of the mean velocity, and P is the least-squares slope of their times against k / 2 (t = 0 is the first, the release).
The paper's scenes: Test 1 and Test 2 (t1 = 18, 22, 26), under (10), with the largest max_penetration_exact and
max_held_off_exact of their histories: how far (10) is from the true foundation there (solved by the active set,
whose pressed nodes are exact: IPOPT at -tol leaves small multipliers on nodes above the foundation).
--only runs the cases it names; the summary covers every case of OUT that has a history. --np N (make sliding NP=N)
runs each case on N processes; one that -np refuses (the rolling bodies' friction) runs on one, with a note.
Writes OUT/summary.md, OUT/sliding.csv and OUT/sliding.png/.pdf (the disk's and the ball's centres); each run in OUT/<case>/. A run that fails stops the
study with one `error:` line and exit status 1.
"""
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import jobs  # noqa: E402
from driver import ROOT, run_case  # noqa: E402
from history import read_run, read_summary  # noqa: E402

G, R_BODY, R_BOWL, THETA0 = 0.1, 20.0, 60.0, 30.0
QUIET = ["-snapshots", "none", "-progress", "0"]
BALL = ["-mesh", os.path.join(ROOT, "meshes", "ball.msh")]
ROLLING = ["-material", "neohookean", "-friction", "coulomb", "-friction_coefficient", "0.5"]
# case: (scene, arguments, closed form's inertia factor c, or None for a paper scene)
CASES = {
    "disk frictionless exact": ("bowl", ["-T", "140"], 1.0),
    "disk frictionless linearised": ("bowl", ["-T", "140", "-gap", "linearised"], 1.0),
    "disk rolling exact": ("bowl", ROLLING + ["-T", "175"], 1.5),
    "disk rolling linearised": ("bowl", ROLLING + ["-T", "175", "-gap", "linearised"], 1.5),
    "ball frictionless exact": ("bowl", BALL + ["-T", "140"], 1.0),
    "ball frictionless linearised": ("bowl", BALL + ["-T", "140", "-gap", "linearised"], 1.0),
    "ball rolling exact": ("bowl", BALL + ROLLING + ["-T", "165"], 1.4),
    "ball rolling linearised": ("bowl", BALL + ROLLING + ["-T", "165", "-gap", "linearised"], 1.4),
    "Test 1": ("test1", ["-solver", "activeset"], None),
    "Test 2, t1 = 18": ("test2", ["-t1", "18", "-solver", "activeset"], None),
    "Test 2, t1 = 22": ("test2", ["-t1", "22", "-solver", "activeset"], None),
    "Test 2, t1 = 26": ("test2", ["-t1", "26", "-solver", "activeset"], None),
}


def elliptic_k(k):
    """The complete elliptic integral of the first kind K(k), by the arithmetic-geometric mean."""
    a, b = 1.0, math.sqrt(1.0 - k * k)
    while abs(a - b) > 1e-15 * a:
        a, b = (a + b) / 2, math.sqrt(a * b)
    return math.pi / (2 * a)


def pendulum_period(c, length=R_BOWL - R_BODY, theta0=THETA0, g=G):
    """4 sqrt(c L / g) K(sin(theta0 / 2)): the bowl's closed form (c = 1 sliding, 3/2 a rolling disk, 7/5 a ball)."""
    return 4 * math.sqrt(c * length / g) * elliptic_k(math.sin(math.radians(theta0) / 2))


def pendulum_angle(t, c, length=R_BOWL - R_BODY, theta0=THETA0, g=G):
    """theta(t) of theta'' = -(g / (c L)) sin(theta), released at rest at theta0 (RK4 on a fine grid)."""
    h, w2 = 0.01, g / (c * length)
    grid = np.arange(0.0, t.max() + h, h)
    th, om, out = math.radians(theta0), 0.0, []
    f = lambda a: -w2 * math.sin(a)  # noqa: E731
    for _ in grid:
        out.append(th)
        k1, l1 = om, f(th)
        k2, l2 = om + h / 2 * l1, f(th + h / 2 * k1)
        k3, l3 = om + h / 2 * l2, f(th + h / 2 * k2)
        k4, l4 = om + h * l3, f(th + h * k3)
        th, om = th + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4), om + h / 6 * (l1 + 2 * l2 + 2 * l3 + l4)
    return np.interp(t, grid, np.array(out))


def centre_x(h):
    """The centre of mass's horizontal displacement: u1_mean where a friction run records it, else the trapezoid
    integral of v1_mean (exact: the mid-point scheme's (2) is the trapezoid rule, and the mean is linear)."""
    if "u1_mean" in h:
        return h["u1_mean"]
    v, t = h["v1_mean"], h["t"]
    return np.concatenate([[0.0], np.cumsum(0.5 * (v[1:] + v[:-1]) * np.diff(t))]) + h["u1_low"][0]


def turning_times(h, window=10.0):
    """The turning points of the centre: the vertex of the least-squares parabola through x(t) on t +- window around
    each sign change of v1_mean (changes closer than a window to the last one are the same turn, its chatter). A turn
    made by an impact (the body in flight between them, as under (10) in the bowl: no node pressed at most steps of
    the window) is the sign change itself, interpolated."""
    t, v, x = h["t"], h["v1_mean"], centre_x(h)
    turns = []
    for i in np.where(np.sign(v[1:]) * np.sign(v[:-1]) < 0)[0]:
        tc = t[i]
        if tc < window or tc > t[-1] - window or (turns and tc - turns[-1] < 2 * window):
            continue
        m = np.abs(t - tc) <= window
        if np.mean(h["active_nodes"][m] > 0) < 0.5:
            turns.append(tc - v[i] * (t[i + 1] - tc) / (v[i + 1] - v[i]))
            continue
        c = np.polyfit(t[m] - tc, x[m], 2)
        turns.append(tc - c[1] / (2 * c[0]))
    return np.array(turns)


def period_of(h):
    """P from the turning times t_k = k P / 2 (k = 1, 2, ...; the release is k = 0): their least-squares slope."""
    turns = turning_times(h)
    if len(turns) == 0:
        return float("nan")
    k = np.arange(1, len(turns) + 1) / 2
    return float((k @ turns) / (k @ k))


def run_dir(out, case):
    return os.path.join(out, case.replace(" ", "_").replace(",", "").replace("=", ""))


def run_one(out, case):
    scene, args, _ = CASES[case]
    r = run_case(scene, run_dir(out, case), QUIET + args, merge=True)
    if r.returncode != 0:
        raise RuntimeError(f"{case}: edp/run.sh {scene} exited with {r.returncode}: {r.last_line}")
    return case, r.wall


def energy_change(h):
    e = h["modified_energy"]
    return float((e[-1] - e[0]) / abs(e[0]))


def figure(out, runs):
    """The centre's X1 against the closed form's, -gap exact and linearised: the disk, and the ball where it ran."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    bodies = [b for b in ("disk", "ball") if all(f"{b} {k} {g}" in runs for k in ("frictionless", "rolling")
                                                  for g in ("exact", "linearised"))]
    fig, axes = plt.subplots(len(bodies), 2, figsize=(9, 3.4 * len(bodies)), layout="constrained", squeeze=False)
    for row, body in zip(axes, bodies):
        for ax, kind in zip(row, ("frictionless", "rolling")):
            c = 1.0 if kind == "frictionless" else (1.5 if body == "disk" else 1.4)
            h = runs[f"{body} {kind} exact"]
            t = h["t"]
            ax.plot(t, (R_BOWL - R_BODY) * np.sin(pendulum_angle(t, c)), "k-", lw=1, label="closed form (rigid pendulum)")
            ax.plot(t, centre_x(h), "-", label="-gap exact")
            hl = runs[f"{body} {kind} linearised"]
            ax.plot(hl["t"], centre_x(hl), "--", label="-gap linearised (the paper's (10))")
            ax.set(xlabel="t", ylabel="centre's X1", title=f"the {body} in the bowl, {kind}")
            ax.legend(fontsize=7)
    for ext in ("png", "pdf"):
        fig.savefig(os.path.join(out, f"sliding.{ext}"), dpi=110)


def main():
    ap = jobs.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", default="results/sliding")
    ap.add_argument("--jobs", type=jobs.positive_int, default=2)
    ap.add_argument("--only", default="", help="the cases to run, separated by semicolons (default: all)")
    jobs.add_processes_option(ap)
    a = ap.parse_args()
    jobs.use_processes(a.np)
    out = os.path.abspath(a.out)
    os.makedirs(out, exist_ok=True)
    jobs.stop_on_interrupt("make sliding", out, ["summary.md", "sliding.csv", "*.png", "*.pdf"])
    cases = [c for c in CASES if not a.only or c in a.only.split(";")]
    try:
        for case, seconds in jobs.run_parallel(lambda c: run_one(out, c), cases, a.jobs):
            print(f"sliding {case}: {seconds:.0f} s", flush=True)
    except RuntimeError as e:
        sys.exit(f"error: {e}")
    runs = {c: read_run(run_dir(out, c)) for c in CASES if os.path.exists(os.path.join(run_dir(out, c), "history.csv"))}
    cases = list(runs)
    size = 2 * R_BODY
    lines = ["| case | period | closed form | difference | max_penetration_exact / size | max_held_off_exact / size "
             "| energy change | exact-gap rounds / step |", "| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |"]
    csv = ["case,period,closed_form,difference,max_penetration_exact,max_held_off_exact,energy_change,rounds_per_step"]
    for c in cases:
        h, c_inertia = runs[c], CASES[c][2]
        pen, held = float(np.max(h["max_penetration_exact"])), float(np.max(h["max_held_off_exact"]))
        rounds = int(read_summary(run_dir(out, c)).get("exact_gap_rounds", 0)) / (len(h["t"]) - 1)
        if c_inertia is None:
            period = want = diff = float("nan")
            cells = "| | | | "
        else:
            period, want = period_of(h), pendulum_period(c_inertia)
            diff = period / want - 1
            cells = f"| {period:.2f} | {want:.2f} | {100 * diff:+.2f}% | "
        lines.append(f"| {c} {cells}{pen / size:.2e} | {held / size:.2e} | {100 * energy_change(h):+.2f}% | {rounds:.2f} |")
        csv.append(f"{c},{period:.9g},{want:.9g},{diff:.6g},{pen:.6g},{held:.6g},{energy_change(h):.6g},{rounds:.4g}")
    text = "\n".join(lines)
    with open(os.path.join(out, "summary.md"), "w") as f:
        f.write(text + "\n")
    with open(os.path.join(out, "sliding.csv"), "w") as f:
        f.write("\n".join(csv) + "\n")
    if all(f"disk {k} {g}" in runs for k in ("frictionless", "rolling") for g in ("exact", "linearised")):
        figure(out, runs)
    print(text)
    print(f"sliding: {os.path.join(a.out, 'summary.md')}")


if __name__ == "__main__":
    main()
