"""`make bench`: cost measured side by side in one run (no timed tests anywhere).

For each case: wall seconds, CPU seconds of the FreeFEM process, peak memory
(max RSS), steps, steps that needed a QP, and milliseconds per step. Then the
ratios asked for:
  - Test 1 with -skip_free 1 (default) against -skip_free 0: same answer, how much faster;
  - -solver activeset against ipopt on Test 1 and Test 2;
  - -factorization cholesky (default) against lu for the free predictor;
  - the cost per step on three meshes of the same disk, for both solvers;
  - the St Venant-Kirchhoff body (-material svk, semi-smooth Newton + GMRES)
    beside the linear body's activeset and ipopt runs: Test 1 with the paper's
    lambda = mu = 30 to T = 16 (SVK collapses at t = 16.8), and the stiff
    Test 1 (lambda = mu = 300, to --T); Newton iterations per step and GMRES
    iterations per Newton iteration from the runs' summary.txt, and the aim
    "SVK Test 1 at most 20x the linear active-set wall time";
  - the Neo-Hookean body (-material neohookean) beside SVK on the same cases (Test 1
    to T = 16, the stiff Test 1, P2 to T = 16), and on the paper's Test 1 to --T; the
    aim "a Neo-Hookean step at most 1.5x an SVK step on Test 1" (--nh-only: these
    material rows alone, SVK and Neo-Hookean alternated run by run);
  - every method of make methods (penalty, Nitsche, singular and lumped mass,
    Newmark, explicit Verlet) on Test 1: ms per step and wall time against
    the paper's method;
  - the 3D ball (docs/3d.md) on three meshes (ball.msh, ball_medium.msh, ball_refine4.msh):
    vertices, dofs, set-up, ms per step and peak memory of the active set, of the same run with no
    foundation, of IPOPT (on a ball that starts in contact), and of an independent scipy implementation
    of the same scheme (tests/reference/scipy_midpoint.py, SuperLU and cached Schur columns), with the
    aims "the active-set ball within 1.5x the no-foundation run at the largest size" and "a step at
    least 3x faster than scipy's", and how the cost grows with the vertices (--ball-only: these rows
    alone, into bench_ball.md and .csv);
  - a step against its floor: edp/limit.edp's one solve with the factor of A and one product with K on the three
    balls and the refine-8 disk, beside Test 1 to T = 20 with the active set and without foundation, the aims
    "no foundation within 1.2x the limit" and "the active set within 1.5x (the disk: 1.35x) the run without
    foundation", and CHOLMOD's orderings, kinds and OpenBLAS threads on the largest meshes (--step-cost-only:
    these rows alone, into bench_step_cost.md and .csv);
  - -np N (docs/parallel.md): the ball starting in contact on four meshes (up to ball_refine6.msh,
    87,684 vertices) on 1, 2 and 4 processes (4 oversubscribe the 2 cores) beside the serial direct solver:
    set-up, ms per step, solves and Krylov iterations per step, peak memory per process, the difference from
    the serial history, and parallel.png (--parallel-only: these rows alone, into bench_parallel.md and .csv).
Cases run one at a time, so they do not compete for the 2 cores. A case that
takes less than 10 s is run --repeat times and its median kept (the spread is
reported), so the ratios of short runs are not one noisy sample. Writes
results/bench/bench.md and bench.csv (--nh-only: bench_neohookean.md and .csv;
--ball-only: bench_ball.md and .csv; --parallel-only: bench_parallel.md and .csv).
"""
import argparse
import json
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import jobs  # noqa: E402
from driver import ROOT, case_row, freefem_env, timed_process  # noqa: E402
from history import read_run, read_summary  # noqa: E402
from methods import RUNNING_METHODS as METHODS  # noqa: E402 (the classical Newmark stops: not timed)


def case_table(rows):
    """The table of every case: wall time (and the range of its runs), CPU, peak memory, steps, ms per step."""
    lines = ["| case | wall s | runs (wall range) | CPU s | peak MiB | steps | QP steps | ms/step |",
             "| --- | ---: | --- | ---: | ---: | ---: | ---: | ---: |"]
    for r in rows:
        spread = f"{r['runs']} ({r['wall_min']:.2f}-{r['wall_max']:.2f})" if r["runs"] > 1 else "1"
        lines.append(f"| {r['case']} | {r['wall_s']:.2f} | {spread} | {r['cpu_s']:.2f} | {r['peak_MiB']:.0f} | {r['steps']} | "
                     f"{r['qp_steps']} | {r['ms_per_step']:.2f} |")
    return lines


def ms_after_first_step(run, one):
    """The cost of a step in the time loop: the run's wall time less its one-step run's (set-up and the first step),
    in ms per further step."""
    return 1000 * (run["wall_s"] - one["wall_s"]) / (run["steps"] - 1)


def timed_case(out_base, name, scene, args, repeat, allow_stop=False):
    """case_row, repeated when short: the median wall and CPU time, and their spread."""
    runs = [case_row(out_base, name, scene, args, allow_stop)]
    while runs[0]["wall_s"] < 10 and len(runs) < repeat:
        runs.append(case_row(out_base, name, scene, args, allow_stop))
    return median_row(runs)


def timed_group(out_base, group, repeat):
    """Each case (name, scene, args) of the group run `repeat` times, whatever its length, the cases
    alternated (a, b, c, a, b, c, ...) so that a slower spell of a shared machine falls on all of
    them; one median_row per case, with case = name."""
    runs = {name: [] for name, _, _ in group}
    for _ in range(repeat):
        for name, scene, args in group:
            print(f"bench: {name} ...", flush=True)
            runs[name].append(case_row(out_base, name.replace(" ", "_").replace("=", ""), scene, args))
    return [dict(median_row(r), case=name) for name, r in runs.items()]


def median_row(runs):
    """The last run's row with the median wall and CPU time of the runs, their spread and the peak memory."""
    walls = sorted(r["wall_s"] for r in runs)
    row = dict(runs[-1])
    row.update(wall_s=float(np.median(walls)), cpu_s=float(np.median([r["cpu_s"] for r in runs])),
               peak_MiB=max(r["peak_MiB"] for r in runs), runs=len(runs), wall_min=walls[0], wall_max=walls[-1])
    row["ms_per_step"] = 1000 * row["wall_s"] / row["steps"]
    return row


