"""`make svk`: the St Venant-Kirchhoff body (-material svk) next to the linear one.

Runs, --jobs at a time (2), into OUT/<case>/<model>/ (model: linear, svk):
  test1   Test 1, T = 45 (paper's lambda = mu = 30): svk is expected to collapse
          during the first impact (exit 4, an inverted triangle);
  test2   Test 2 with t1 = 18, T = 45: svk is expected to collapse likewise;
  stiff   Test 1 with lambda = mu = 300, T = 120: both must complete;
  spin    the spin scene (free flight, spinning, f = 0): both must complete.
A run that stops with exit 4 and an "inverted" message is recorded (step, t,
message) where a collapse is expected; any other failure stops this script with
a one-line error and exit status 1.
Draws (PNG and PDF) into OUT/ and writes OUT/summary.md.
"""
import argparse
import glob
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
from history import read_csv, read_freefem_mesh, read_run, read_summary  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
RUN = os.path.join(ROOT, "edp", "run.sh")
MODELS = ("linear", "svk")
MODEL_ARGS = {"linear": ["-solver", "activeset"], "svk": ["-material", "svk"]}
COLORS = {"linear": "tab:blue", "svk": "tab:red"}
LABELS = {"linear": "linear elastic", "svk": "St Venant-Kirchhoff"}
TOP_PROBE = ["-probes", "0,40"]            # u2 of the top vertex: the vertical diameter's change

# case: (scene, options, title, models that may collapse, snapshot times of the von Mises figure)
CASES = {
    "test1": ("test1", ["-T", "45"] + TOP_PROBE, "Test 1 (lambda = mu = 30)", ("svk",),
              (11.4, 13.3, 15.25)),
    "test2": ("test2", ["-t1", "18", "-T", "45"] + TOP_PROBE, "Test 2, t1 = 18 (lambda = mu = 30)", ("svk",),
              (15.25, 17.2, 19.15)),
    "stiff": ("test1", ["-lambda", "300", "-mu", "300", "-T", "120"] + TOP_PROBE,
              "Test 1, stiff body (lambda = mu = 300)", (), (11.4, 13.3, 15.25)),
    "spin": ("spin", [], "Spinning free flight (f = 0, no foundation)", (), ()),
}
BREAK_RE = re.compile(r"newton failed at step (\d+), t = ([-+0-9.eE]+)")


class Failure(Exception):
    pass


def run_one(out, case, model):
    scene, args, _, may_collapse, _ = CASES[case]
    run_dir = os.path.join(out, case, model)
    extra = list(MODEL_ARGS[model])
    if case == "spin" and model == "linear":
        extra = []                       # no foundation: no QP, -solver would only draw a warning
    cmd = [RUN, scene, run_dir, "-progress", "0", "-vtk", "0"] + extra + args
    t0 = time.perf_counter()
    p = jobs.run(cmd, env=dict(os.environ, FORCE="1"), cwd=ROOT)
    wall = time.perf_counter() - t0
    with open(os.path.join(out, case, f"{model}.log"), "w") as f:
        f.write("$ " + " ".join(cmd) + "\n" + p.stdout + p.stderr + f"exit status {p.returncode}\n")
    res = {"case": case, "model": model, "dir": run_dir, "wall": wall, "rc": p.returncode, "broke": None}
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


def snapshots(run_dir):
    files = glob.glob(os.path.join(run_dir, "snapshot_t*.csv"))
    return sorted((float(re.search(r"snapshot_t(.*)\.csv", p).group(1)), p) for p in files)


def save(fig, out, name):
    for ext in ("png", "pdf"):
        fig.savefig(os.path.join(out, f"{name}.{ext}"), dpi=150, bbox_inches="tight")
    plt.close(fig)


def mark_break(ax, res, h, col):
    """A cross at the last recorded value and a dotted line, in the legend, at the collapse time."""
    b = res["broke"]
    if b is None:
        return
    ax.axvline(b["t"], color=COLORS["svk"], ls=":", lw=1, label=f"SVK collapses: step {b['step']}, t = {b['t']:g}")
    ax.plot(h["t"][-1], h[col][-1], "x", color=COLORS["svk"], ms=9, mew=2)


def plot_pair(runs, case, cols, ylabels, out, name, what):
    title = CASES[case][2]
    fig, axes = plt.subplots(1, len(cols), figsize=(6 * len(cols), 4))
    for ax, col, yl in zip(axes, cols, ylabels):
        for model in MODELS:
            res, h = runs[(case, model)]
            ax.plot(h["t"], h[col], color=COLORS[model], lw=1, label=LABELS[model])
            if model == "svk":
                mark_break(ax, res, h, col)
        ax.set(xlabel="t", ylabel=yl, title=f"{title}: {what[col]}")
        ax.legend(fontsize=8)
    save(fig, out, name)


