"""`make hertz`: the 3D ball's impact on the rigid flat against Hertz's theory (docs/hertz.md).

Hertz's impact (Johnson, Contact Mechanics, section 11.4): an elastic ball of radius R, density rho
and moduli E, nu (from lambda, mu: E = mu (3 lambda + 2 mu)/(lambda + mu), nu = lambda/(2 (lambda + mu)))
strikes a rigid flat at speed v0. With
    m = 4/3 pi rho R^3,   E* = E/(1 - nu^2) (the flat is rigid),   K = 4/3 E* sqrt(R),
the approach delta(t) (how far the ball's far points have come closer to the flat since the first
touch) obeys
    m delta'' = -K delta^(3/2),   delta(0) = 0,   delta'(0) = v0,
and the contact force is F = K delta^(3/2). Its energy m/2 delta'^2 + 2/5 K delta^(5/2) = m/2 v0^2
gives the largest approach, force and contact radius (a^2 = R delta)
    delta* = (15 m v0^2 / (16 E* sqrt(R)))^(2/5),   F* = K delta*^(3/2),   a* = sqrt(R delta*),
and the contact time
    T_H = 2 delta*/v0 int_0^1 dx / sqrt(1 - x^(5/2)) = 4/5 B(2/5, 1/2) delta*/v0 = 2.943275 delta*/v0
(Johnson's 2.94). integrate_impact() integrates the ODE by RK4 and finds the
same constant from the ODE alone (tests/test_hertz_theory.py). In the units of the peak,
x = delta/delta*, s = t v0/delta*, the ODE is x'' = -5/4 x^(3/2), x(0) = 0, x'(0) = 1, the energy
x'^2 + x^(5/2) = 1, and F/F* = x^(3/2): one curve for every v0, ball and material.

The study runs the scene `hertz` (the ball touching the flat X3 = 0 at t = 0, thrown down at -v0, f = 0,
lambda = mu = 30, rho = 1) through edp/run.sh for v0/c* = 1e-2, 1e-3, 1e-4 (c* = sqrt(E*/rho)), each
on meshes/hertz_coarse.msh and meshes/hertz.msh and with dt = T_H/50 and T_H/100 (to 3 digits), to
T = 1.3 T_H, and at v0/c* = 1e-3 on the default mesh also with the singular mass (-mass singular:
no mass on Gamma_C: its effect on the restitution; a run the driver
refuses, as it may refuse that mass on a mesh, is named in the summary instead); --jobs at a time,
into OUT/<case>/. From each history.csv (columns of the 3D driver: contact_force_z, contact_area,
u3_mean, v3_mean, energy) it measures (measure()):
  contact time      from the first to the last step with contact_force_z > 0 (above 1e-6 of its
                    peak), each end refined by the zero of the line through the two samples of
                    F^(2/3) next to it (F^(2/3) is proportional to delta, linear in t at the ends);
  peak force        the largest contact_force_z, refined by the parabola through it and its neighbours;
  largest approach  the largest delta = -u3_mean (the centre of mass's descent; the lowest node sits
                    on the flat during contact, so it cannot give delta), refined likewise;
  contact radius    sqrt(contact_area/pi) at the step of the peak force, against a*;
  restitution       e = v3_mean at the last step (after the ball has left the flat) / v0;
  energy lost       1 - energy at the last step / energy at step 0;
  mesh mass / m     2 energy(0) / v0^2 / m: the tetrahedra's volume against the ball's.
Writes OUT/summary.md (a table per v0/c*, each run's values and their differences from Hertz, and
issue 25's targets), OUT/hertz.csv, and OUT/hertz.png/.pdf (F/F* and delta/delta* against t/T_H,
the runs on Hertz's curve). Without the scene (it comes with the 3D driver) this script stops
before anything else with one `error:` line and exit status 1; a run that fails (but the singular
mass's) stops it likewise.
Hertz's theory, the cases and measure() are in hertz_analysis.py.
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import jobs  # noqa: E402
from driver import ROOT, run_case as run_driver  # noqa: E402
from hertz_analysis import CASES, LAMBDA, MESHES, MU, RHO, SPEED_OPTION, Failure, case_hertz, report, time_grid  # noqa: E402

SCENE = os.path.join(ROOT, "edp", "scenes", "hertz.idp")


def run_case(out, scene, case):
    ratio, mesh, n, mass = CASES[case]
    h = case_hertz(case)
    dt, steps = time_grid(h, n)
    run_dir = os.path.join(out, case)
    args = ["-progress", "0", "-mesh", MESHES[mesh], SPEED_OPTION, f"{-h['v0']:.10g}",
            "-dt", repr(dt), "-T", f"{steps * dt:.12g}", "-lambda", f"{LAMBDA:g}", "-mu", f"{MU:g}", "-rho", f"{RHO:g}",
            "-solver", "activeset", "-snapshots", "none"] + (["-mass", mass] if mass else [])
    p = run_driver(scene, run_dir, args, log=os.path.join(out, f"{case}.log"), cwd=ROOT)
    if p.returncode != 0 or not os.path.exists(os.path.join(run_dir, "summary.txt")):
        line = p.last_line
        if mass is None:
            raise Failure(f"hertz {case} failed (exit {p.returncode}; see {case}.log): {line}")
        return case, p.wall, f"exit {p.returncode}: {line}"
    return case, p.wall, None


def main():
    ap = jobs.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", default="results/hertz")
    ap.add_argument("--cases", default=",".join(CASES), help="comma-separated subset of " + ",".join(CASES))
    ap.add_argument("--jobs", type=jobs.positive_int, default=2)
    ap.add_argument("--scene", default=SCENE, help="the scene file (default edp/scenes/hertz.idp)")
    jobs.add_processes_option(ap)
    a = ap.parse_args()
    jobs.use_processes(a.np)
    names = a.cases.split(",")
    for c in names:
        if c not in CASES:
            sys.exit(f"error: make hertz: --cases: no case '{c}' (cases: {', '.join(CASES)})")
    if not os.path.isfile(a.scene):
        sys.exit(f"error: make hertz: no scene {os.path.relpath(a.scene, ROOT)} (the scene hertz comes with the 3D "
                 "driver, issue 25); nothing was run")
    out = os.path.abspath(a.out)
    os.makedirs(out, exist_ok=True)
    jobs.stop_on_interrupt("make hertz", out, ["summary.md", "hertz.csv", "*.png", "*.pdf"])
    failed = {}
    try:
        for case, seconds, why in jobs.run_parallel(lambda c: run_case(out, os.path.abspath(a.scene), c), names, a.jobs):
            print(f"hertz {case}: {seconds:.0f} s" + (f", did not run to T ({why})" if why else ""), flush=True)
            if why:
                failed[case] = why
        print(report(out, [c for c in names if c not in failed], failed))
    except Failure as e:
        sys.exit(f"error: {e}")
    print(f"hertz: {os.path.join(a.out, 'summary.md')}")


if __name__ == "__main__":
    main()