def main():
    p = argparse.ArgumentParser(description=__doc__)
    p.add_argument("--out", default=os.path.join(ROOT, "results", "bench"))
    p.add_argument("--T", default="120", help="horizon of the Test 1 / Test 2 cases")
    p.add_argument("--repeat", type=int, default=3, help="runs of a case shorter than 10 s (median kept)")
    p.add_argument("--ball-only", action="store_true",
                   help="only the 3D ball's cases, into bench_ball.md and .csv (bench.md is left as it is)")
    p.add_argument("--parallel-only", action="store_true",
                   help="only the -np N cases, into bench_parallel.md and .csv and parallel.png")
    p.add_argument("--meshes", help="with --parallel-only: only these of its meshes (comma-separated names, e.g. "
                   "ball,ball_medium)")
    p.add_argument("--step-cost-only", action="store_true",
                   help="only the cost of a step against its floor (the limit probe, the active set, no foundation), "
                        "into bench_step_cost.md and .csv")
    p.add_argument("--friction-only", action="store_true",
                   help="only friction's cost against the frictionless run (issue 35), into bench_friction.md and .csv")
    p.add_argument("--gap-only", action="store_true",
                   help="only the exact gap's cost against the linearised one (issue 36), into bench_gap.md and .csv")
    p.add_argument("--nh-only", action="store_true",
                   help="only the SVK and Neo-Hookean cases (with the linear active-set ones), each run --repeat times, "
                        "alternated; into bench_neohookean.md and .csv (bench.md is left as it is)")
    a = p.parse_args()
    os.makedirs(a.out, exist_ok=True)
    stem = ("bench_neohookean" if a.nh_only else "bench_ball" if a.ball_only else "bench_parallel" if a.parallel_only else
            "bench_step_cost" if a.step_cost_only else "bench_friction" if a.friction_only else "bench_gap" if a.gap_only
            else "bench")
    jobs.stop_on_interrupt("make bench", a.out, [f"{stem}.md", f"{stem}.csv"])
    if a.ball_only or a.parallel_only or a.step_cost_only or a.friction_only or a.gap_only:
        rows, text = (ball_section(a.out, a.repeat) if a.ball_only else step_cost_section(a.out, a.repeat) if a.step_cost_only
                      else friction_section(a.out, a.repeat) if a.friction_only else gap_section(a.out, a.repeat) if a.gap_only
                      else parallel_section(a.out, a.repeat, a.meshes.split(",") if a.meshes else None))
        print(text)
        write_tables(a.out, stem, rows, text)
        return
    cases = [
        ("test1 ipopt", "test1", ["-T", a.T]),
        ("test1 ipopt skip_free=0", "test1", ["-T", a.T, "-skip_free", "0"]),
        ("test1 activeset", "test1", ["-T", a.T, "-solver", "activeset"]),
        ("test1 activeset lu", "test1", ["-T", a.T, "-solver", "activeset", "-factorization", "lu"]),
        ("test2 ipopt", "test2", ["-T", a.T, "-t1", "18"]),
        ("test2 activeset", "test2", ["-T", a.T, "-t1", "18", "-solver", "activeset"]),
    ]
    # SVK beside the linear body, in the same run: Test 1 with the paper's lambda = mu = 30 up to
    # T = 16 (SVK inverts an element at t = 16.8), and the stiff body to T = --T
    stiff = ["-lambda", "300", "-mu", "300", "-T", a.T, "-dt", "0.05"]
    svk_pairs = [("test1 T=16", "Test 1 (lambda = mu = 30), T = 16", ["-T", "16"]),
                 ("test1 stiff", f"stiff Test 1 (lambda = mu = 300), T = {a.T}", stiff)]
    for key, _, args in svk_pairs:
        cases += [(f"{key} ipopt", "test1", args),
                  (f"{key} activeset", "test1", args + ["-solver", "activeset"]),
                  (f"{key} svk", "test1", args + ["-material", "svk"]),
                  (f"{key} neohookean", "test1", args + ["-material", "neohookean"])]
    # the Neo-Hookean body on P2 beside SVK's P2 row, and on the paper's whole Test 1 (SVK cannot run it)
    nh_cases = [("test1 T=16 neohookean P2", "test1", ["-T", "16", "-material", "neohookean", "-order", "2"]),
                ("test1 neohookean", "test1", ["-T", a.T, "-material", "neohookean"])]
    if a.nh_only:      # the material rows alone, SVK and Neo-Hookean alternated run by run
        groups = [[c for c in cases if c[0].startswith(key) and not c[0].endswith("ipopt")] for key, _, _ in svk_pairs]
        groups += [[("test1 T=16 svk P2", "test1", ["-T", "16", "-material", "svk", "-order", "2"]), nh_cases[0]],
                   [("test1 activeset", "test1", ["-T", a.T, "-solver", "activeset"]), nh_cases[1]]]
        rows = [r for g in groups for r in timed_group(a.out, g, a.repeat)]
        text = "\n".join(nh_lines({r["case"]: r for r in rows}, svk_pairs, a.T, full=False))
        print(text)
        write_tables(a.out, "bench_neohookean", rows, text)
        return
    meshes = [("coarse", "meshes/disk_coarse.msh"), ("paper", "meshes/disk.msh"), ("fine", "meshes/disk_fine.msh")]
    for solver in ("ipopt", "activeset"):
        for mesh, path in meshes:
            cases.append((f"test1 {solver} {mesh} mesh T=40", "test1", ["-T", "40", "-mesh", path, "-solver", solver]))
    # P2 (-order 2) on the paper's mesh beside P1; the new bodies; CSM3
    cases += [("test1 activeset P2", "test1", ["-T", a.T, "-solver", "activeset", "-order", "2"]),
              ("test1 T=16 svk P2", "test1", ["-T", "16", "-material", "svk", "-order", "2"]), nh_cases[0],
              ("cantilever activeset", "cantilever", ["-solver", "activeset"]),
              ("cantilever svk", "cantilever", ["-material", "svk"]),
              ("csm3", "csm3", []),
              ("csm3 newton_precond initial", "csm3", ["-newton_precond", "initial"]), nh_cases[1]]
    # the methods of make methods (docs/methods.md) on Test 1, the paper's mesh, to --T
    cases += [(f"methods {m}", "test1", ["-T", a.T] + args, True) for m, (_, args) in METHODS.items()]
    # set-up against the cost per step: one step, and T = 20, on meshes up to refine 8 (about 57,000 vertices)
    big = [("paper", "meshes/disk.msh"), ("refine4", "meshes/disk_refine4.msh"), ("refine8", "meshes/disk_refine8.msh")]
    for mesh, path in big:
        for horizon in ("0.05", "20"):
            cases.append((f"test1 activeset {mesh} T={horizon}", "test1", ["-T", horizon, "-mesh", path, "-solver", "activeset"]))
    rows = []
    for name, scene, args, *stop in cases:     # (the methods' cases: a run the energy guard stops is timed to its stop)
        print(f"bench: {name} ...", flush=True)
        rows.append(timed_case(a.out, name.replace(" ", "_").replace("=", ""), scene, args, a.repeat, bool(stop)))
        rows[-1]["case"] = name
    by = {r["case"]: r for r in rows}
    lines = case_table(rows)

    def u2_gap(x, y):
        return np.abs(by[x]["history"]["u2_low"] - by[y]["history"]["u2_low"]).max()

    def ratio(slow, fast):
        return by[slow]["wall_s"] / by[fast]["wall_s"]

    lines += ["",
              f"- skip_free: -skip_free 1 is {ratio('test1 ipopt skip_free=0', 'test1 ipopt'):.2f}x faster than "
              f"-skip_free 0 on Test 1 (T = {a.T}); max |u2_low difference| {u2_gap('test1 ipopt', 'test1 ipopt skip_free=0'):.2g}",
              f"- activeset against ipopt, Test 1 (T = {a.T}): {ratio('test1 ipopt', 'test1 activeset'):.1f}x less wall time; "
              f"max |u2_low difference| {u2_gap('test1 ipopt', 'test1 activeset'):.2g} (IPOPT's own error at tol 1e-8)",
              f"- activeset against ipopt, Test 2 t1 = 18 (T = {a.T}): {ratio('test2 ipopt', 'test2 activeset'):.1f}x less wall time; "
              f"max |u2_low difference| {u2_gap('test2 ipopt', 'test2 activeset'):.2g}",
              f"- aim of at least 20x less wall time than IPOPT on Test 1 (T = {a.T}): "
              f"{'met' if ratio('test1 ipopt', 'test1 activeset') >= 20 else 'NOT met'} "
              f"({ratio('test1 ipopt', 'test1 activeset'):.1f}x; slowest activeset run "
              f"{by['test1 ipopt']['wall_s'] / by['test1 activeset']['wall_max']:.1f}x)",
              f"- factorisation of A, Test 1 activeset: -factorization cholesky is "
              f"{ratio('test1 activeset lu', 'test1 activeset'):.2f}x faster than lu; "
              f"max |u2_low difference| {u2_gap('test1 activeset', 'test1 activeset lu'):.2g}"]
    for solver in ("ipopt", "activeset"):
        c, m, f = (by[f"test1 {solver} {mesh} mesh T=40"] for mesh, _ in meshes)
        lines.append(f"- mesh scaling, {solver} (ms per step, T = 40): coarse (277) {c['ms_per_step']:.2f}, "
                     f"paper (989) {m['ms_per_step']:.2f} ({m['ms_per_step'] / c['ms_per_step']:.1f}x), "
                     f"fine (3750) {f['ms_per_step']:.2f} ({f['ms_per_step'] / m['ms_per_step']:.1f}x)")
    lines += ["", "St Venant-Kirchhoff (-material svk, -solver newton) beside the linear body:", "",
              "| case | Newton it/step | GMRES it/Newton it | Newton retries | ms/Newton it | "
              "SVK wall / activeset wall | SVK wall / ipopt wall |",
              "| --- | ---: | ---: | ---: | ---: | ---: | ---: |"]
    for key, _, _ in svk_pairs:
        s = by[f"{key} svk"]
        lines.append(f"| {key} svk | {s['newton_iterations'] / s['steps']:.2f} | "
                     f"{s['gmres_iterations'] / s['newton_iterations']:.2f} | {s['newton_retries']} | "
                     f"{s['wall_s'] * 1000 / s['newton_iterations']:.2f} | {ratio(f'{key} svk', f'{key} activeset'):.1f} | "
                     f"{ratio(f'{key} svk', f'{key} ipopt'):.2f} |")
    lines.append("")
    aim_met = True
    for key, title, _ in svk_pairs:
        s, lin, ip = by[f"{key} svk"], by[f"{key} activeset"], by[f"{key} ipopt"]
        r, worst = ratio(f"{key} svk", f"{key} activeset"), s["wall_max"] / lin["wall_s"]
        aim_met &= worst <= 20
        lines.append(f"- SVK, {title}: {s['wall_s']:.2f} s, {r:.1f}x the linear activeset wall time "
                     f"({lin['wall_s']:.2f} s; slowest SVK run {worst:.1f}x) and "
                     f"{ratio(f'{key} svk', f'{key} ipopt'):.2f}x ipopt's ({ip['wall_s']:.2f} s); "
                     f"{s['newton_iterations'] / s['steps']:.2f} Newton iterations per step, "
                     f"{s['gmres_iterations'] / s['newton_iterations']:.2f} GMRES iterations per Newton iteration; "
                     f"linear activeset against ipopt: max |u2_low difference| {u2_gap(f'{key} ipopt', f'{key} activeset'):.2g}")
    worst_all = max(by[f"{k} svk"]["wall_max"] / by[f"{k} activeset"]["wall_s"] for k, _, _ in svk_pairs)
    lines.append(f"- aim of SVK Test 1 at most 20x the linear active-set wall time: {'met' if aim_met else 'NOT met'} "
                 f"(" + "; ".join(f"{k} {ratio(f'{k} svk', f'{k} activeset'):.1f}x" for k, _, _ in svk_pairs)
                 + f"; slowest SVK run {worst_all:.1f}x)")
    p1, p2 = by["test1 activeset"], by["test1 activeset P2"]
    s1, s2 = by["test1 T=16 svk"], by["test1 T=16 svk P2"]
    ca, cs, c3, c3a = by["cantilever activeset"], by["cantilever svk"], by["csm3"], by["csm3 newton_precond initial"]
    lines += ["", "Beyond the disk and P1:", "",
              f"- P2 on the paper's mesh, Test 1 activeset (T = {a.T}): {p2['wall_s']:.2f} s, {p2['ms_per_step']:.2f} ms/step, "
              f"{ratio('test1 activeset P2', 'test1 activeset'):.1f}x P1's ({p1['wall_s']:.2f} s); SVK Test 1 (T = 16): "
              f"{s2['wall_s']:.2f} s, {ratio('test1 T=16 svk P2', 'test1 T=16 svk'):.1f}x P1's ({s1['wall_s']:.2f} s), "
              f"{s2['newton_iterations'] / s2['steps']:.2f} Newton it/step, {s2['gmres_iterations'] / s2['newton_iterations']:.1f} GMRES it/Newton it",
              f"- cantilever (T = 30): activeset {ca['wall_s']:.2f} s ({ca['ms_per_step']:.2f} ms/step), svk {cs['wall_s']:.2f} s "
              f"({cs['ms_per_step']:.2f} ms/step, {ratio('cantilever svk', 'cantilever activeset'):.1f}x), "
              f"{cs['newton_iterations'] / cs['steps']:.2f} Newton it/step",
              f"- csm3 (T = 5, P2, SVK): {c3['wall_s']:.1f} s wall, {c3['cpu_s']:.1f} s CPU, {c3['ms_per_step']:.1f} ms/step, "
              f"{c3['newton_iterations'] / c3['steps']:.2f} Newton it/step, {c3['gmres_iterations'] / c3['newton_iterations']:.1f} GMRES it/Newton it "
              f"(-newton_precond step, the scene's); with -newton_precond initial {c3a['wall_s']:.1f} s wall "
              f"({ratio('csm3 newton_precond initial', 'csm3'):.2f}x), {c3a['gmres_iterations'] / c3a['newton_iterations']:.1f} GMRES it/Newton it; "
              f"max |u2_probe0 difference| {np.abs(c3['history']['u2_probe0'] - c3a['history']['u2_probe0']).max():.2g}",
              "", "| mesh (Test 1 activeset) | vertices | one step: wall s (set-up) | T = 20: wall s | ms per step after the first |",
              "| --- | ---: | ---: | ---: | ---: |"]
    for mesh, _ in big:
        one, run = by[f"test1 activeset {mesh} T=0.05"], by[f"test1 activeset {mesh} T=20"]
        per_step = ms_after_first_step(run, one)
        lines.append(f"| {mesh} | {read_summary(os.path.join(a.out, f'test1_activeset_{mesh}_T20'))['vertices']} | "
                     f"{one['wall_s']:.2f} | {run['wall_s']:.2f} | {per_step:.2f} |")
    paper = by["methods paper"]
    lines += ["", f"The methods of docs/methods.md, Test 1 on the paper's mesh to T = {a.T} (wall time against the "
              "paper's method, mid-point + constraint by the active-set solver, in the same run):", "",
              "| method | wall s | steps | ms/step | wall / the paper's |", "| --- | ---: | ---: | ---: | ---: |"]
    for m, (label, _) in METHODS.items():
        r = by[f"methods {m}"]
        if r["stopped"]:           # stopped by the energy guard: its cost per step, to where it stopped
            lines.append(f"| {label} (**stopped by the energy guard at t = {r['history']['t'][-1]:g}**) | {r['wall_s']:.2f} | "
                         f"{r['steps']} | {r['ms_per_step']:.2f} | - |")
        else:
            lines.append(f"| {label} | {r['wall_s']:.2f} | {r['steps']} | {r['ms_per_step']:.2f} | "
                         f"{r['wall_s'] / paper['wall_s']:.1f} |")
    lines += [f"\n{METHODS[m][0]}: `{by[f'methods {m}']['stopped']}`" for m in METHODS if by[f"methods {m}"]["stopped"]]
    lines += [""] + nh_lines(by, svk_pairs, a.T, full=True)
    ball_rows, ball_text = ball_section(a.out, a.repeat)
    rows += ball_rows
    lines += ["", "The 3D ball (docs/3d.md):", "", ball_text]
    step_rows, step_text = step_cost_section(a.out, a.repeat)
    rows += step_rows
    lines += ["", "A step against its floor (docs/bench.md):", "", step_text]
    parallel_rows, parallel_text = parallel_section(a.out, a.repeat)
    rows += parallel_rows
    lines += ["", "-np N (docs/parallel.md):", "", parallel_text]
    for title, section in (("Friction (docs/friction.md):", friction_section), ("The exact gap (docs/sliding.md):", gap_section)):
        part_rows, part_text = section(a.out, a.repeat)
        rows += part_rows
        lines += ["", title, "", part_text]
    text = "\n".join(lines)
    print(text)
    write_tables(a.out, "bench", rows, text)


