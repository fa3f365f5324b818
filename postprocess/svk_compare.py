"""`make svk`: the linear body, St Venant-Kirchhoff (-material svk) and Neo-Hookean
(-material neohookean) on the same axes.

Runs, --jobs at a time (2), into OUT/<case>/<model>/ (model: linear, svk, neohookean):
  test1        Test 1, T = 120 (paper's lambda = mu = 30): svk is expected to collapse during
               the first impact (exit 4, an inverted triangle); linear and Neo-Hookean run to T;
  test2_t1_18, test2_t1_22, test2_t1_26
               Test 2 with t1 = 18, 22, 26, T = 120: svk may collapse likewise;
  stiff        Test 1 with lambda = mu = 300, T = 120: all three must complete;
  spin         the spin scene (free flight, spinning, f = 0): all three must complete.
Every run has T = 120 (spin: 30); an svk run stops where it collapses, so it costs no more.
A run that stops with exit 4 and an "inverted" message is recorded (step, t, message) where a
collapse is expected (svk on the paper's cases); any other failure, a Neo-Hookean collapse
included, stops this script with a one-line error and exit status 1.
Draws (PNG and PDF) into OUT/ and writes OUT/summary.md.
"""
import argparse
import os
import re
import sys
import time

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import jobs  # noqa: E402
from driver import ROOT, run_case as run_driver  # noqa: E402
from history import read_csv, read_freefem_mesh, read_run  # noqa: E402
from svk_measures import Failure, metrics, snapshot_min_J, snapshots, uniaxial_stress  # noqa: E402

MODELS = ("linear", "svk", "neohookean")
MODEL_ARGS = {"linear": ["-solver", "activeset"], "svk": ["-material", "svk"],
              "neohookean": ["-material", "neohookean"]}
COLORS = {"linear": "tab:blue", "svk": "tab:red", "neohookean": "tab:green"}
LABELS = {"linear": "linear elastic", "svk": "St Venant-Kirchhoff", "neohookean": "Neo-Hookean"}
TOP_PROBE = ["-probes", "0,40"]            # u2 of the top vertex: the vertical diameter's change
PAPER = ["-T", "120"] + TOP_PROBE          # the paper's horizon; snapshots at the paper's times (Fig. 3)


def test2(t1, vm_times):
    return ("test2", ["-t1", str(t1)] + PAPER, f"Test 2, t1 = {t1} (lambda = mu = 30)", ("svk",), vm_times)


# case: (scene, options, title, models that may collapse, snapshot times of the von Mises figure)
CASES = {
    "test1": ("test1", PAPER, "Test 1 (lambda = mu = 30)", ("svk",), (11.4, 13.3, 15.25)),
    "test2_t1_18": test2(18, (15.25, 17.2, 19.15)),
    "test2_t1_22": test2(22, (11.4, 13.3, 15.25)),
    "test2_t1_26": test2(26, (11.4, 13.3, 15.25)),
    "stiff": ("test1", ["-lambda", "300", "-mu", "300"] + PAPER,
              "Test 1, stiff body (lambda = mu = 300)", (), (11.4, 13.3, 15.25)),
    "spin": ("spin", [], "Spinning free flight (f = 0, no foundation)", (), ()),
}
CONTACT_CASES = [c for c in CASES if c != "spin"]
BREAK_RE = re.compile(r"newton failed at step (\d+), t = ([-+0-9.eE]+)")


def run_one(out, case, model):
    scene, args, _, may_collapse, _ = CASES[case]
    run_dir = os.path.join(out, case, model)
    extra = list(MODEL_ARGS[model])
    if case == "spin" and model == "linear":
        extra = []                       # no foundation: no QP, -solver would only draw a warning
    p = run_driver(scene, run_dir, ["-progress", "0", "-vtk", "0"] + extra + args, log=os.path.join(out, case, f"{model}.log"),
                   cwd=ROOT)
    res = {"case": case, "model": model, "dir": run_dir, "wall": p.wall, "rc": p.returncode, "broke": None}
    if p.returncode == 0 and os.path.exists(os.path.join(run_dir, "summary.txt")):
        return res
    err = " ".join(line.strip() for line in p.stderr.splitlines() if line.startswith("error")) or p.stderr.strip()
    if p.returncode == 4 and "inverted" in p.stderr and model in may_collapse:
        m = BREAK_RE.search(p.stderr)
        if not m:
            raise Failure(f"{case}/{model}: exit 4 with an unreadable message: {err}")
        res["broke"] = {"step": int(m.group(1)), "t": float(m.group(2)), "message": err}
        return res
    raise Failure(f"{case}/{model} failed (exit {p.returncode}; see {case}/{model}.log): {err[:300]}")


