"""`make friction`: friction's closed-form rigid-body benchmarks (docs/friction.md), run by this code.

Each disk case runs on three bodies, with Coulomb's friction, started at rest on the foundation (-initial static):
  stiff Neo-Hookean  lambda = mu = 3000, nearly rigid and objective: the body the closed forms are checked on;
  stiff linear       lambda = mu = 3000, the linear body (it cannot turn without straining: docs/friction.md);
  soft Neo-Hookean   lambda = mu = 30, the paper's disk (it sags 8.6% of R).
and compares it with the rigid body's closed form (g = 0.1, R = 20, a disk: I = m R^2 / 2; a sphere: 2/5 m R^2):
  incline slides     the 30 degree plane, F = 0.1 (tan theta > 3 F): the centre's acceleration along the slope
                     g (sin theta - F cos theta), the angular acceleration 2 F g cos theta / R;
  incline rolls      the 10 degree plane, F = 0.5 (tan theta <= 3 F): 2/3 g sin theta, and that over R;
  at the threshold   tan theta = 3 F (theta = 30.96 degrees, F = 0.2): both formulas agree, 2/3 g sin theta;
  skidding launch    v0 = 0.5 on the flat, F = 0.3: it rolls from t* = v0 / (3 F g) at 2 v0 / 3, friction having
                     taken 1/3 of the kinetic energy;
  belt               set down on a belt at V = 0.5, F = 0.3: it rolls from t* = V / (3 F g) at V / 3;
  the sphere         rolling, sliding, the threshold, the skidding launch and the belt of the stiff Neo-Hookean Hertz ball
                     (hertz_coarse, dt = 0.2), against the rigid body of its mesh (below, SPHERES);
  oblique ball       the Hertz ball (hertz_coarse, linear, dt = 0.2) thrown at the flat at v_t / v_n = 4 >
                     7/2 F (1 + e): it slides throughout, the tangential impulse F times the normal one, the spin
                     5 F (1 + e) v_n / (2 R), e its measured normal restitution.
  below gross slip   the same ball at normalised incidences Psi1 = 0.5 ... 8 (Maw, Barber and Fawcett's), against their
                     theory (postprocess/oblique_theory.py): the normalised rebound Psi2 and the spin.
Released at t = 0, a body rocks on its elastic contact (a period of about 3 on the stiff disk), so the incline's
accelerations are those of the least-squares parabolas through the centre's displacement and the angle turned over
the run, not the last values of the speed and the spin.
Writes OUT/summary.md (a table: each quantity, the closed form, and each body's value and difference),
OUT/friction.csv and OUT/friction.png/.pdf (the stiff Neo-Hookean disk's speed and spin against the closed forms,
the linear body's beside them), OUT/oblique.csv and OUT/friction_oblique.png/.pdf (the oblique impacts); each run in OUT/<case>/<body>/. A run that fails stops the study with one `error:`
line and exit status 1.
"""
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import jobs  # noqa: E402
from driver import ROOT, run_case as run_driver  # noqa: E402
from history import read_run  # noqa: E402
import oblique_theory  # noqa: E402

G, R, V0 = 0.1, 20.0, 0.5
QUIET = ["-initial", "static", "-snapshots", "none", "-progress", "0"]
BODIES = {
    "stiff Neo-Hookean": ["-material", "neohookean", "-lambda", "3000", "-mu", "3000"],
    "stiff linear": ["-lambda", "3000", "-mu", "3000"],
    "soft Neo-Hookean": ["-material", "neohookean"],
}
THRESHOLD = math.degrees(math.atan(0.6))
SLOPES = {   # case: (theta in degrees, F)
    "incline slides": (30.0, 0.1),
    "incline rolls": (10.0, 0.5),
    "at the threshold": (THRESHOLD, 0.2),
}
DISK_K = 0.5                      # I / (m R^2) of the rigid disk
CASES = {
    **{case: ("roll", QUIET + ["-angle", repr(theta), "-friction_coefficient", str(F), "-T", "10"])
       for case, (theta, F) in SLOPES.items()},
    "skidding launch": ("slide", QUIET + ["-T", "12"]),
    "belt": ("belt", QUIET + ["-T", "12"]),
}
BALL = ("oblique_ball", ["-mesh", os.path.join(ROOT, "meshes", "hertz_coarse.msh"), "-dt", "0.2", "-snapshots", "none",
                         "-progress", "0"])