# ---- the 3D ball: three meshes of the scene `ball` (Test 1 in 3D), T = BALL_T
BALL_MESHES = [("ball", "meshes/ball.msh"), ("ball_medium", "meshes/ball_medium.msh"), ("ball_refine4", "meshes/ball_refine4.msh")]
BALL_T = "20"      # the fall (first contact at t = 8.95), the impact and most of the rebound: 400 steps
# IPOPT against the active set on the ball starting in contact at Test 1's impact speed sqrt(2 g 4) = 0.894,
# so that every step is a QP: 20 steps, 5 on the middle mesh and 1 on the largest (IPOPT takes minutes per step there)
IMPACT = ["-u0z", "0", "-v0z", "-0.894"]
IMPACT_T = {"ball": "1", "ball_medium": "0.25", "ball_refine4": "0.05"}
# the active set on the same impact to 50, 50 and 10 steps: its cost per step is the difference of two runs, which
# one or five steps lose in the start-up's noise (-solver activeset takes 2 to 1000 ms a step there)
IMPACT_ACTIVE_T = {"ball": "2.5", "ball_medium": "2.5", "ball_refine4": "0.5"}
BALL_AIM_FOUNDATION = 1.5    # the active-set ball within 1.5x the no-foundation run at the largest size
BALL_AIM_SCIPY = 3           # a step at least 3x faster than the scipy implementation of the same scheme
SCIPY = os.path.join(ROOT, "tests", "reference", "scipy_midpoint.py")
# the scipy run's horizon: BALL_T, but T = 10 (the fall and the impact's first 22 steps) on the largest mesh, where
# SuperLU's factorisation and steps are the slowest; the active set then also runs to that T beside it
SCIPY_T = {"ball": BALL_T, "ball_medium": BALL_T, "ball_refine4": "10"}


