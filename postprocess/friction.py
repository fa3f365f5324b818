"""`make friction`: friction's closed-form rigid-body benchmarks (docs/friction.md), run by this code.

Each case starts the body at rest on the foundation (-initial static), stiff enough to be nearly rigid
(lambda = mu = 3000, the linear body: the Neo-Hookean one with friction is not implemented yet), with Coulomb's
friction and the exact active set, and compares it with the rigid body's closed form (g = 0.1, R = 20, a disk:
I = m R^2 / 2; a sphere: I = 2/5 m R^2):
  incline slides     the 10 degree plane, F = 0.02 (tan theta > 3 F): the centre's speed along the slope
                     g (sin theta - F cos theta) t, the spin 2 F g cos theta t / R;
  incline rolls      F = 0.5 (tan theta <= 3 F): speed 2/3 g sin theta t, spin that over R;
  at the threshold   tan theta = 3 F (theta = 30.96 degrees, F = 0.2): both formulas agree, 2/3 g sin theta t;
  skidding launch    v0 = 0.5 on the flat, F = 0.3: it rolls from t* = v0 / (3 F g) at 2 v0 / 3, friction having
                     taken 1/3 of the kinetic energy;
  belt               set down on a belt at V = 0.5, F = 0.3: it rolls from t* = V / (3 F g) at V / 3;
  oblique ball       the Hertz ball (hertz_coarse, dt = 0.2) thrown at the flat at v_t / v_n = 4 > 7/2 F (1 + e):
                     it slides throughout, the tangential impulse F times the normal one, the spin
                     5 F (1 + e) v_n / (2 R), e its measured normal restitution.
Writes OUT/summary.md (a table: each quantity, this code, the closed form, the difference), OUT/friction.csv and
OUT/friction.png/.pdf (the disk cases' speed and spin against their closed forms); each run in OUT/<case>/.
A run that fails stops the study with one `error:` line and exit status 1.
"""
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import jobs  # noqa: E402
from driver import ROOT, run_case as run_driver  # noqa: E402
from history import read_run  # noqa: E402

G, R, V0 = 0.1, 20.0, 0.5
STIFF = ["-lambda", "3000", "-mu", "3000", "-initial", "static", "-snapshots", "none", "-progress", "0"]
THRESHOLD = math.degrees(math.atan(0.6))
CASES = {
    "incline slides": ("roll", STIFF + ["-friction_coefficient", "0.02", "-T", "10"]),
    "incline rolls": ("roll", STIFF + ["-friction_coefficient", "0.5", "-T", "10"]),
    "at the threshold": ("roll", STIFF + ["-angle", repr(THRESHOLD), "-friction_coefficient", "0.2", "-T", "10"]),
    "skidding launch": ("slide", STIFF + ["-T", "12"]),
    "belt": ("belt", STIFF + ["-T", "12"]),
    "oblique ball": ("oblique_ball", ["-mesh", os.path.join(ROOT, "meshes", "hertz_coarse.msh"), "-dt", "0.2",
                                      "-snapshots", "none", "-progress", "0"]),
}


def slope_case(h, theta_deg, F, rolls):
    """(speed along the slope, spin) measured at the last step, and the closed form's."""
    th, t = math.radians(theta_deg), h["t"][-1]
    speed = -(h["v1_mean"][-1] * math.cos(th) + h["v2_mean"][-1] * math.sin(th))
    a = 2 / 3 * G * math.sin(th) if rolls else G * (math.sin(th) - F * math.cos(th))
    spin = a * t / R if rolls else 2 * F * G * math.cos(th) * t / R
    return [("speed along the slope at t = 10", speed, a * t), ("spin at t = 10", h["angular_velocity"][-1], spin)]


def rolling_from(h, v_contact):
    """When the contact point first moves with the foundation: the first zero of its velocity relative to it (the
    sign change after the first step, interpolated linearly), and v1 then."""
    start = np.sign(v_contact[1])
    k = int(np.argmax(np.sign(v_contact[1:]) != start)) + 1
    w = v_contact[k - 1] / (v_contact[k - 1] - v_contact[k])
    return h["t"][k - 1] + w * (h["t"][k] - h["t"][k - 1]), h["v1_mean"][k - 1] + w * (h["v1_mean"][k] - h["v1_mean"][k - 1])