HERTZ = os.path.join(ROOT, "meshes", "hertz_coarse.msh")


def ball_of_mesh(path):
    """The rigid body of a tetrahedral mesh (MSH 2.2) resting on its lowest point: its volume, its moment of inertia
    about a horizontal axis through its centre of mass, and the height h of that centre above the lowest point
    (exact integrals of the tetrahedra)."""
    lines = open(path).read().split("\n")
    i = lines.index("$Nodes")
    points = np.array([[float(v) for v in line.split()[1:4]] for line in lines[i + 2:i + 2 + int(lines[i + 1])]])
    i = lines.index("$Elements")
    tets = np.array([[int(v) - 1 for v in line.split()[-4:]] for line in lines[i + 2:i + 2 + int(lines[i + 1])]
                     if line.split()[1] == "4"])
    q = points[tets]
    a = q[:, 0]
    vol = np.abs(np.einsum("ij,ij->i", np.cross(q[:, 1] - a, q[:, 2] - a), q[:, 3] - a)) / 6
    volume = vol.sum()
    centre = (vol[:, None] * q.mean(1)).sum(0) / volume
    s = q.sum(1)
    second = np.einsum("i,ij,ik->jk", vol / 20, s, s) + np.einsum("i,inj,ink->jk", vol / 20, q, q)
    second -= volume * np.outer(centre, centre)
    return volume, second[0, 0] + second[2, 2], centre[2] - points[:, 2].min()


# The sphere: the stiff Neo-Hookean Hertz ball (hertz_coarse, graded towards its lowest point, dt = 0.2) on the flat,
# the incline's slope given by tilting g (f = g (sin theta, 0, -cos theta)) so that the ball presses the mesh's fine
# pole. Its closed forms are the rigid body's of the mesh's own volume, inertia I and height h of the centre of mass
# (k = I / (m h^2): 0.397 on hertz_coarse, 2/5 for a sphere): rolling at g sin theta / (1 + k) when
# tan theta <= F (1 + k) / k, else sliding with the spin F g cos theta m h / I; the skidding launch rolls from
# t* = v0 k / ((1 + k) F g) at v0 / (1 + k), friction having taken k / (1 + k) of the kinetic energy; on a belt at V
# it rolls from t* = V k / ((1 + k) F g) at V k / (1 + k).
SPHERE_MASS, SPHERE_INERTIA, SPHERE_H = ball_of_mesh(HERTZ)
SPHERE_K = SPHERE_INERTIA / (SPHERE_MASS * SPHERE_H**2)
SPHERE_SLOPES = {"sphere rolls": (10.0, 0.5), "sphere slides": (30.0, 0.1),
                 "sphere at the threshold": (math.degrees(math.atan(0.2 * (1 + SPHERE_K) / SPHERE_K)), 0.2)}
SPHERE_ARGS = ["-mesh", HERTZ, "-dt", "0.2", "-initial", "static", "-friction", "coulomb", "-material", "neohookean",
               "-lambda", "3000", "-mu", "3000", "-T", "10", "-snapshots", "none", "-progress", "0"]