def scipy_case(out_base, name, mesh, horizon):
    """The scipy implementation (scipy_midpoint.py) of the same run (ball, -solver activeset) to T = horizon,
    in its own process: its set-up and ms per step as it times them, its wall time and peak memory."""
    out = os.path.join(out_base, name)
    os.makedirs(out, exist_ok=True)
    r = timed_process([sys.executable, SCIPY, "--mesh", os.path.join(ROOT, mesh), "--T", horizon,
                       "--out", os.path.join(out, "history.csv"), "--json", os.path.join(out, "summary.json")], merge=True)
    if r.returncode != 0:
        sys.exit(f"bench case {name} failed:\n{r.stdout}")
    with open(os.path.join(out, "summary.json")) as fh:
        res = json.load(fh)
    return dict(res, case=name, wall_s=r.wall, cpu_s=r.cpu_s, peak_MiB=r.peak_MiB, history=read_run(out))


def ball_section(out_base, repeat):
    """The 3D rows: for each mesh of BALL_MESHES, one step (the set-up), the active set and the same run with
    no foundation to BALL_T, IPOPT and the active set on the impact, and the scipy implementation. Returns
    (rows for bench.csv, the text of the tables and aims)."""
    rows, by, scipy = [], {}, {}
    for mesh, path in BALL_MESHES:
        cases = [(f"ball {mesh} set-up", ["-T", "0.05", "-solver", "activeset"]),
                 (f"ball {mesh} activeset", ["-T", BALL_T, "-solver", "activeset"]),
                 (f"ball {mesh} no foundation", ["-T", BALL_T, "-foundation", "none"]),
                 (f"ball {mesh} impact activeset", IMPACT + ["-T", IMPACT_ACTIVE_T[mesh], "-solver", "activeset"]),
                 (f"ball {mesh} impact ipopt", IMPACT + ["-T", IMPACT_T[mesh], "-solver", "ipopt"])]
        if SCIPY_T[mesh] != BALL_T:
            cases.append((f"ball {mesh} activeset T={SCIPY_T[mesh]}", ["-T", SCIPY_T[mesh], "-solver", "activeset"]))
        for name, args in cases:
            print(f"bench: {name} ...", flush=True)
            r = timed_case(out_base, name.replace(" ", "_").replace("-", "_").replace("=", ""), "ball", ["-mesh", path] + args,
                           repeat)
            r["case"] = name
            rows.append(r)
            by[name] = r
        print(f"bench: ball {mesh} scipy ...", flush=True)
        scipy[mesh] = scipy_case(out_base, f"ball_{mesh}_scipy", path, SCIPY_T[mesh])
    lines = case_table(rows + [dict(q, case=f"ball {mesh} scipy", runs=1, ms_per_step=1000 * q["wall_s"] / q["steps"])
                               for mesh, q in scipy.items()])
    # the time loop's cost per step: the run to BALL_T less the one-step run (set-up and the first step)
    def loop_ms(name, mesh):
        return ms_after_first_step(by[name], by[f"ball {mesh} set-up"])
    lines += ["", f"Test 1 in 3D (scene ball) to T = {BALL_T} ({by['ball ball activeset']['steps']} "
              "steps): set-up is the wall time of a one-step run, ms/step the rest of the run's wall time per further step.", "",
              "| mesh | vertices | dofs | Gamma_C nodes | set-up s | peak MiB | active set: ms/step | QP steps | Schur solves | "
              "no foundation: ms/step | active set / no foundation: run (per step) |",
              "| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |"]
    summary = {}
    for mesh, _ in BALL_MESHES:
        s = summary[mesh] = read_summary(os.path.join(out_base, f"ball_{mesh}_activeset"))
        act, none = by[f"ball {mesh} activeset"], by[f"ball {mesh} no foundation"]
        q = scipy[mesh]
        lines.append(f"| {mesh} | {s['vertices']} | {3 * int(s['vertices'])} | {q['contact_nodes']} | "
                     f"{by[f'ball {mesh} set-up']['wall_s']:.2f} | {act['peak_MiB']:.0f} | {loop_ms(f'ball {mesh} activeset', mesh):.2f} | "
                     f"{act['qp_steps']} | {s['schur_solves']} | {loop_ms(f'ball {mesh} no foundation', mesh):.2f} | "
                     f"{act['wall_s'] / none['wall_s']:.2f} ({loop_ms(f'ball {mesh} activeset', mesh) / loop_ms(f'ball {mesh} no foundation', mesh):.2f}) |")
    lines += ["", "IPOPT against the active set, the ball starting in contact at Test 1's impact speed (every step a QP): "
              "IPOPT's ms per step after the active-set one-step run's set-up, the active set's from its run to T = "
              + ", ".join(f"{IMPACT_ACTIVE_T[m]} on {m}" for m, _ in BALL_MESHES) + " less that one-step run; the "
              "difference over IPOPT's steps:", "",
              "| mesh | IPOPT: steps | IPOPT: wall s | IPOPT: ms/step | active set: steps | active set: wall s | "
              "active set: ms/step | IPOPT / active set per step | max abs u3_low difference |",
              "| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |"]
    for mesh, _ in BALL_MESHES:
        ip, act = by[f"ball {mesh} impact ipopt"], by[f"ball {mesh} impact activeset"]
        setup = by[f"ball {mesh} set-up"]["wall_s"]
        ip_ms = 1000 * max(ip["wall_s"] - setup, 0) / ip["steps"]
        act_ms = loop_ms(f"ball {mesh} impact activeset", mesh)
        common = len(ip["history"]["u3_low"])
        gap = np.abs(ip["history"]["u3_low"] - act["history"]["u3_low"][:common]).max()
        lines.append(f"| {mesh} | {ip['steps']} | {ip['wall_s']:.2f} | {ip_ms:.1f} | {act['steps']} | {act['wall_s']:.2f} | "
                     f"{act_ms:.2f} | {(f'{ip_ms / act_ms:.0f}' if act_ms > 0 else '-')} | {gap:.2g} |")
    def beside_scipy(mesh):      # the active-set run to the scipy run's horizon
        return f"ball {mesh} activeset" + ("" if SCIPY_T[mesh] == BALL_T else f" T={SCIPY_T[mesh]}")
    lines += ["", "The same scheme in scipy (tests/reference/scipy_midpoint.py: SuperLU, Schur columns cached; set-up and "
              "ms/step by its own timers, after reading the mesh), beside the active-set run to the same T:", "",
              "| mesh | T | scipy set-up s | scipy ms/step | scipy peak MiB | FreeFEM set-up s | FreeFEM ms/step | "
              "scipy / FreeFEM per step | max abs u3_low difference |", "| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |"]
    for mesh, _ in BALL_MESHES:
        q, act = scipy[mesh], by[beside_scipy(mesh)]
        gap = np.abs(q["history"]["u3_low"] - act["history"]["u3_low"]).max()
        ff_ms = loop_ms(beside_scipy(mesh), mesh)
        lines.append(f"| {mesh} | {SCIPY_T[mesh]} | {q['setup_seconds']:.2f} | {q['ms_per_step']:.2f} | {q['peak_MiB']:.0f} | "
                     f"{by[f'ball {mesh} set-up']['wall_s']:.2f} | {ff_ms:.2f} | {q['ms_per_step'] / ff_ms:.1f} | {gap:.2g} |")
    big = BALL_MESHES[-1][0]
    r_run = by[f"ball {big} activeset"]["wall_s"] / by[f"ball {big} no foundation"]["wall_s"]
    r_loop = loop_ms(f"ball {big} activeset", big) / loop_ms(f"ball {big} no foundation", big)
    r_scipy = {mesh: scipy[mesh]["ms_per_step"] / loop_ms(beside_scipy(mesh), mesh) for mesh, _ in BALL_MESHES}
    lines += ["", f"- aim of the active-set ball within {BALL_AIM_FOUNDATION:g}x the no-foundation run at the largest size ({big}): "
              f"{'met' if r_run <= BALL_AIM_FOUNDATION else 'NOT met'} on the whole run ({r_run:.2f}x); the time loop alone "
              f"{r_loop:.2f}x ({'within' if r_loop <= BALL_AIM_FOUNDATION else 'beyond'} the aim)",
              f"- aim of a step at least {BALL_AIM_SCIPY:g}x faster than the scipy implementation: "
              + "; ".join(f"{mesh} {r:.1f}x ({'met' if r >= BALL_AIM_SCIPY else 'NOT met'})" for mesh, r in r_scipy.items())]
    # growth: the exponent p of cost ~ vertices^p between consecutive meshes
    nv = {mesh: int(summary[mesh]["vertices"]) for mesh, _ in BALL_MESHES}
    for label, cost in (("set-up", lambda m: by[f"ball {m} set-up"]["wall_s"]),
                        ("active set ms/step", lambda m: loop_ms(f"ball {m} activeset", m)),
                        ("no foundation ms/step", lambda m: loop_ms(f"ball {m} no foundation", m)),
                        ("peak memory", lambda m: by[f"ball {m} activeset"]["peak_MiB"]),
                        ("scipy ms/step" + "".join(f" (T = {t} on {m})" for m, t in SCIPY_T.items() if t != BALL_T),
                         lambda m: scipy[m]["ms_per_step"])):
        pairs = list(zip(BALL_MESHES, BALL_MESHES[1:]))
        lines.append(f"- growth of the {label} with the vertices: " + ", ".join(
            f"{a} to {b}: vertices^{np.log(cost(b) / cost(a)) / np.log(nv[b] / nv[a]):.2f}" for (a, _), (b, _) in pairs))
    csv_rows = rows + [dict(case=f"ball {mesh} scipy", wall_s=q["wall_s"], runs=1, wall_min=q["wall_s"], wall_max=q["wall_s"],
                            cpu_s=q["cpu_s"], peak_MiB=q["peak_MiB"], steps=q["steps"], qp_steps=q["qp_steps"],
                            ms_per_step=q["ms_per_step"], newton_iterations=0, newton_retries=0, gmres_iterations=0)
                       for mesh, q in scipy.items()]
    return csv_rows, "\n".join(lines)