def save(fig, out, name):
    for ext in ("png", "pdf"):
        fig.savefig(os.path.join(out, f"{name}.{ext}"), dpi=150, bbox_inches="tight")
    plt.close(fig)


def mark_break(ax, res, h, col):
    """A cross at the last recorded value and a dotted line, in the legend, at the collapse time."""
    b, c = res["broke"], COLORS[res["model"]]
    if b is None:
        return
    ax.axvline(b["t"], color=c, ls=":", lw=1, label=f"{LABELS[res['model']]} collapses: step {b['step']}, t = {b['t']:g}")
    ax.plot(h["t"][-1], h[col][-1], "x", color=c, ms=9, mew=2)


def plot_models(ax, runs, case, col):
    for model in MODELS:
        res, h = runs[(case, model)]
        ax.plot(h["t"], h[col], color=COLORS[model], lw=1, label=LABELS[model])
        mark_break(ax, res, h, col)


def plot_pair(runs, case, cols, ylabels, out, name, what):
    title = CASES[case][2]
    fig, axes = plt.subplots(1, len(cols), figsize=(6 * len(cols), 4))
    for ax, col, yl in zip(axes, cols, ylabels):
        plot_models(ax, runs, case, col)
        ax.set(xlabel="t", ylabel=yl, title=f"{title}: {what[col]}")
        ax.legend(fontsize=8)
    save(fig, out, name)


def plot_von_mises(runs, case, out, name):
    """The models on the deformed body at the case's snapshot times (before any collapse)."""
    dirs = {m: runs[(case, m)][0]["dir"] for m in MODELS}
    files = {m: dict(snapshots(dirs[m])) for m in MODELS}
    times = [t for t in CASES[case][4] if all(t in files[m] for m in MODELS)]
    if not times:
        return None
    snap = {(m, t): read_csv(files[m][t]) for m in MODELS for t in times}
    vmax = max(s["vonmises"].max() for s in snap.values())
    fig, axes = plt.subplots(len(MODELS), len(times), figsize=(3.6 * len(times), 3.7 * len(MODELS)), squeeze=False)
    for i, m in enumerate(MODELS):
        _, tri = read_freefem_mesh(os.path.join(dirs[m], "mesh.msh"))
        for j, t in enumerate(times):
            s, ax = snap[(m, t)], axes[i, j]
            tp = ax.tripcolor(s["x"] + s["u1"], s["y"] + s["u2"], tri, s["vonmises"], shading="gouraud",
                              vmin=0, vmax=vmax, cmap="jet")
            fpath = os.path.join(dirs[m], "foundation.csv")
            if os.path.exists(fpath):
                fd = read_csv(fpath)
                tk = fd["t"][np.argmin(np.abs(fd["t"] - t))]
                ax.plot(fd["X1"][fd["t"] == tk], fd["psi"][fd["t"] == tk], "k-", lw=1.5)
            ax.set_aspect("equal")
            ax.set_xlim(-25, 25)
            ax.set_ylim(-4, 42)
            ax.set_title(f"{LABELS[m]}, t = {t:g}\nmax {s['vonmises'].max():.1f}", fontsize=9)
            ax.axis("off")
    fig.colorbar(tp, ax=axes, shrink=0.6, label="von Mises stress (non-linear bodies: of the Cauchy stress)")
    fig.suptitle(f"{CASES[case][2]}: von Mises stress on the deformed body")
    save(fig, out, name)
    return times


def panels(n, w=5.0, h=3.8, cols=3):
    rows = (n + cols - 1) // cols
    fig, axes = plt.subplots(rows, cols, figsize=(w * cols, h * rows), squeeze=False)
    for ax in axes.flat[n:]:
        ax.axis("off")
    return fig, list(axes.flat[:n])


