"""Newton's cradle as rigid balls joined by Hertz springs: the model the cradle benchmark compares with
(Herrmann and Seitz 1982; Hinch and Saint-Jean 1999). Balls 1..N on a line, masses m_i, positions x_i (the gaps
between touching neighbours 0 at t = 0); neighbours i, i+1 push each other with the force K delta^p while their
overlap delta = x_i - x_{i+1} (+ the initial gap) is positive, nothing otherwise (p = 3/2: Hertz's law of two
balls, K = 4/3 E* sqrt(R*) with R* = R/2 and E* = E/(2 (1 - nu^2)): hertz_analysis.hertz_two_balls()).
Integrated by the classical Runge-Kutta method with a step far below the contact time; its total momentum is
conserved to round-off and its energy to the step's order."""
import numpy as np

import hertz_analysis


def forces(x, masses, stiffness, exponent):
    """The accelerations of the balls at positions x (displacements from the touching start)."""
    overlap = np.maximum(x[:-1] - x[1:], 0.0)
    push = stiffness * overlap ** exponent
    f = np.zeros_like(x)
    f[:-1] -= push
    f[1:] += push
    return f / masses


def energy(x, v, masses, stiffness, exponent):
    """Kinetic energy plus the springs' K delta^(p+1)/(p+1)."""
    overlap = np.maximum(x[:-1] - x[1:], 0.0)
    return 0.5 * float(masses @ v ** 2) + float(np.sum(stiffness * overlap ** (exponent + 1) / (exponent + 1)))


def strike(velocities, masses, stiffness, exponent=1.5, horizon=None, steps_per_contact=4000):
    """The balls (initial velocities and masses, touching at t = 0) until every pair has parted for good (or t =
    horizon): a dict with the final velocities, the times and overlaps of every pair, the momentum and energy at
    every step, and the step dt. The step is the two-ball contact time's 1/steps_per_contact at the largest
    relative speed."""
    v = np.array(velocities, dtype=float)
    m = np.array(masses, dtype=float)
    x = np.zeros_like(v)
    speed = max(np.max(np.abs(np.diff(v))), 1e-300)
    m_pair = np.min(m) / 2
    # the largest overlap of two balls at that speed, m* V^2/2 = K delta^(p+1)/(p+1), and their contact time
    # (Hertz's T = 2.943 delta*/V for p = 3/2; the step's scale otherwise)
    delta = (m_pair * speed ** 2 * (exponent + 1) / (2 * stiffness)) ** (1 / (exponent + 1))
    contact_time = hertz_analysis.CONTACT_TIME_CONSTANT * delta / speed
    dt = contact_time / steps_per_contact
    horizon = horizon if horizon is not None else 20 * len(v) * contact_time
    times, overlaps, momenta, energies = [0.0], [np.maximum(x[:-1] - x[1:], 0.0)], [float(m @ v)], \
        [energy(x, v, m, stiffness, exponent)]
    t = 0.0
    while t < horizon:
        k1x, k1v = v, forces(x, m, stiffness, exponent)
        k2x, k2v = v + 0.5 * dt * k1v, forces(x + 0.5 * dt * k1x, m, stiffness, exponent)
        k3x, k3v = v + 0.5 * dt * k2v, forces(x + 0.5 * dt * k2x, m, stiffness, exponent)
        k4x, k4v = v + dt * k3v, forces(x + dt * k3x, m, stiffness, exponent)
        x = x + dt / 6 * (k1x + 2 * k2x + 2 * k3x + k4x)
        v = v + dt / 6 * (k1v + 2 * k2v + 2 * k3v + k4v)
        t += dt
        overlap = np.maximum(x[:-1] - x[1:], 0.0)
        times.append(t)
        overlaps.append(overlap)
        momenta.append(float(m @ v))
        energies.append(energy(x, v, m, stiffness, exponent))
        # parted for good: no overlap, and every neighbour recedes from the one before it
        if not overlap.any() and np.all(np.diff(v) >= 0):
            break
    return {"velocities": v, "t": np.array(times), "overlaps": np.array(overlaps), "momentum": np.array(momenta),
            "energy": np.array(energies), "dt": dt, "contact_time": contact_time}


if __name__ == "__main__":
    import argparse
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--balls", type=int, default=3)
    ap.add_argument("--v0", type=float, default=1e-3, help="the first ball's speed toward the others")
    a = ap.parse_args()
    if a.balls < 2:
        raise SystemExit("cradle_ode.py: --balls must be at least 2")
    pair = hertz_analysis.hertz_two_balls(a.v0)
    result = strike([a.v0] + [0.0] * (a.balls - 1), [pair["m"]] * a.balls, pair["K"])
    print("final velocities / v0:", " ".join(f"{w / a.v0:.6f}" for w in result["velocities"]))