# ---- the cost of a step against its floor (issue 34): the limit probe (edp/limit.edp: one solve with the factor of A
# and one product with K, as the driver factorises A) beside the run without foundation and the active-set run
STEP_COST_MESHES = [("ball", "meshes/ball.msh", 3), ("ball_medium", "meshes/ball_medium.msh", 3),
                    ("ball_refine4", "meshes/ball_refine4.msh", 3), ("disk_refine8", "meshes/disk_refine8.msh", 2)]
STEP_COST_DIAGNOSTICS_EVERY = "20"   # the no-foundation run again with max_strain every 20 steps (once a second of T)
STEP_COST_AIMS = {"ball_refine4": (1.2, 1.5), "disk_refine8": (None, 1.35)}   # (no foundation / limit, active set / no foundation)
# CHOLMOD's choices measured by the probe on the largest meshes: the ordering, supernodal or simplicial, OpenBLAS's threads
SOLVE_VARIANTS = [("default", "auto", None), ("amd", "auto", None), ("metis", "auto", None), ("nesdis", "auto", None),
                  ("default", "simplicial", None), ("default", "auto", "1")]


def limit_probe(mesh, dim, ordering="default", kind="auto", threads=None, repeats=20):
    """edp/limit.edp on one mesh: its key=value line as a dict, its CPU ms (FreeFEM's clock(), which counts
    OpenBLAS's threads) and wall ms (the plugin's steady clock) of a solve, of the two halves and of a product with K,
    over at least `repeats` repetitions and about 3 s of them (a first probe of one repetition sets their number)."""
    env = freefem_env(**({"OPENBLAS_NUM_THREADS": threads} if threads else {}))

    def probe(n):
        r = timed_process(["FreeFem++-nw", "-nw", "-v", "0", os.path.join(ROOT, "edp", "limit.edp"), "-mesh",
                           os.path.join(ROOT, mesh), "-dim", str(dim), "-n", str(n), "-ordering", ordering, "-kind", kind],
                          merge=True, env=env)
        line = [ln for ln in r.stdout.splitlines() if ln.startswith("limit ")]
        if r.returncode != 0 or not line:
            sys.exit(f"bench: the limit probe failed on {mesh}:\n{r.stdout}")
        values = dict(kv.split("=", 1) for kv in line[-1].split()[1:])
        return {k: (v if k in ("ordering", "kind") else float(v)) for k, v in values.items()}

    first = probe(1)
    wall = sum(first[k] for k in ("solve_wall_ms", "halves_wall_ms", "K_product_wall_ms"))
    return probe(max(repeats, min(20000, int(3000 / max(wall, 1e-3)))))


