"""The rigid-balls-and-Hertz-springs model of postprocess/cradle_ode.py (the reference of the cradle benchmark)
and the two-ball Hertz values of postprocess/hertz_analysis.py, checked against what they must give. Fast, no
FreeFEM."""
import numpy as np
import pytest

import cradle_ode
import hertz_analysis

V0 = 1e-3


def test_two_balls_exchange_their_velocities_in_hertzs_contact_time():
    """Two equal balls head-on (one at rest): Hertz's impact of R* = R/2, E* = E/(2(1 - nu^2)), m* = m/2 at the
    approach speed; the model's contact lasts T_H = 2.943 delta*/V within 0.1%, and the balls exchange their
    velocities (an elastic impact of equal masses) within 1e-6 v0."""
    pair = hertz_analysis.hertz_two_balls(V0 / 2)
    assert pair["v0"] == pytest.approx(V0)
    result = cradle_ode.strike([V0, 0.0], [pair["m"]] * 2, pair["K"])
    touching = result["t"][result["overlaps"][:, 0] > 0]
    assert touching[-1] - touching[0] == pytest.approx(pair["T_H"], rel=1e-3)
    assert result["velocities"] == pytest.approx([0.0, V0], abs=1e-6 * V0)
    peak = hertz_analysis.hertz_two_balls(V0 / 2)["delta_star"]
    assert result["overlaps"][:, 0].max() == pytest.approx(peak, rel=1e-4)


def test_the_pair_is_the_single_ball_on_a_flat_with_its_effective_values():
    """hertz_two_balls at +-v0 is hertz() of the ball of radius R/2, E*/2 and mass m/2 at 2 v0: the same K, delta*,
    F* (E* halves, R* halves: K = 4/3 E* sqrt(R*) is the single ball's over 2^(3/2))."""
    pair, one = hertz_analysis.hertz_two_balls(V0), hertz_analysis.hertz(V0)
    assert pair["K"] == pytest.approx(one["K"] / 2 ** 1.5)
    assert pair["delta_star"] == pytest.approx((15 * one["m"] / 2 * (2 * V0) ** 2 / (16 * one["E_star"] / 2
                                                * np.sqrt(one["R"] / 2))) ** 0.4)


def test_a_struck_row_of_three_conserves_momentum_and_energy():
    """Three equal balls, the first struck: the model conserves momentum to 1e-12 and energy to 1e-8 (Runge-Kutta's
    error), the row parts for good, and the last ball leaves with most of the momentum; the first two keep a small
    part (the Hertz row is not a rigid cradle)."""
    pair = hertz_analysis.hertz_two_balls(V0 / 2)
    result = cradle_ode.strike([V0, 0.0, 0.0], [pair["m"]] * 3, pair["K"])
    scale = pair["m"] * V0
    assert np.max(np.abs(result["momentum"] - result["momentum"][0])) <= 1e-12 * scale
    assert np.max(np.abs(result["energy"] / result["energy"][0] - 1)) <= 1e-8
    v = result["velocities"]
    assert np.all(np.diff(v) >= 0) and v[2] > 0.9 * V0 and abs(v[0]) + abs(v[1]) > 1e-4 * V0