def plot_per_case(runs, col, ylabel, out, name, linear_points=None):
    """One panel per case, the models on the same axes. linear_points: case -> (t, value) pairs drawn
    as markers for the linear body, whose history has no such column."""
    fig, axes = panels(len(CASES))
    for ax, case in zip(axes, CASES):
        for model in MODELS:
            res, h = runs[(case, model)]
            if col in h:
                ax.plot(h["t"], h[col], color=COLORS[model], lw=1, label=LABELS[model])
                mark_break(ax, res, h, col)
            elif linear_points and linear_points.get(case):
                t, v = zip(*linear_points[case])
                ax.plot(t, v, "o", color=COLORS[model], ms=4, label=f"{LABELS[model]} (at the snapshots)")
        ax.set(xlabel="t", ylabel=ylabel, title=CASES[case][2])
        ax.title.set_fontsize(9)
        ax.legend(fontsize=7)
    fig.tight_layout()
    save(fig, out, name)


def plot_spin(runs, out, name):
    fig, axes = plt.subplots(1, 3, figsize=(17, 4))
    for model in MODELS:
        _, h = runs[("spin", model)]
        e, am = h["energy"], h["angular_momentum"]
        axes[0].semilogy(h["t"][1:], np.maximum(np.abs(e[1:] - e[0]) / abs(e[0]), 1e-17), color=COLORS[model],
                         lw=1, label=LABELS[model])
        axes[1].semilogy(h["t"][1:], np.maximum(np.abs(am[1:] - am[0]) / abs(am[0]), 1e-17), color=COLORS[model],
                         lw=1, label=LABELS[model])
        axes[2].plot(h["t"], h["max_strain"], color=COLORS[model], lw=1, label=LABELS[model])
    axes[0].set(xlabel="t", ylabel="|E(t) - E(0)| / E(0)", title="energy drift")
    axes[1].set(xlabel="t", ylabel="|L(t) - L(0)| / |L(0)|", title="angular momentum drift")
    axes[2].set(xlabel="t", ylabel="largest principal Green-Lagrange strain",
                title="strain of a rigid rotation (0.05 rad per unit t)")
    for ax in axes:
        ax.legend(fontsize=8)
    fig.suptitle(CASES["spin"][2], y=1.04)
    save(fig, out, name)


def plot_uniaxial(out, name, lam=30.0, mu=30.0):
    """Why the soft SVK body collapses and the Neo-Hookean one does not: the uniaxial-strain stress."""
    s = np.linspace(0.2, 1.3, 400)
    k = lam + 2 * mu
    fig, ax = plt.subplots(figsize=(6.5, 4))
    P = uniaxial_stress(s, lam, mu)
    formula = {"linear": "(lambda + 2 mu)(s - 1)", "svk": "(lambda + 2 mu) s (s^2 - 1) / 2",
               "neohookean": "mu (s - 1/s) + lambda ln(s) / s"}
    for model in MODELS:
        ax.plot(s, P[model], color=COLORS[model], label=f"{LABELS[model]}: {formula[model]}")
    sc = 1 / np.sqrt(3)
    ax.plot(sc, -k / (3 * np.sqrt(3)), "ko")
    ax.annotate(f"SVK's peak |P| = (lambda + 2 mu) / (3 sqrt 3) = {k / (3 * np.sqrt(3)):.1f}\nat s = 1/sqrt 3",
                (sc, -k / (3 * np.sqrt(3))), xytext=(0.3, -45), fontsize=8, arrowprops=dict(arrowstyle="->"))
    ax.axhline(0, color="gray", lw=0.5)
    ax.set_ylim(-60, 30)
    ax.set(xlabel="stretch s (uniaxial strain)", ylabel="first Piola-Kirchhoff stress P",
           title=f"uniaxial strain, lambda = mu = {lam:g}")
    ax.legend(fontsize=8)
    save(fig, out, name)


def status(res, m):
    if res["broke"]:
        return f"**collapsed** at step {res['broke']['step']}, t = {res['broke']['t']:g} (history to t = {m['t_end']:g})"
    return f"completed to T = {m['t_end']:g} ({m['steps']} steps)"