def step_cost_section(out_base, repeat):
    """For each mesh of STEP_COST_MESHES: the limit probe, and Test 1 (scene ball, or test1 on the disk) to T = 20 with
    the active set, without foundation, and one step (the set-up). Returns (rows for bench.csv, the text)."""
    rows, lines = [], []
    probes, by = {}, {}
    for mesh, path, dim in STEP_COST_MESHES:
        print(f"bench: limit {mesh} ...", flush=True)
        probes[mesh] = limit_probe(path, dim)
        scene = "ball" if dim == 3 else "test1"
        for name, args in ((f"step {mesh} set-up", ["-T", "0.05", "-solver", "activeset"]),
                           (f"step {mesh} activeset", ["-T", BALL_T, "-solver", "activeset"]),
                           (f"step {mesh} no foundation", ["-T", BALL_T, "-foundation", "none"]),
                           (f"step {mesh} no foundation thin", ["-T", BALL_T, "-foundation", "none",
                                                                "-diagnostics_every", STEP_COST_DIAGNOSTICS_EVERY])):
            print(f"bench: {name} ...", flush=True)
            r = timed_case(out_base, name.replace(" ", "_").replace("-", "_"), scene, ["-mesh", path] + args, repeat)
            r["case"] = name
            rows.append(r)
            by[name] = r
    def loop_ms(name, mesh):
        return ms_after_first_step(by[name], by[f"step {mesh} set-up"])
    lines += [f"Test 1 to T = {BALL_T} (scene ball; test1 on the disk): the limit is one solve with the factor of A and one "
              "product with K (edp/limit.edp: wall ms, on a steady clock); ms/step is a run's wall time less its one-step "
              f"run's, per further step; \"thin\": with -diagnostics_every {STEP_COST_DIAGNOSTICS_EVERY} (history.csv's max_strain "
              "every that many steps: docs/outputs.md).", "",
              "| mesh | dofs | limit: solve + K ms | no foundation ms/step | ÷ limit | thin ms/step | ÷ limit | active set ms/step | "
              "Schur columns | active set ÷ no foundation: run (loop) |", "| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |"]
    verdicts = []
    for mesh, path, dim in STEP_COST_MESHES:
        pr = probes[mesh]
        limit = pr["solve_wall_ms"] + pr["K_product_wall_ms"]
        act, none = by[f"step {mesh} activeset"], by[f"step {mesh} no foundation"]
        none_ms, act_ms = loop_ms(f"step {mesh} no foundation", mesh), loop_ms(f"step {mesh} activeset", mesh)
        thin_ms = loop_ms(f"step {mesh} no foundation thin", mesh)
        summary = read_summary(os.path.join(out_base, f"step_{mesh}_activeset"))
        run_ratio, loop_ratio = act["wall_s"] / none["wall_s"], act_ms / none_ms
        lines.append(f"| {mesh} | {int(pr['dofs'])} | {limit:.2f} | {none_ms:.2f} | {none_ms / limit:.2f} | {thin_ms:.2f} | "
                     f"{thin_ms / limit:.2f} | {act_ms:.2f} | "
                     f"{summary.get('schur_solves', '-')} | {run_ratio:.2f} ({loop_ratio:.2f}) |")
        aim_limit, aim_active = STEP_COST_AIMS.get(mesh, (None, None))
        if aim_limit:
            for what, ms in (("every step's diagnostics (the default)", none_ms),
                             (f"-diagnostics_every {STEP_COST_DIAGNOSTICS_EVERY}", thin_ms)):
                verdicts.append(f"- aim {mesh}: no foundation within {aim_limit}x the limit per step, {what}: "
                                f"{'met' if ms / limit <= aim_limit else 'NOT met'} ({ms / limit:.2f}x)")
        if aim_active:
            ok = run_ratio <= aim_active and loop_ratio <= aim_active
            verdicts.append(f"- aim {mesh}: the active set within {aim_active}x the run without foundation, over the run and "
                            f"in the loop: {'met' if ok else 'NOT met'} ({run_ratio:.2f}x, {loop_ratio:.2f}x)")
    lines += [""] + verdicts
    # CHOLMOD's choices on the two largest meshes
    lines += ["", "The factorisation's choices (edp/limit.edp; CHOLMOD's default is FreeFEM's own: AMD, METIS when AMD "
              "fills much, supernodal for these meshes; OpenBLAS threads: all cores unless 1):", "",
              "| mesh | ordering | kind | OpenBLAS threads | factorise s (CPU) | factor entries | solve wall ms | halves wall ms | solve CPU ms |",
              "| --- | --- | --- | --- | ---: | ---: | ---: | ---: | ---: |"]
    for mesh, path, dim in STEP_COST_MESHES[2:]:
        for ordering, kind, threads in SOLVE_VARIANTS:
            print(f"bench: limit {mesh} {ordering} {kind} {threads or 'all'} ...", flush=True)
            pr = probes[mesh] if (ordering, kind, threads) == ("default", "auto", None) else limit_probe(path, dim, ordering, kind, threads)
            lines.append(f"| {mesh} | {ordering} | {kind} | {threads or 'all'} | {pr['factorise_s']:.2f} | {pr['factor_entries']:.3g} | "
                         f"{pr['solve_wall_ms']:.2f} | {pr['halves_wall_ms']:.2f} | {pr['solve_ms']:.2f} |")
    return rows, "\n".join(lines)


# ---- friction (issue 35): a step with friction against the frictionless one, side by side (timed_group alternates the
# runs), on the disk (the slide scene: started static, launched at v0x = 0.5) and the ball (the same, in 3D); IPOPT on a
# shorter horizon (its step is a fixed point of about 5 solves; in 3D of the step's dual); the balls' frictionless runs
# on a longer one, whose loop would otherwise be within the set-up's noise (ball_medium's came out at -4.48 ms a step)
FRICTION_GROUPS = [
    ("disk", "slide", ["-T", "10"], [("frictionless", ["-friction", "none", "-solver", "activeset"]),
                                     ("coulomb", []), ("tresca", ["-friction", "tresca", "-friction_bound", "0.05"]),
                                     ("coulomb ipopt", ["-solver", "ipopt", "-T", "2"])]),
    ("ball", "ball", ["-T", "4", "-initial", "static", "-v0x", "0.5"],
     [("frictionless", ["-solver", "activeset", "-T", "20"]),
      ("coulomb", ["-friction", "coulomb", "-friction_coefficient", "0.3"]),
      ("coulomb ipopt", ["-friction", "coulomb", "-friction_coefficient", "0.3", "-solver", "ipopt", "-T", "1"])]),
    ("ball_medium", "ball", ["-T", "2", "-initial", "static", "-v0x", "0.5", "-mesh", "meshes/ball_medium.msh"],
     [("frictionless", ["-solver", "activeset", "-T", "10"]),
      ("coulomb", ["-friction", "coulomb", "-friction_coefficient", "0.3"])]),
]


def side_by_side(out_base, repeat, groups, prefix, baseline, cells):
    """Each group's runs, alternated, with one step of each (the set-up: the static start, the factorisation): per
    variant the loop's ms per step, its ratio to the baseline variant's, and cells(name, history, out dir)'s columns."""
    rows, lines = [], []
    for body, scene, base, variants in groups:
        group = []
        for name, args in variants:
            full = base + args
            if full.count("-T") > 1:          # (a variant's own horizon replaces the group's)
                at = full.index("-T")
                full = full[:at] + full[at + 2:]
            group.append((f"{prefix} {body} {name}", scene, full))
            at = full.index("-T")
            step = full[full.index("-dt") + 1] if "-dt" in full else "0.05"     # (one step: the scene's -dt is given)
            group.append((f"{prefix} {body} {name} set-up", scene, full[:at] + full[at + 2:] + ["-T", step]))
        by = {r["case"]: r for r in timed_group(out_base, group, repeat)}
        rows += list(by.values())
        plain = None
        for name, _ in variants:
            run, one = by[f"{prefix} {body} {name}"], by[f"{prefix} {body} {name} set-up"]
            ms = ms_after_first_step(run, one)
            plain = ms if name == baseline else plain
            out = os.path.join(out_base, f"{prefix} {body} {name}".replace(" ", "_"))
            lines.append(f"| {body} | {name} | {run['steps']} | {ms:.2f} | {ms / plain:.2f} | "
                         + " | ".join(cells(name, read_run(out), out)) + " |")
    return rows, lines


def friction_section(out_base, repeat):
    """Each group's runs, alternated, with one step of each (the set-up: the static start, the factorisation); the
    loop's ms per step, its ratio to the frictionless run's, and the iterations of a step's sets (or IPOPT's solves)."""
    def cells(name, h, out):
        qp = h["qp_solved"] > 0
        its = h["newton_iterations"][qp] if name != "frictionless" else np.zeros(1)
        return [f"{its.mean():.2f}, {its.max():.0f}", read_summary(out).get('schur_solves', '-')]
    rows, lines = side_by_side(out_base, repeat, FRICTION_GROUPS, "friction", "frictionless", cells)
    return rows, "\n".join(["Per step of the time loop (a run's wall time less its one-step run's, per further step), with "
                            "friction against the frictionless run of the same scene; iterations: a QP step's stick and slip "
                            "iterations (IPOPT: its solves).", "",
                            "| body | run | steps | ms/step | ÷ frictionless | iterations per step (mean, max) | Schur solves |",
                            "| --- | --- | ---: | ---: | ---: | --- | ---: |"] + lines)


# ---- the exact gap (issue 36): -gap exact against the paper's -gap linearised, side by side, on Test 2 (the same
# motion under both: its foundation is concave where the disk lands) and on the bowl, where (10) lets the body sink to
# the bottom (fewer QPs: the ratio is not that of the same motion); rounds: the QPs solved again per step
GAP_GROUPS = [
    ("test2", "test2", ["-T", "30", "-t1", "18", "-solver", "activeset"], [("linearised", []), ("exact", ["-gap", "exact"])]),
    ("disk bowl", "bowl", ["-T", "40", "-dt", "0.2"], [("linearised", ["-gap", "linearised"]), ("exact", [])]),
    ("ball bowl", "bowl", ["-T", "40", "-dt", "0.2", "-mesh", "meshes/ball.msh"], [("linearised", ["-gap", "linearised"]), ("exact", [])]),
]