SPHERES = {
    **{case: ("ball", SPHERE_ARGS + ["-friction_coefficient", str(F), "-fx", repr(G * math.sin(math.radians(theta))),
                                     "-fz", repr(-G * math.cos(math.radians(theta)))])
       for case, (theta, F) in SPHERE_SLOPES.items()},
    "sphere skidding launch": ("ball", SPHERE_ARGS + ["-friction_coefficient", "0.3", "-v0x", str(V0)]),
    "sphere belt": ("ball", SPHERE_ARGS + ["-friction_coefficient", "0.3", "-belt_speed", str(V0)]),
}
# Below gross slip: the oblique ball at normalised incidences Psi1 = c V_t1 / (F V_n1) (c = 2 (1 - nu) / (2 - nu),
# nu = 1/4 at lambda = mu) against Maw, Barber and Fawcett's theory (postprocess/oblique_theory.py)
OBLIQUE_NU, OBLIQUE_VN, OBLIQUE_F = 0.25, 0.0125, 0.3
OBLIQUE_C = 2 * (1 - OBLIQUE_NU) / (2 - OBLIQUE_NU)
OBLIQUE_PSI1 = [0.5, 1, 2, 3, 4, 5, 6, 8]
OBLIQUES = {f"oblique ball Psi1 = {p:g}": ("oblique_ball", BALL[1] + ["-v0x", repr(p * OBLIQUE_F * OBLIQUE_VN / OBLIQUE_C)])
            for p in OBLIQUE_PSI1}
RUNS = [(case, body) for case in CASES for body in BODIES] + [("oblique ball", "linear")] + \
    [(case, "stiff Neo-Hookean") for case in SPHERES] + [(case, "linear") for case in OBLIQUES]


def parabola(t, y):
    """The second derivative of the least-squares parabola through (t, y): an acceleration that the body's rocking
    on its elastic contact, released at t = 0, disturbs less than a straight line through the velocity does."""
    return np.polyfit(t, y, 2)[0] * 2


def turned(h, column):
    """The angle turned so far, from the angular velocity (trapezoids)."""
    w = h[column]
    return np.concatenate([[0], np.cumsum(0.5 * (w[1:] + w[:-1]) * np.diff(h["t"]))])


def rigid_slope(theta, F, k, lever):
    """The rigid body's acceleration along a slope theta (degrees) and its angular acceleration, k = I / (m lever^2),
    lever the height of its centre of mass above the contact point: it rolls at g sin theta / (1 + k) where
    tan theta <= F (1 + k) / k (a disk: 3 F, 2/3 g sin theta; a sphere: 7/2 F, 5/7 g sin theta), else slides at
    g (sin theta - F cos theta) with the spin F g cos theta / (k lever)."""
    th = math.radians(theta)
    if math.tan(th) <= F * (1 + k) / k * (1 + 1e-9):
        a = G * math.sin(th) / (1 + k)
        return a, a / lever
    return G * (math.sin(th) - F * math.cos(th)), F * G * math.cos(th) / (k * lever)


def slope_rows(h, theta, F, k, lever, along, spin):
    """(acceleration along the slope, angular acceleration) of the parabolas through the centre's displacement along
    the slope (along) and the angle turned (spin: the angular velocity's column), and the closed form's."""
    a, alpha = rigid_slope(theta, F, k, lever)
    return [("acceleration along the slope", parabola(h["t"], along), a),
            ("angular acceleration", parabola(h["t"], turned(h, spin)), alpha)]


def launch_rows(h, v_contact, k, belt):
    """The skidding launch (v0 = V0, F = 0.3) or the belt (V = V0) of a rigid body with k = I / (m lever^2), from the
    contact point's velocity relative to the foundation: it rolls from t* = V0 k / ((1 + k) F g), at V0 / (1 + k)
    (friction having taken k / (1 + k) of the kinetic energy), or on the belt at V0 k / (1 + k)."""
    t_star, v = rolling_from(h, v_contact)
    rows = [("t* (rolling from)", t_star, V0 * k / ((1 + k) * 0.3 * G))]
    if belt:
        return rows + [("v1 at t*", v, V0 * k / (1 + k))]
    mass = np.median(np.diff(h["t"])[1:] * h["contact_force_x"][2:] / np.diff(h["v1_mean"])[1:])
    work = np.interp(t_star, h["t"], h["friction_work"])
    return rows + [("v1 at t*", v, V0 / (1 + k)),
                   ("friction's work at t* / initial kinetic energy", work / (0.5 * mass * V0**2), k / (1 + k))]