def fmt(pair, spec=".3g"):
    """(value, t) as 'value (t)'; '-' if there is none."""
    return "-" if pair is None or pair[0] is None else f"{pair[0]:{spec}} ({pair[1]:g})"


def case_tables(runs, case):
    L = []
    if case == "spin":
        L += ["| model | status | max strain | min J (t) | min J at the snapshots (t) | energy drift max abs(E - E0)/E0 | angular momentum drift "
              "max abs(L - L0)/abs(L0) | Newton it./step (mean, max) | wall s |",
              "| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |"]
    else:
        L += ["| model | status | first contact | bounces | impact v2 | rebound v2 (ratio) | rebound height (t) | "
              "peak alpha (t) | max penetration |",
              "| --- | --- | --- | ---: | ---: | ---: | ---: | ---: | ---: |"]
    body = ["", "| model | max compression (t) | max strain (t) | min J (t) | min J at the snapshots (t) | "
            "max von Mises at the snapshots (t) | modified energy start, end | largest one-step rise, fixed "
            "foundation | Newton it./step (mean, max) | wall s |",
            "| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |"]
    for model in MODELS:
        res, h = runs[(case, model)]
        m = metrics(res, h)
        newton = f"{m['newton_mean']:.2f}, {m['newton_max']}" if model != "linear" else "-"
        minJ = f"{fmt(m['min_J'], '.4f')} | {fmt(m['snapshot_min_J'], '.4f')}"
        if case == "spin":
            L.append(f"| {model} | {status(res, m)} | {m['max_strain'][0]:.4g} | {minJ} | {m['energy_drift']:.1e} | "
                     f"{m['am_drift']:.1e} | {newton} | {res['wall']:.1f} |")
            continue
        fc = m["first_contact"]
        first = "-" if fc is None else f"[{fc[0]:g}, {fc[1]:g}]" + (" (collapsed)" if "v_impact" not in m else "")
        if "v_impact" in m and m["v_rebound"] is not None:
            reb = f"{m['v_rebound']:.4f} ({-m['v_rebound'] / m['v_impact']:.3f})"
        else:
            reb = "-"
        vi = f"{m['v_impact']:.4f}" if "v_impact" in m else "-"
        L.append(f"| {model} | {status(res, m)} | {first} | {m['bounces']} | {vi} | {reb} | "
                 f"{fmt(m.get('rebound_height'), '.3f')} | {fmt(m['alpha'], '.2f')} | {m['max_pen']:.1e} |")
        e0, e1, rise = m["energy"]
        body.append(f"| {model} | {fmt(m['compression'], '.3f')} | {fmt(m['max_strain'], '.4f')} | {minJ} | "
                    f"{fmt(m['vm'], '.1f')} | {e0:.2f}, {e1:.2f} | {rise:.1e} ({rise / abs(e0):.1e} of E0) | "
                    f"{newton} | {res['wall']:.1f} |")
    return L + (body if case != "spin" else [])


