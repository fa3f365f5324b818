"""The two bars' closed form of postprocess/bars_exact.py (the bodies-against-bodies benchmark), checked against
an independent computation: two lumped-mass chains, central differences at the 1D wave's "magic" step dt = dx/c
(exact for the wave equation at the nodes) and Carpenter, Taylor and Katona's forward-increment Lagrange
multiplier for the contact of their ends. Fast, no FreeFEM."""
import numpy as np
import pytest

import bars_exact

MU, RHO, HEIGHT = 50.0, 1.0, 1.0


def chains(lengths, velocities, elements_per_unit=8):
    """The two chains' impact: (times, contact forces, each bar's mean velocity at the end, total momentum at
    every step). dx = 1/elements_per_unit, dt = dx/c."""
    c = bars_exact.wave_speed(MU, RHO)
    dx = 1.0 / elements_per_unit
    dt = dx / c
    k = 2 * MU * HEIGHT / dx
    bars = []
    for length, v in zip(lengths, velocities):
        n = int(round(length / dx))
        m = np.full(n + 1, RHO * HEIGHT * dx)
        m[[0, -1]] /= 2
        bars.append({"u": np.zeros(n + 1), "v": np.full(n + 1, float(v)), "m": m})
    times, forces, momenta = [], [], []
    duration = 2 * min(lengths) / c
    steps = int(round(2.5 * duration / dt))
    for n in range(steps):
        for b in bars:                      # v^{n+1/2}, then the predicted u^{n+1}
            strain = np.diff(b["u"]) / dx
            f = np.zeros_like(b["u"])
            f[:-1] += k * dx * strain
            f[1:] -= k * dx * strain
            b["v"] += dt * f / b["m"]
            b["u"] += dt * b["v"]
        left, right = bars[0], bars[1]
        gap = right["u"][0] - left["u"][-1]          # (the bars touch at t = 0: the gap is the ends' displacement)
        force = 0.0
        if gap < 0:                                   # the forward-increment multiplier closes the gap exactly
            inv = 1 / left["m"][-1] + 1 / right["m"][0]
            force = -gap / (dt * dt * inv)
            left["v"][-1] -= dt * force / left["m"][-1]
            left["u"][-1] -= dt * dt * force / left["m"][-1]
            right["v"][0] += dt * force / right["m"][0]
            right["u"][0] += dt * dt * force / right["m"][0]
        times.append((n + 1) * dt)
        forces.append(force)
        momenta.append(sum(float(b["m"] @ b["v"]) for b in bars))
    means = tuple(float(b["m"] @ b["v"] / b["m"].sum()) for b in bars)
    return np.array(times), np.array(forces), means, np.array(momenta), dt


@pytest.mark.parametrize("lengths,velocities", [((10, 10), (0.01, -0.01)), ((10, 20), (0.01, 0.0)),
                                                 ((5, 8), (0.02, 0.005))])
def test_the_closed_form_is_the_chains_exact_impact(lengths, velocities):
    """Contact lasts 2 L_short / c, its force is h rho c dv / 2 throughout, the short bar leaves with the long
    one's initial velocity, momentum is conserved: the closed form against the chains, to the step dt and 1%."""
    exact = bars_exact.impact(lengths, velocities, MU, RHO, HEIGHT)
    t, f, means, momenta, dt = chains(lengths, velocities)
    touching = t[f > 1e-6 * exact["contact_force"]]     # (after it the ends move together, at v2: round-off's touches)
    assert abs(touching[-1] - exact["contact_end"]) <= 2 * dt
    steady = f[(t > 0.1 * exact["contact_end"]) & (t < 0.9 * exact["contact_end"])]
    assert np.allclose(steady, exact["contact_force"], rtol=1e-2)
    assert means == pytest.approx(exact["mean_velocity_after"], rel=1e-2, abs=1e-2 * max(map(abs, velocities)))
    assert np.allclose(momenta, exact["momentum"], rtol=1e-12)
    assert exact["momentum_after"] == pytest.approx(exact["momentum"], rel=1e-14)


def test_the_issues_cases():
    """Equal bars at +-v0: contact lasts 2L/c with force rho c v0 h, and they leave with their velocities reversed;
    bars L and 2L, the short one striking the long one at rest: the short one ends at rest, the long one carries
    all the momentum (mean velocity v0/2)."""
    c = np.sqrt(2 * MU / RHO)
    equal = bars_exact.impact((10, 10), (0.01, -0.01), MU, RHO, HEIGHT)
    assert equal["contact_duration"] == pytest.approx(20 / c)
    assert equal["contact_force"] == pytest.approx(RHO * c * 0.01 * HEIGHT)
    assert equal["mean_velocity_after"] == pytest.approx((-0.01, 0.01))
    unequal = bars_exact.impact((10, 20), (0.01, 0.0), MU, RHO, HEIGHT)
    assert unequal["mean_velocity_after"] == pytest.approx((0.0, 0.005), abs=1e-15)


@pytest.mark.parametrize("kwargs,message", [({"lam": 1.0}, "lambda = 0"), ({"mu": -1.0}, "positive")])
def test_refusals(kwargs, message):
    """The closed form holds for a one-dimensional bar only: lambda != 0 is refused, and so is a bad modulus."""
    with pytest.raises(ValueError, match=message):
        bars_exact.wave_speed(kwargs.get("mu", MU), RHO, kwargs.get("lam", 0.0))