def sphere_rows(case, h):
    """The sphere's rows against the rigid body of the mesh (its contact point below the centre, its spin about X2)."""
    if case in ("sphere skidding launch", "sphere belt"):
        belt = case == "sphere belt"
        return launch_rows(h, h["v1_mean"] - SPHERE_H * h["angular_velocity_2"] - (V0 if belt else 0), SPHERE_K, belt)
    theta, F = SPHERE_SLOPES[case]
    rows = slope_rows(h, theta, F, SPHERE_K, SPHERE_H, h["u1_mean"], "angular_velocity_2")
    return rows[:1] if case == "sphere at the threshold" else rows


def disk_along(h, theta):
    """The disk's centre's displacement down the slope theta (degrees)."""
    th = math.radians(theta)
    return -(h["u1_mean"] * math.cos(th) + h["u2_mean"] * math.sin(th))


def rolling_from(h, v_contact):
    """When the contact point first moves with the foundation: the first zero of its velocity relative to it (the
    sign change after the first step, interpolated linearly), and v1 then."""
    start = np.sign(v_contact[1])
    k = int(np.argmax(np.sign(v_contact[1:]) != start)) + 1
    w = v_contact[k - 1] / (v_contact[k - 1] - v_contact[k])
    return h["t"][k - 1] + w * (h["t"][k] - h["t"][k - 1]), h["v1_mean"][k - 1] + w * (h["v1_mean"][k] - h["v1_mean"][k - 1])


def rows_of(case, h):
    """The case's rows: (quantity, this code, closed form)."""
    if case in SPHERES:
        return sphere_rows(case, h)
    if case in SLOPES:
        theta, F = SLOPES[case]
        rows = slope_rows(h, theta, F, DISK_K, R, disk_along(h, theta), "angular_velocity")
        return rows[:1] if case == "at the threshold" else rows
    if case in ("skidding launch", "belt"):     # (the disk turns counter-clockwise > 0: its contact point moves at v1 + R omega)
        belt = case == "belt"
        return launch_rows(h, h["v1_mean"] + R * h["angular_velocity"] - (V0 if belt else 0), DISK_K, belt)
    normal = h["contact_force_z"].sum()
    tangential = math.hypot(h["contact_force_x"].sum(), h["contact_force_y"].sum())
    e = h["v3_mean"][-1] / 0.0125
    return [("tangential impulse / normal impulse", tangential / normal, 0.3),
            ("spin after the impact", h["angular_velocity_2"][-1], 5 * 0.3 * (1 + e) * 0.0125 / (2 * R))]


def run_dir(out, case, body):
    return os.path.join(out, case.replace(" ", "_"), body.replace(" ", "_").replace("-", "_"))


def run_one(out, item):
    case, body = item
    if case in SPHERES or case in OBLIQUES:
        scene, args = SPHERES[case] if case in SPHERES else OBLIQUES[case]
    else:
        scene, args = BALL if case == "oblique ball" else (CASES[case][0], CASES[case][1] + BODIES[body])
    where = run_dir(out, case, body)
    p = run_driver(scene, where, args, log=where + ".log", cwd=ROOT)
    if p.returncode != 0:
        raise RuntimeError(f"make friction: {case} on the {body} body failed (exit {p.returncode}): {p.last_line}")
    return item, p.wall