def write_summary(runs, out, vm_times, wall, jobs):
    L = ["# make svk: the linear body, St Venant-Kirchhoff and Neo-Hookean", "",
         f"Written by postprocess/svk_compare.py ({len(runs)} runs, {wall:.0f} s wall, {jobs} at a time; "
         "lambda = mu = 30 unless stated, dt = 0.05, the paper's mesh). The linear body is solved by the exact "
         "active-set solver, the others by semi-smooth Newton.", "",
         "- First contact: the first interval with a node in contact (gaps under 0.5 merged); bounces: the number "
         "of such intervals. Impact and rebound v2: the mean vertical velocity of the body (its centre of mass) "
         "at the step before the first contact and the step after it; ratio = -rebound / impact. Rebound height: "
         "the highest u2 of the lowest point (0, 0) between the first and the second contact (Test 2's foundation "
         "is at -2 there after t1). Peak alpha: the contact stress at the lowest point, every step.",
         "- Compression: the largest shortening of the vertical diameter, u2(0, 0) - u2(0, 40). Max strain: the "
         "largest principal Green-Lagrange strain over the body. Min J: the smallest det F over the triangles, "
         "every step (the history's min_J; the linear body's history has none). At the snapshots: the paper's "
         "times 11.4 to 21.1, the first bounce (spin: 0, 15, 30), det F computed from the snapshot's displacements, for all "
         "three (for the non-linear bodies it equals min_J there, checked). Max von Mises: over the snapshots "
         "(non-linear bodies: of the Cauchy stress).",
         "- Modified energy: kinetic + stored - f.u (the paper's); the largest rise in one step counts only the "
         "steps during which the foundation is fixed (Test 2: before t0 = 9 and after t1), where the paper's "
         "scheme cannot create energy. Wall s: the run's wall time, "
         f"{jobs} runs at a time.", ""]
    for case in CASES:
        L += [f"## {case}: {CASES[case][2]}", ""] + case_tables(runs, case)
        for model in MODELS:
            res, _ = runs[(case, model)]
            if res["broke"]:
                L += ["", f"{model}: `{res['broke']['message']}`"]
        if vm_times.get(case):
            L += ["", f"Von Mises figure: t = {', '.join(f'{t:g}' for t in vm_times[case])}."]
        L.append("")
    k = (30 + 2 * 30) / (3 * np.sqrt(3))
    L += [f"SVK under uniaxial strain with lambda = mu = 30: |P| peaks at (lambda + 2 mu)/(3 sqrt 3) = {k:.2f} "
          "(stretch 1/sqrt 3); beyond it the stored energy is not convex. The Neo-Hookean stress grows without "
          "bound as the stretch goes to 0 (svk_uniaxial.png).", ""]
    with open(os.path.join(out, "summary.md"), "w") as f:
        f.write("\n".join(L))
    return "\n".join(L)


def main():
    p = jobs.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--out", default=os.path.join(ROOT, "results", "svk"))
    p.add_argument("--jobs", type=jobs.positive_int, default=2)
    jobs.add_processes_option(p)
    a = p.parse_args()
    jobs.use_processes(a.np)
    out = os.path.abspath(a.out)
    for case in CASES:
        os.makedirs(os.path.join(out, case), exist_ok=True)
    jobs.stop_on_interrupt("make svk", out, ["summary.md", "*.png", "*.pdf"])
    t0 = time.perf_counter()
    results = {}
    try:
        for res in jobs.run_parallel(lambda cm: run_one(out, *cm), [(c, m) for c in CASES for m in MODELS], a.jobs):
            b = res["broke"]
            print(f"svk: {res['case']}/{res['model']}: "
                  + (f"collapsed at step {b['step']}, t = {b['t']:g}" if b else "completed")
                  + f" ({res['wall']:.1f} s)", flush=True)
            results[(res["case"], res["model"])] = res
        wall = time.perf_counter() - t0
        runs = {k: (r, read_run(r["dir"])) for k, r in results.items()}
        what = {"u2_low": "u2 at the lowest point", "contact_pressure_low": "contact stress at the lowest point",
                "energy": "energy", "modified_energy": "modified energy"}
        vm_times = {}
        for case in CONTACT_CASES:
            plot_pair(runs, case, ["u2_low", "contact_pressure_low"],
                      ["u2 at (0, 0)", "contact stress alpha at (0, 0)"], out, f"svk_{case}_low_point", what)
            plot_pair(runs, case, ["energy", "modified_energy"], ["energy", "modified energy"], out,
                      f"svk_{case}_energy", what)
            vm_times[case] = plot_von_mises(runs, case, out, f"svk_{case}_von_mises")
        plot_per_case(runs, "max_strain", "largest principal Green-Lagrange strain", out, "svk_max_strain")
        linear_J = {case: snapshot_min_J(runs[(case, "linear")][0]["dir"]) for case in CASES}
        plot_per_case(runs, "min_J", "smallest det F over the body", out, "svk_min_J", linear_J)
        plot_spin(runs, out, "svk_spin")
        plot_uniaxial(out, "svk_uniaxial")
        print(write_summary(runs, out, vm_times, wall, a.jobs))
    except Failure as e:
        print(f"error: make svk: {e}", file=sys.stderr)
        sys.exit(1)
    print(f"figures and summary.md written to {out}/")


if __name__ == "__main__":
    main()