def gap_section(out_base, repeat):
    def cells(name, h, out):
        steps = len(h["t"]) - 1
        rounds = int(read_summary(out).get("exact_gap_rounds", 0))
        return [f"{int(h['qp_solved'].sum())}", f"{rounds / steps:.2f}", f"{h['max_penetration_exact'].max():.2g}",
                f"{h['max_held_off_exact'].max():.2g}"]
    rows, lines = side_by_side(out_base, repeat, GAP_GROUPS, "gap", "linearised", cells)
    return rows, "\n".join(["Per step of the time loop (a run's wall time less its one-step run's, per further step), "
                            "-gap exact against the paper's -gap linearised; rounds: the QPs solved again per step, with the "
                            "rows linearised about the last result.", "",
                            "| body | gap | steps | ms/step | ÷ linearised | QP steps | rounds per step | "
                            "max_penetration_exact | max_held_off_exact |",
                            "| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |"] + lines)


# ---- -np N: the ball starting in contact (IMPACT, every step a QP with new Schur columns), to
# PARALLEL_T (50 steps on the small meshes, where 10 would be lost in the start-up's noise; 10 on the large ones),
# on 1, 2 and 4 processes beside the serial direct solver
PARALLEL_MESHES = BALL_MESHES + [("ball_refine6", "meshes/ball_refine6.msh")]
PARALLEL_NP = {"ball": [1, 2, 4], "ball_medium": [1, 2, 4], "ball_refine4": [1, 2, 4], "ball_refine6": [2, 4]}
# issue 37's aims: on ball_refine6, peak memory per process at most these fractions of the serial run's
MEMORY_AIMS = {2: 0.6, 4: 0.35}
PARALLEL_T = {"ball": "2.5", "ball_medium": "2.5", "ball_refine4": "0.5", "ball_refine6": "0.5"}


def parallel_section(out_base, repeat, only=None):
    """The -np rows: for each mesh of PARALLEL_MESHES (or those named in `only`), serially and on each N of
    PARALLEL_NP, a one-step run (the set-up) and a run to PARALLEL_T. Returns (rows for bench.csv, the text);
    draws parallel.png into out_base."""
    rows, by, runs = [], {}, {}
    meshes = [(m, path) for m, path in PARALLEL_MESHES if not only or m in only]
    for mesh, path in meshes:
        for n in [0] + PARALLEL_NP[mesh]:
            who = f"np {n}" if n else "serial"
            extra = ["-np", str(n)] if n else []
            for horizon in ("0.05", PARALLEL_T[mesh]):
                name = f"parallel {mesh} {who} T={horizon}"
                print(f"bench: {name} ...", flush=True)
                r = timed_case(out_base, name.replace(" ", "_").replace("=", ""), "ball",
                               ["-mesh", path, "-solver", "activeset", "-T", horizon] + IMPACT + extra, repeat)
                r["case"] = name
                rows.append(r)
                by[name] = r
            runs[(mesh, n)] = os.path.join(out_base, f"parallel_{mesh}_{who.replace(' ', '_')}_T{PARALLEL_T[mesh]}")
    lines = case_table(rows)
    lines += ["", "The ball starting in contact at Test 1's impact speed (every step a QP), to T = "
              + ", ".join(f"{PARALLEL_T[m]} on {m}" for m, _ in meshes) + ": set-up is the "
              "wall time of a one-step run, ms/step the rest per further step; solves are those with A (the predictor, the "
              "Schur columns of the nodes that enter the contact, the correction); memory is the largest process's peak.", "",
              "| mesh | vertices | dofs | processes | set-up s | ms/step | solves/step | Krylov it/solve | peak MiB/process | "
              "ms/step / serial | max abs u3_low difference from serial |",
              "| --- | ---: | ---: | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |"]
    table = {}
    for mesh, _ in meshes:
        serial = None
        for n in [0] + PARALLEL_NP[mesh]:
            who = f"np {n}" if n else "serial"
            one, run = by[f"parallel {mesh} {who} T=0.05"], by[f"parallel {mesh} {who} T={PARALLEL_T[mesh]}"]
            summary = read_summary(runs[(mesh, n)])
            ms = ms_after_first_step(run, one)
            solves = int(summary["schur_solves"]) + run["steps"] + run["qp_steps"]
            krylov = int(summary["krylov_iterations"]) / max(1, int(summary["krylov_solves"]))
            serial = serial or (run, ms)
            gap = np.abs(run["history"]["u3_low"] - serial[0]["history"]["u3_low"]).max()
            table[(mesh, n)] = dict(vertices=int(summary["vertices"]), setup=one["wall_s"], ms=ms, memory=run["peak_MiB"])
            lines.append(f"| {mesh} | {summary['vertices']} | {3 * int(summary['vertices'])} | {n if n else '1 (serial, CHOLMOD)'} | "
                         f"{one['wall_s']:.2f} | {ms:.1f} | {solves / run['steps']:.1f} | {krylov if n else 0:.1f} | "
                         f"{run['peak_MiB']:.0f} | {ms / serial[1]:.2f} | {gap:.2g} |")
    lines.append("")
    for n in (1, 2, 4):
        on_n = [m for m, _ in meshes if n in PARALLEL_NP[m]]
        if not on_n:
            continue
        faster = [m for m in on_n if table[(m, n)]["ms"] < table[(m, 0)]["ms"]]
        lines.append(f"- {n} process{'es' if n > 1 else ''}: faster than the serial direct solver per step on "
                     + (", ".join(faster) if faster else "none of " + ", ".join(on_n))
                     + "; memory per process " + ", ".join(f"{m} {table[(m, n)]['memory'] / table[(m, 0)]['memory']:.2f}x"
                                                           + memory_aim(m, n, table) for m in on_n) + " the serial run's")
    lines += memory_lines(table, meshes)
    plot_parallel(table, os.path.join(out_base, "parallel.png"))
    return rows, "\n".join(lines + [""] + strategy_lines(only))


def memory_fit(ns, mib):
    """m(N) = R + F / N^beta through the peaks mib on ns processes (least squares in R and F for each beta on a
    grid): (R, F, beta)."""
    best = None
    for beta in np.linspace(0.3, 2.0, 171):
        basis = np.vstack([np.ones(len(ns)), np.asarray(ns, float) ** -beta]).T
        coef, *_ = np.linalg.lstsq(basis, np.asarray(mib, float), rcond=None)
        err = np.sum((basis @ coef - mib) ** 2)
        if best is None or err < best[0]:
            best = (err, coef[0], coef[1], beta)
    return best[1], best[2], best[3]


def memory_aim(mesh, n, table):
    """" (issue 37's aim, at most 0.6x: holds)" for ball_refine6 on an N of MEMORY_AIMS, else ""."""
    if mesh != "ball_refine6" or n not in MEMORY_AIMS:
        return ""
    f = table[(mesh, n)]["memory"] / table[(mesh, 0)]["memory"]
    return f" (issue 37's aim, at most {MEMORY_AIMS[n]}x: {'holds' if f <= MEMORY_AIMS[n] else 'does not hold'})"


def memory_lines(table, meshes):
    """Peak memory per process against N: for each mesh run on three or more N, m(N) = R + F / N^beta fitted to
    its values, with the projection to 64 processes."""
    lines = []
    for mesh, _ in meshes:
        ns = [n for n in PARALLEL_NP[mesh] if (mesh, n) in table]
        if len(ns) >= 3:
            R, F, beta = memory_fit(ns, [table[(mesh, n)]["memory"] for n in ns])
            lines.append(f"- {mesh}: m(N) = {R:.0f} + {F:.0f} / N^{beta:.2f} MiB fitted on N = {ns} "
                         f"({R * 1024 / table[(mesh, ns[0])]['vertices']:.1f} KiB a vertex held whole); "
                         f"on 64 processes {R + F / 64 ** beta:.0f} MiB a process")
    return ["", "Peak memory per process against N:", ""] + lines if lines else []


STRATEGY_MESHES = [("ball", "meshes/ball.msh"), ("ball_medium", "meshes/ball_medium.msh")]