def figure(out, runs):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 3, figsize=(12, 3.6), layout="constrained")
    for case, ax in (("incline slides", axes[0]), ("incline rolls", axes[1])):
        theta, F = SLOPES[case]
        th = math.radians(theta)
        a, alpha = rigid_slope(theta, F, DISK_K, R)
        for body, style in (("stiff Neo-Hookean", "-"), ("stiff linear", ":")):
            h = runs[case, body]
            ax.plot(h["t"], -(h["v1_mean"] * math.cos(th) + h["v2_mean"] * math.sin(th)), "C0" + style,
                    label=f"speed along the slope ({body.split()[1]})")
            ax.plot(h["t"], R * h["angular_velocity"], "C1" + style, label=f"R x spin ({body.split()[1]})")
        ax.plot(h["t"], a * h["t"], "k--", lw=1, label="rigid body")
        ax.plot(h["t"], R * alpha * h["t"], "k:", lw=1)
        ax.set(title=f"{case} ({theta:.0f} degrees, F = {F})", xlabel="t")
        ax.legend(fontsize=6)
    h, ax = runs["skidding launch", "stiff Neo-Hookean"], axes[2]
    t_star = V0 / (3 * 0.3 * G)
    ax.plot(h["t"], h["v1_mean"], label="v1")
    ax.plot(h["t"], -R * h["angular_velocity"], label="-R x spin")
    ax.plot(h["t"], np.where(h["t"] < t_star, V0 - 0.3 * G * h["t"], 2 * V0 / 3), "k--", lw=1, label="rigid body")
    ax.plot(h["t"], np.where(h["t"] < t_star, 2 * 0.3 * G * h["t"], 2 * V0 / 3), "k:", lw=1)
    ax.set(title="skidding launch (F = 0.3, stiff Neo-Hookean)", xlabel="t")
    ax.legend(fontsize=7)
    for ext in ("png", "pdf"):
        fig.savefig(os.path.join(out, f"friction.{ext}"), dpi=110)


def oblique_sweep(out, runs):
    """The oblique impacts below and above gross slip against Maw, Barber and Fawcett's theory: the normalised
    rebound Psi2 = c V_t2 / (F V_n1) and the spin over the rigid ball's in gross slip, omega_gs = F (1 + e) V_n1 / (k h),
    each run's e its own; the contact point's tangential velocity is v1 - h omega_2. Writes OUT/oblique.csv and
    OUT/friction_oblique.png/.pdf; returns the summary's table."""
    nu, k, h = OBLIQUE_NU, SPHERE_K, SPHERE_H
    rows = []
    for p1 in OBLIQUE_PSI1:
        hist = runs[f"oblique ball Psi1 = {p1:g}", "linear"]
        e = hist["v3_mean"][-1] / OBLIQUE_VN
        vt2 = hist["v1_mean"][-1] - h * hist["angular_velocity_2"][-1]
        spin = hist["angular_velocity_2"][-1] * k * h / (OBLIQUE_F * (1 + e) * OBLIQUE_VN)
        rows.append((p1, OBLIQUE_C * vt2 / (OBLIQUE_F * OBLIQUE_VN), spin, e))
    psi1 = np.array([r[0] for r in rows])
    psi2_theory, spin_theory = oblique_theory.rebound(psi1, nu, k)
    gross = oblique_theory.gross_slip(psi1, nu, k, np.array([r[3] for r in rows]))
    csv = ["psi1,psi2,psi2_theory,psi2_gross_slip,spin_ratio,spin_ratio_theory,normal_restitution"]
    lines = ["| Psi1 | Psi2 | Psi2, theory | Psi2, rigid gross slip | spin / gross slip's | theory | e |",
             "| ---: | ---: | ---: | ---: | ---: | ---: | ---: |"]
    for (p1, p2, spin, e), t2, g2, ts in zip(rows, psi2_theory, gross, spin_theory):
        csv.append(f"{p1:g},{p2:.6g},{t2:.6g},{g2:.6g},{spin:.6g},{ts:.6g},{e:.6g}")
        lines.append(f"| {p1:g} | {p2:.3f} | {t2:.3f} | {g2:.3f} | {spin:.3f} | {ts:.3f} | {e:.4f} |")
    with open(os.path.join(out, "oblique.csv"), "w") as f:
        f.write("\n".join(csv) + "\n")
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fine = np.linspace(0.1, max(OBLIQUE_PSI1), 80)
    fine2, fine_spin = oblique_theory.rebound(fine, nu, k)
    fig, axes = plt.subplots(1, 2, figsize=(9, 3.6), layout="constrained")
    axes[0].plot(fine, fine2, "k-", lw=1, label="Maw, Barber and Fawcett's model (MDR)")
    axes[0].plot(fine, oblique_theory.gross_slip(fine, nu, k, 1.0), "k:", lw=1, label="rigid ball, gross slip (e = 1)")
    axes[0].plot(psi1, [r[1] for r in rows], "o", label="this code (linear Hertz ball)")
    axes[0].set(xlabel="Psi1 = c V_t1 / (F V_n1)", ylabel="Psi2 = c V_t2 / (F V_n1)")
    axes[1].plot(fine, fine_spin, "k-", lw=1, label="model (MDR)")
    axes[1].plot(psi1, [r[2] for r in rows], "o", label="this code")
    axes[1].set(xlabel="Psi1", ylabel="spin / rigid gross slip's")
    for ax in axes:
        ax.legend(fontsize=7)
    for ext in ("png", "pdf"):
        fig.savefig(os.path.join(out, f"friction_oblique.{ext}"), dpi=110)
    return "\n".join(lines)


