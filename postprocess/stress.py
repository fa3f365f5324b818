"""`make stress`: hard cases, each with the criteria it must pass.

Criteria for every case:
  - every value of history.csv finite;
  - the solver succeeds on every step (a failed step stops the run: exit 4);
  - penetration (violation of (10)) no larger than the solver tolerance, 1e-8;
  - the energy bound that applies:
      f = 0 (Prop. 2, foundation fixed or decreasing): the discrete energy
        rho/2|v|^2 + a(u,u)/2 does not increase from step to step;
      gravity, foundation fixed or decreasing: the modified energy does not
        increase (take w = u^n in (1); f is constant);
    both up to the solver tolerance, 1e-8 of the energy's size;
  - a run that exits 0 reaches its horizon T.
The cases of THROUGH squash the body past Gamma_C (an impact near its P-wave speed, or a soft body): its
boundary beside Gamma_C may go more than 5% of its size below the foundation, and the run then stops there
(exit 4, docs/errors.md). That stop is an accepted outcome of theirs, when it is clean: one
stderr line "error: the body passed through the foundation at step N ...", history.csv holding steps 0..N,
the last the first whose max_penetration_outside passed 5% of the body's size, every row passing the criteria.
The "svk ..." cases run the St Venant-Kirchhoff body (-material svk, Newton),
whose energy is v'Mv / 2 + int W(E(u)) (modified: minus (f,u)); same criteria.
SVK may collapse under strong compression (an element inverts, or past the
collapse no step solution exists and Newton does not converge). For an svk case
the outcome "breaks at t = X: <reason>" is accepted, and reported as such with
Newton's reason, never as a pass of the full horizon, only when the run stops
cleanly: exit 4 with one stderr line "error: newton failed at step N, t = X: ...",
and history.csv intact (steps 0..N-1, all finite, no penetration, the energy
bound on every recorded step). Any other failure of an svk case is a failure.
The "neohookean ..." cases run the Neo-Hookean body (-material neohookean, Newton with
Gonzalez's discrete gradient) on the four cases where SVK collapses (dt 1, v0y -5, the
soft lambda = mu = 3, the fast drop). Their criteria, set before any of them was run:
every value finite; penetration <= 1e-8; min_J > 0 in every recorded step;
and no energy gain at round-off level: the largest one-step rise of the modified energy
at most NH_ROUNDOFF = 1e-12 of its size (the scheme is energy non-increasing with contact
on a fixed foundation, and on the fast drop's lowered one the contact force does no
positive work; the non-linear runs measured so far rise by at most 3e-14 relative). A
case passes when it completes its horizon, or when it stops cleanly as an svk case may
(exit 4, one "newton failed" line, the history intact and passing these criteria): the
outcome column says which.
The cases of METHOD_CASES run the methods of docs/methods.md, with their own bounds (below).
The cases of FRICTION_CASES run Coulomb's friction (docs/friction.md); their energy bound is Prop. 2 with
friction: E - (f, u) + D - W does not increase (D the friction's work, W the foundation's along itself), up to
the solver tolerance.
Writes results/stress/summary.md (one row per case; --nh-only: the Neo-Hookean cases
alone, into summary_neohookean.md). The cases, these criteria and `FAST`, the subset that
`make check` runs on shorter horizons, are in stress_cases.py.
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import jobs  # noqa: E402
from driver import ROOT, run_case as run_driver  # noqa: E402
from stress_cases import BALL_CASES, CASES, FAST, FRICTION_CASES, METHOD_CASES, case_args, evaluate, is_neohookean, \
    outcome  # noqa: E402


def run(name, out, horizon=None):
    scene, args = case_args(name, horizon)
    p = run_driver(scene, out, ["-progress", "0", "-vtk", "0"] + args)
    return p, p.wall


def main():
    p = jobs.ArgumentParser(description=__doc__)
    p.add_argument("--out", default=os.path.join(ROOT, "results", "stress"))
    p.add_argument("--fast", action="store_true", help="only the make check subset")
    p.add_argument("--methods-only", action="store_true",
                   help="only the cases of the methods (METHOD_CASES), into summary_methods.md (summary.md is left as it is)")
    p.add_argument("--nh-only", action="store_true",
                   help="only the Neo-Hookean cases, into summary_neohookean.md (summary.md is left as it is)")
    p.add_argument("--friction-only", action="store_true",
                   help="only the friction cases (FRICTION_CASES), into summary_friction.md (summary.md is left as it is)")
    p.add_argument("--ball-only", action="store_true",
                   help="only the 3D ball's cases (BALL_CASES), into summary_ball.md (summary.md is left as it is)")
    jobs.add_processes_option(p)
    a = p.parse_args()
    jobs.use_processes(a.np)
    os.makedirs(a.out, exist_ok=True)
    summary = "summary_neohookean.md" if a.nh_only else "summary_methods.md" if a.methods_only else \
        "summary_ball.md" if a.ball_only else "summary_friction.md" if a.friction_only else "summary.md"
    jobs.stop_on_interrupt("make stress", a.out, [summary])
    names = list(FAST) if a.fast else [n for n in CASES if is_neohookean(n)] if a.nh_only else \
        list(METHOD_CASES) if a.methods_only else list(BALL_CASES) if a.ball_only else \
        list(FRICTION_CASES) if a.friction_only else list(CASES)
    lines = ["| case | stresses | outcome | steps | energy bound | max one-step gain (relative) | max penetration | "
             "max active nodes | contact intervals | failures | seconds |",
             "| --- | --- | --- | ---: | --- | ---: | ---: | ---: | ---: | --- | ---: |"]
    failed = broken = stopped = 0
    for name in names:
        print(f"stress: {name} ...", flush=True)
        out = os.path.join(a.out, name.replace(" ", "_").replace("=", "").replace("+", "plus"))
        proc, seconds = run(name, out, FAST[name] if a.fast else None)
        m, failures = evaluate(name, out, proc.returncode, proc.stderr)
        failed += bool(failures)
        broken += bool(m["broke"]) and not failures
        stopped += bool(m.get("stopped") or m.get("through")) and not failures
        if m["steps"]:
            lines.append(f"| {name} | {CASES[name][3]} | {outcome(m, failures)} | {m['steps']} | {m['energy']} | "
                         f"{m['max_gain']:.2g} ({m['rel_gain']:.1e}) | {m['max_penetration']:.1e} | {m['max_active']} | "
                         f"{m['bounces']} | {'; '.join(failures) or 'none'} | {seconds:.1f} |")
        else:
            lines.append(f"| {name} | {CASES[name][3]} | FAILED | 0 | | | | | | {'; '.join(failures)} | {seconds:.1f} |")
    text = "\n".join(lines)
    with open(os.path.join(a.out, summary), "w") as f:
        f.write(text + "\n")
    print(text)
    print(f"{len(names) - failed - broken - stopped} completed their horizon, {broken} broke as accepted (SVK or Neo-Hookean "
          f"collapse, exit 4, one 'newton failed' line), {stopped} stopped as accepted (the energy guard, or the body through the "
          f"foundation: exit 4, one line), "
          f"{failed} failed")
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()