def plot_von_mises(runs, case, out, name):
    """Both models on the deformed body at the case's snapshot times (before any collapse)."""
    dirs = {m: runs[(case, m)][0]["dir"] for m in MODELS}
    files = {m: dict(snapshots(dirs[m])) for m in MODELS}
    times = [t for t in CASES[case][4] if all(t in files[m] for m in MODELS)]
    if not times:
        return None
    snap = {(m, t): read_csv(files[m][t]) for m in MODELS for t in times}
    vmax = max(s["vonmises"].max() for s in snap.values())
    fig, axes = plt.subplots(2, len(times), figsize=(3.6 * len(times), 7.4), squeeze=False)
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
    fig.colorbar(tp, ax=axes, shrink=0.6, label="von Mises stress (svk: of the Cauchy stress)")
    fig.suptitle(f"{CASES[case][2]}: von Mises stress on the deformed body")
    save(fig, out, name)
    return times


def plot_max_strain(runs, out, name):
    fig, axes = plt.subplots(1, len(CASES), figsize=(5 * len(CASES), 3.8))
    for ax, case in zip(axes, CASES):
        for model in MODELS:
            res, h = runs[(case, model)]
            ax.plot(h["t"], h["max_strain"], color=COLORS[model], lw=1, label=LABELS[model])
            if model == "svk":
                mark_break(ax, res, h, "max_strain")
        ax.set(xlabel="t", ylabel="largest principal Green-Lagrange strain", title=CASES[case][2])
        ax.title.set_fontsize(9)
        ax.legend(fontsize=8)
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
    """Why the soft body collapses: SVK's uniaxial-strain stress peaks in compression."""
    s = np.linspace(0.2, 1.3, 400)
    k = lam + 2 * mu
    fig, ax = plt.subplots(figsize=(6.5, 4))
    ax.plot(s, k * (s - 1), color=COLORS["linear"], label="linear: (lambda + 2 mu)(s - 1)")
    ax.plot(s, k * s * (s * s - 1) / 2, color=COLORS["svk"], label="SVK: (lambda + 2 mu) s (s^2 - 1) / 2")
    sc = 1 / np.sqrt(3)
    ax.plot(sc, -k / (3 * np.sqrt(3)), "ko")
    ax.annotate(f"peak |P| = (lambda + 2 mu) / (3 sqrt 3) = {k / (3 * np.sqrt(3)):.1f}\nat s = 1/sqrt 3",
                (sc, -k / (3 * np.sqrt(3))), xytext=(0.3, -45), fontsize=8, arrowprops=dict(arrowstyle="->"))
    ax.axhline(0, color="gray", lw=0.5)
    ax.set_ylim(-60, 30)
    ax.set(xlabel="stretch s (uniaxial strain)", ylabel="first Piola-Kirchhoff stress P",
           title=f"uniaxial strain, lambda = mu = {lam:g}")
    ax.legend(fontsize=8)
    save(fig, out, name)


def metrics(res, h):
    s = read_summary(res["dir"]) if os.path.exists(os.path.join(res["dir"], "summary.txt")) else {}
    n = h["newton_iterations"][1:]
    m = {"steps": len(h["t"]) - 1, "t_end": h["t"][-1], "max_strain": float(h["max_strain"].max()),
         "newton_mean": float(n.mean()) if len(n) else 0.0, "newton_max": int(n.max()) if len(n) else 0,
         "cpu": s.get("cpu_seconds"), "max_pen": float(h["max_penetration"].max())}
    if "u2_probe0" in h:
        comp = h["u2_low"] - h["u2_probe0"]          # shortening of the vertical diameter (40 at rest)
        k = int(np.argmax(comp))
        m["compression"], m["compression_t"] = float(comp[k]), float(h["t"][k])
    vm = [(read_csv(p)["vonmises"].max(), t) for t, p in snapshots(res["dir"])]
    m["vm"] = max(vm) if vm else None
    e, am = h["energy"], h["angular_momentum"]
    m["energy_drift"] = float(np.abs(e - e[0]).max() / abs(e[0]))
    m["am_drift"] = float(np.abs(am - am[0]).max() / abs(am[0])) if am[0] != 0 else None
    m["u2_min"] = float(h["u2_low"].min())
    return m