def main():
    ap = jobs.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", default="results/friction")
    ap.add_argument("--jobs", type=jobs.positive_int, default=2)
    a = ap.parse_args()
    out = os.path.abspath(a.out)
    os.makedirs(out, exist_ok=True)
    jobs.stop_on_interrupt("make friction", out, ["summary.md", "friction.csv", "*.png", "*.pdf"])
    try:
        for (case, body), seconds in jobs.run_parallel(lambda item: run_one(out, item), RUNS, a.jobs):
            print(f"friction {case} ({body}): {seconds:.0f} s", flush=True)
    except RuntimeError as e:
        sys.exit(f"error: {e}")
    runs = {item: read_run(run_dir(out, *item)) for item in RUNS}
    names = list(BODIES)
    lines = ["| case | quantity | rigid body | " + " | ".join(names) + " |", "| --- | --- | ---: |" + " ---: |" * len(names)]
    csv = ["case,body,quantity,this_code,rigid_body,difference"]
    for case in list(CASES) + list(SPHERES) + ["oblique ball"]:
        bodies = ["linear"] if case == "oblique ball" else (["stiff Neo-Hookean"] if case in SPHERES else names)
        table = {body: rows_of(case, runs[case, body]) for body in bodies}
        for k, (what, _, want) in enumerate(table[bodies[0]]):
            cells = []
            for body in names:
                if body not in table:
                    cells.append("")
                    continue
                got = table[body][k][1]
                cells.append(f"{got:.6g} ({100 * (got / want - 1):+.2f}%)")
                csv.append(f"{case},{body},{what},{got:.9g},{want:.9g},{got / want - 1:.6g}")
            if case == "oblique ball":
                got = table["linear"][k][1]
                csv.append(f"{case},linear,{what},{got:.9g},{want:.9g},{got / want - 1:.6g}")
                cells = [f"{got:.6g} ({100 * (got / want - 1):+.2f}%), the linear Hertz ball", "", ""]
            lines.append(f"| {case} | {what} | {want:.6g} | " + " | ".join(cells) + " |")
    text = "\n".join(lines) + "\n\nThe oblique ball below and above gross slip (oblique.csv):\n\n" + oblique_sweep(out, runs)
    with open(os.path.join(out, "summary.md"), "w") as f:
        f.write(text + "\n")
    with open(os.path.join(out, "friction.csv"), "w") as f:
        f.write("\n".join(csv) + "\n")
    figure(out, runs)
    print(text)
    print(f"friction: {os.path.join(a.out, 'summary.md')}")


if __name__ == "__main__":
    main()
