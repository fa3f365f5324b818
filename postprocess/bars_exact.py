"""The longitudinal impact of two elastic bars, exactly (d'Alembert; Carpenter, Taylor and Katona 1991;
Laursen and Chawla 1997): the closed form the bodies-against-bodies benchmarks compare with.

Two bars of one material and one height h, lengths L1 <= L2, end to end and touching at t = 0 with velocities
v1 > v2 (they approach at dv = v1 - v2). With lambda = 0 a plane bar is one-dimensional (Poisson's ratio 0, so
sigma_yy = lambda eps_xx = 0): its modulus is 2 mu and its wave speed c = sqrt(2 mu / rho). At the impact each
bar's end takes the common velocity (v1 + v2)/2 and a compressive wave of stress rho c dv / 2 runs into each bar.
The short bar's wave returns to the contact after 2 L1 / c as a release wave that brings its end's velocity below
the long bar's: the bars part then, the short one with velocity v2 everywhere and no strain (its whole momentum
m1 dv passed to the long one). While in contact the force is constant:

    F = h rho c dv / 2                      for 0 < t < 2 L1 / c

Equal bars (L1 = L2) exchange their velocities and both leave unstrained; with L2 = 2 L1 and v2 = 0 the short
bar is at rest after 2 L1 / c and the long one carries all the momentum, its mean velocity v1 / 2.
"""
import math


def wave_speed(mu, rho, lam=0.0):
    """c of a plane bar. Only lambda = 0 makes the bar one-dimensional (no lateral stress); then c = sqrt(2 mu/rho)."""
    if lam != 0:
        raise ValueError("the closed form needs lambda = 0 (Poisson's ratio 0): the bar is then one-dimensional")
    if mu <= 0 or rho <= 0:
        raise ValueError("mu and rho must be positive")
    return math.sqrt(2 * mu / rho)


def impact(lengths, velocities, mu, rho, height=1.0):
    """The exact impact of two bars (lengths (L1, L2), velocities (v1, v2) along the line from bar 1 to bar 2,
    v1 > v2): a dict with the contact's start and end times, its constant force, each bar's mean velocity after
    the bars part, and their total momentum and kinetic energy before and after (per unit thickness)."""
    (l1, l2), (v1, v2) = lengths, velocities
    if min(l1, l2) <= 0:
        raise ValueError("the lengths must be positive")
    if v1 <= v2:
        raise ValueError("the bars must approach each other (v1 > v2)")
    c = wave_speed(mu, rho)
    dv = v1 - v2
    short, duration = (0, 2 * l1 / c) if l1 <= l2 else (1, 2 * l2 / c)
    m = (rho * height * l1, rho * height * l2)
    force = height * rho * c * dv / 2
    impulse = force * duration                     # = m_short dv
    after = (v1 - impulse / m[0], v2 + impulse / m[1])
    momentum = m[0] * v1 + m[1] * v2
    return {
        "wave_speed": c,
        "contact_start": 0.0,
        "contact_end": duration,
        "contact_duration": duration,
        "contact_force": force,
        "short_bar": short + 1,
        "mean_velocity_after": after,
        "momentum": momentum,
        "momentum_after": m[0] * after[0] + m[1] * after[1],
        "kinetic_energy_before": 0.5 * (m[0] * v1 ** 2 + m[1] * v2 ** 2),
        # after: the short bar rigid, unstrained; the long one's energy (rigid motion and wave) is the rest
        "short_bar_energy_after": 0.5 * m[short] * after[short] ** 2,
    }


if __name__ == "__main__":
    import argparse
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--lengths", default="10,10", help="L1,L2")
    ap.add_argument("--velocities", default="0.01,-0.01", help="v1,v2 (v1 > v2)")
    ap.add_argument("--mu", type=float, default=50.0)
    ap.add_argument("--rho", type=float, default=1.0)
    ap.add_argument("--height", type=float, default=1.0)
    a = ap.parse_args()
    try:
        result = impact(tuple(float(x) for x in a.lengths.split(",")), tuple(float(x) for x in a.velocities.split(",")),
                        a.mu, a.rho, a.height)
    except ValueError as e:
        raise SystemExit(f"bars_exact.py: {e}")
    for key, value in result.items():
        print(f"{key}: {value}")