def strategy_lines(only=None):
    """The contact QP's two strategies under -np (docs/parallel.md), counted on scipy_midpoint's scheme (the same
    active set as the driver's) for the scene ball to T = 20: the Schur columns gathered, or S never formed (CG
    on S_aa, one solve with A a product). Every solve is a distributed Krylov solve under -np, so the count of
    solves with A is what decides."""
    sys.path.insert(0, os.path.dirname(SCIPY))
    import scipy_midpoint
    lines = ["The contact QP under -np: S's columns gathered (the driver's choice) against an active set on distributed "
             "solves that never forms S (each active-set iteration solving S_aa lm_a = r_a by CG to 1e-12, warm-started; "
             "tests/reference/scipy_midpoint.py, strategy=), on the scene ball to T = 20 (serial SuperLU; under -np each "
             "solve is a Krylov solve):", "",
             "| mesh | dofs | Gamma_C nodes | strategy | solves with A | predictor | Schur columns | corrections | CG products "
             "| warm starts | solves / QP step | largest CG | same active sets | max abs u3_low difference | ms/step (scipy) |",
             "| --- | ---: | ---: | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | --- | ---: | ---: |"]
    for mesh, path in STRATEGY_MESHES:
        if only and mesh not in only:
            continue
        print(f"bench: contact strategies on {mesh} ...", flush=True)
        res = {k: scipy_midpoint.run(os.path.join(ROOT, path), T=20.0, strategy=k) for k in ("gathered", "matrix-free")}
        ga = res["gathered"]["history"]
        for k, r in res.items():
            h, by = r["history"], r["solves_by_purpose"]
            same = bool((h["active_nodes"] == ga["active_nodes"]).all()
                        and (h["active_set_iterations"] == ga["active_set_iterations"]).all())
            lines.append(f"| {mesh} | {r['dofs']} | {r['contact_nodes']} | {k} | {r['solves']} | {by.get('predictor', 0)} | "
                         f"{by.get('schur_columns', 0)} | {by.get('correction', 0)} | {by.get('cg_products', 0)} | "
                         f"{by.get('warm_start', 0)} | {(r['solves'] - r['steps']) / r['qp_steps'] + 1:.1f} | "
                         f"{r['cg_max_iterations']} | {same} | {np.abs(h['u3_low'] - ga['u3_low']).max():.1e} | "
                         f"{r['ms_per_step']:.1f} |")
        ratio = res["matrix-free"]["solves"] / res["gathered"]["solves"]
        lines.append(f"| {mesh} | | | matrix-free / gathered | {ratio:.1f}x | | | | | | | | | | |")
    return lines


def plot_parallel(table, path):
    """parallel.png: ms per step and peak memory per process against the vertices, serially and on N processes."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    for n in sorted({n for _, n in table}):
        keys = sorted((k for k in table if k[1] == n), key=lambda k: table[k]["vertices"])
        v = [table[k]["vertices"] for k in keys]
        label = f"{n} process{'es' if n > 1 else ''} (ffddm)" if n else "serial (CHOLMOD)"
        axes[0].loglog(v, [table[k]["ms"] for k in keys], "o-", label=label)
        axes[1].loglog(v, [table[k]["memory"] for k in keys], "o-", label=label)
    axes[0].set(xlabel="vertices", ylabel="ms per step (the impact, every step a QP)")
    axes[1].set(xlabel="vertices", ylabel="peak MiB per process")
    for ax in axes:
        ax.grid(True, which="both", alpha=0.3)
        ax.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def write_tables(out, stem, rows, text):
    """stem.md (text) and stem.csv (one line per row) into out."""
    with open(os.path.join(out, f"{stem}.md"), "w") as fh:
        fh.write(text + "\n")
    with open(os.path.join(out, f"{stem}.csv"), "w") as fh:
        keys = ["case", "wall_s", "runs", "wall_min", "wall_max", "cpu_s", "peak_MiB", "steps", "qp_steps", "ms_per_step",
                "newton_iterations", "newton_retries", "gmres_iterations"]
        fh.write(",".join(keys) + "\n")
        for r in rows:
            fh.write(",".join(str(r[k]) for k in keys) + "\n")


NH_AIM = 1.5    # a Neo-Hookean step at most 1.5x an SVK step on Test 1


def nh_lines(by, svk_pairs, horizon, full):
    """The Neo-Hookean rows beside SVK's, from the same run: per case wall s, ms/step, Newton it/step,
    GMRES it/Newton it, ms/Newton it, and the ratios NH / SVK, with the aim NH_AIM. Without `full`
    (--nh-only) the table of wall times of those runs comes first."""
    lines = []
    if not full:
        lines += ["| case | wall s | runs (wall range) | CPU s | peak MiB | steps | QP steps | ms/step |",
                  "| --- | ---: | --- | ---: | ---: | ---: | ---: | ---: |"]
        for r in by.values():
            lines.append(f"| {r['case']} | {r['wall_s']:.2f} | {r['runs']} ({r['wall_min']:.2f}-{r['wall_max']:.2f}) | "
                         f"{r['cpu_s']:.2f} | {r['peak_MiB']:.0f} | {r['steps']} | {r['qp_steps']} | {r['ms_per_step']:.2f} |")
        lines.append("")
    pairs = [(key, f"{key} svk", f"{key} neohookean") for key, _, _ in svk_pairs]
    pairs.append(("test1 T=16 P2", "test1 T=16 svk P2", "test1 T=16 neohookean P2"))
    lines += ["Neo-Hookean (-material neohookean) beside SVK, same cases, same run:", "",
              "| case | material | wall s (range) | ms/step | Newton it/step | GMRES it/Newton it | Newton retries | "
              "ms/Newton it | NH / SVK: wall (slowest NH / fastest SVK) | NH / SVK: ms/Newton it |",
              "| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |"]

    def cells(r):
        return (f"{r['wall_s']:.2f} ({r['wall_min']:.2f}-{r['wall_max']:.2f}) | {r['ms_per_step']:.2f} | "
                f"{r['newton_iterations'] / r['steps']:.2f} | {r['gmres_iterations'] / max(1, r['newton_iterations']):.2f} | "
                f"{r['newton_retries']} | {r['wall_s'] * 1000 / max(1, r['newton_iterations']):.2f}")
    worst = {}
    for key, svk, nh in pairs:
        s, n = by[svk], by[nh]
        worst[key] = n["wall_max"] / s["wall_min"]
        per_it = (n["wall_s"] / n["newton_iterations"]) / (s["wall_s"] / s["newton_iterations"])
        lines += [f"| {key} | SVK | {cells(s)} | | |",
                  f"| {key} | Neo-Hookean | {cells(n)} | {n['wall_s'] / s['wall_s']:.2f} ({worst[key]:.2f}) | {per_it:.2f} |"]
    r = by["test1 neohookean"]
    lin = by["test1 activeset"]
    lines += ["", f"- Neo-Hookean, the paper's Test 1 to T = {horizon} (SVK collapses at t = 16.8): {r['wall_s']:.2f} s, "
              f"{r['ms_per_step']:.2f} ms/step, {r['newton_iterations'] / r['steps']:.2f} Newton it/step, "
              f"{r['gmres_iterations'] / r['newton_iterations']:.2f} GMRES it/Newton it, {r['newton_retries']} retries; "
              f"{r['wall_s'] / lin['wall_s']:.1f}x the linear activeset wall time ({lin['wall_s']:.2f} s)",
              f"- aim of a Neo-Hookean step at most {NH_AIM:g}x an SVK step on Test 1: "
              + "; ".join(f"{key} {by[nh]['wall_s'] / by[svk]['wall_s']:.2f}x "
                          f"({'met' if by[nh]['wall_s'] / by[svk]['wall_s'] <= NH_AIM else 'NOT met'})"
                          for key, svk, nh in pairs[:-1])
              + f"; P2 {by[pairs[-1][2]]['wall_s'] / by[pairs[-1][1]]['wall_s']:.2f}x (not part of the aim)"]
    return lines


if __name__ == "__main__":
    main()