def rows_of(case, h):
    """The case's rows: (quantity, this code, closed form)."""
    if case == "incline slides":
        return slope_case(h, 10, 0.02, False)
    if case == "incline rolls":
        return slope_case(h, 10, 0.5, True)
    if case == "at the threshold":
        return slope_case(h, THRESHOLD, 0.2, True)[:1]
    if case == "skidding launch":
        t_star, v = rolling_from(h, h["v1_mean"] + R * h["angular_velocity"])
        mass = np.median(np.diff(h["t"])[1:] * h["contact_force_x"][2:] / np.diff(h["v1_mean"])[1:])
        work = np.interp(t_star, h["t"], h["friction_work"])
        return [("t* (rolling from)", t_star, V0 / (3 * 0.3 * G)), ("v1 at t*", v, 2 * V0 / 3),
                ("friction's work at t* / initial kinetic energy", work / (0.5 * mass * V0**2), 1 / 3)]
    if case == "belt":
        t_star, v = rolling_from(h, h["v1_mean"] + R * h["angular_velocity"] - V0)
        return [("t* (rolling from)", t_star, V0 / (3 * 0.3 * G)), ("v1 at t*", v, V0 / 3)]
    normal = h["contact_force_z"].sum()
    tangential = math.hypot(h["contact_force_x"].sum(), h["contact_force_y"].sum())
    e = h["v3_mean"][-1] / 0.0125
    return [("tangential impulse / normal impulse", tangential / normal, 0.3),
            ("spin after the impact", h["angular_velocity_2"][-1], 5 * 0.3 * (1 + e) * 0.0125 / (2 * R))]


def run_one(out, case):
    scene, args = CASES[case]
    run_dir = os.path.join(out, case.replace(" ", "_"))
    p = run_driver(scene, run_dir, args, log=os.path.join(out, case.replace(" ", "_") + ".log"), cwd=ROOT)
    if p.returncode != 0:
        raise RuntimeError(f"make friction: {case} failed (exit {p.returncode}): {p.last_line}")
    return case, p.wall


def figure(out, runs):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 3, figsize=(12, 3.6), layout="constrained")
    for case, theta, F, rolls, ax in (("incline slides", 10, 0.02, False, axes[0]), ("incline rolls", 10, 0.5, True, axes[1])):
        h, th = runs[case], math.radians(theta)
        a = 2 / 3 * G * math.sin(th) if rolls else G * (math.sin(th) - F * math.cos(th))
        ax.plot(h["t"], -(h["v1_mean"] * math.cos(th) + h["v2_mean"] * math.sin(th)), label="speed along the slope")
        ax.plot(h["t"], a * h["t"], "k--", lw=1, label="rigid body")
        ax.plot(h["t"], R * h["angular_velocity"], label="R x spin")
        ax.plot(h["t"], (a if rolls else 2 * F * G * math.cos(th)) * h["t"], "k:", lw=1, label="rigid body")
        ax.set(title=f"{case} (F = {F})", xlabel="t")
        ax.legend(fontsize=7)
    h, ax = runs["skidding launch"], axes[2]
    t_star = V0 / (3 * 0.3 * G)
    ax.plot(h["t"], h["v1_mean"], label="v1")
    ax.plot(h["t"], -R * h["angular_velocity"], label="-R x spin")
    ax.plot(h["t"], np.where(h["t"] < t_star, V0 - 0.3 * G * h["t"], 2 * V0 / 3), "k--", lw=1, label="rigid body")
    ax.plot(h["t"], np.where(h["t"] < t_star, 2 * 0.3 * G * h["t"], 2 * V0 / 3), "k:", lw=1)
    ax.set(title="skidding launch (F = 0.3)", xlabel="t")
    ax.legend(fontsize=7)
    for ext in ("png", "pdf"):
        fig.savefig(os.path.join(out, f"friction.{ext}"), dpi=110)


def main():
    ap = jobs.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", default="results/friction")
    ap.add_argument("--jobs", type=jobs.positive_int, default=2)
    a = ap.parse_args()
    out = os.path.abspath(a.out)
    os.makedirs(out, exist_ok=True)
    jobs.stop_on_interrupt("make friction", out, ["summary.md", "friction.csv", "*.png", "*.pdf"])
    try:
        for case, seconds in jobs.run_parallel(lambda c: run_one(out, c), list(CASES), a.jobs):
            print(f"friction {case}: {seconds:.0f} s", flush=True)
    except RuntimeError as e:
        sys.exit(f"error: {e}")
    runs = {case: read_run(os.path.join(out, case.replace(" ", "_"))) for case in CASES}
    lines = ["| case | quantity | this code | rigid body | difference |", "| --- | --- | ---: | ---: | ---: |"]
    csv = ["case,quantity,this_code,rigid_body,difference"]
    for case, h in runs.items():
        for what, got, want in rows_of(case, h):
            lines.append(f"| {case} | {what} | {got:.6g} | {want:.6g} | {100 * (got / want - 1):+.2f}% |")
            csv.append(f"{case},{what},{got:.9g},{want:.9g},{got / want - 1:.6g}")
    text = "\n".join(lines)
    with open(os.path.join(out, "summary.md"), "w") as f:
        f.write(text + "\n")
    with open(os.path.join(out, "friction.csv"), "w") as f:
        f.write("\n".join(csv) + "\n")
    figure(out, runs)
    print(text)
    print(f"friction: {os.path.join(a.out, 'summary.md')}")


if __name__ == "__main__":
    main()