def status(res, m):
    if res["broke"]:
        return f"**collapsed** at step {res['broke']['step']}, t = {res['broke']['t']:g} (history to t = {m['t_end']:g})"
    return f"completed to T = {m['t_end']:g} ({m['steps']} steps)"


def write_summary(runs, out, vm_times, wall, jobs):
    L = ["# make svk: St Venant-Kirchhoff next to the linear body", "",
         f"Written by postprocess/svk_compare.py ({len(runs)} runs, {wall:.0f} s wall, {jobs} at a time). "
         "Compression = the largest shortening of the vertical diameter, u2(0, 0) - u2(0, 40), and the time it "
         "is reached. Max strain = the largest principal Green-Lagrange strain over the body and the run. "
         "Max von Mises = over the snapshots of the run (svk: of the Cauchy stress). Newton = iterations per step "
         "(mean, max); the linear body is solved by the exact active-set solver. Wall s = the run's wall time, " + f"{jobs} runs at a time.", ""]
    for case in CASES:
        L += [f"## {case}: {CASES[case][2]}", ""]
        if case == "spin":
            L += ["| model | status | max strain | energy drift max abs(E - E0)/E0 | angular momentum drift "
                  "max abs(L - L0)/abs(L0) | Newton it./step (mean, max) | wall s |",
                  "| --- | --- | ---: | ---: | ---: | ---: | ---: |"]
        else:
            L += ["| model | status | max compression (at t) | max strain | max von Mises (at t) | "
                  "Newton it./step (mean, max) | max penetration | wall s |",
                  "| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: |"]
        for model in MODELS:
            res, h = runs[(case, model)]
            m = metrics(res, h)
            newton = f"{m['newton_mean']:.2f}, {m['newton_max']}" if model == "svk" else "-"
            cpu = f"{res['wall']:.1f}"
            if case == "spin":
                L.append(f"| {model} | {status(res, m)} | {m['max_strain']:.4g} | {m['energy_drift']:.1e} | "
                         f"{m['am_drift']:.1e} | {newton} | {cpu} |")
            else:
                vm = f"{m['vm'][0]:.1f} ({m['vm'][1]:g})" if m["vm"] else "-"
                L.append(f"| {model} | {status(res, m)} | {m['compression']:.3f} ({m['compression_t']:g}) | "
                         f"{m['max_strain']:.4g} | {vm} | {newton} | {m['max_pen']:.1e} | {cpu} |")
        for model in MODELS:
            res, _ = runs[(case, model)]
            if res["broke"]:
                L += ["", f"{model}: `{res['broke']['message']}`"]
        if case in vm_times and vm_times[case]:
            L += ["", f"Von Mises figure: t = {', '.join(f'{t:g}' for t in vm_times[case])}."]
        L.append("")
    k = (30 + 2 * 30) / (3 * np.sqrt(3))
    L += [f"SVK under uniaxial strain with lambda = mu = 30: |P| peaks at (lambda + 2 mu)/(3 sqrt 3) = {k:.2f} "
          "(stretch 1/sqrt 3); beyond it the stored energy is not convex (svk_uniaxial.png).", ""]
    with open(os.path.join(out, "summary.md"), "w") as f:
        f.write("\n".join(L))
    return "\n".join(L)


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--out", default=os.path.join(ROOT, "results", "svk"))
    p.add_argument("--jobs", type=int, default=2)
    a = p.parse_args()
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
    except Failure as e:
        print(f"error: make svk: {e}", file=sys.stderr)
        sys.exit(1)
    wall = time.perf_counter() - t0
    runs = {k: (r, read_run(r["dir"])) for k, r in results.items()}
    what = {"u2_low": "u2 at the lowest point", "contact_pressure_low": "contact stress at the lowest point",
            "energy": "energy", "modified_energy": "modified energy"}
    vm_times = {}
    for case in ("test1", "test2", "stiff"):
        plot_pair(runs, case, ["u2_low", "contact_pressure_low"], ["u2 at (0, 0)", "contact stress alpha at (0, 0)"],
                  out, f"svk_{case}_low_point", what)
        plot_pair(runs, case, ["energy", "modified_energy"], ["energy", "modified energy"], out,
                  f"svk_{case}_energy", what)
        vm_times[case] = plot_von_mises(runs, case, out, f"svk_{case}_von_mises")
    plot_max_strain(runs, out, "svk_max_strain")
    plot_spin(runs, out, "svk_spin")
    plot_uniaxial(out, "svk_uniaxial")
    print(write_summary(runs, out, vm_times, wall, a.jobs))
    print(f"figures and summary.md written to {out}/")


if __name__ == "__main__":
    main()
