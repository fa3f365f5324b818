"""Short physics tests of the scenes beyond the paper (edp/scenes)."""
import numpy as np
import pytest

G = 0.1          # |f| / rho of the scenes


def test_freeflight_conserves_the_modified_energy_to_roundoff(histories):
    h = histories["freeflight"]
    assert h["qp_solved"].sum() == 0
    m = h["modified_energy"]
    assert np.abs(m - m[0]).max() <= 1e-10 * abs(m[0])
    assert np.abs(h["v1_mean"] - 0.3).max() < 1e-12            # no horizontal force


@pytest.mark.parametrize("name", ["incline", "svk_incline"])
def test_incline_slides_with_g_sin_theta(histories, name):
    # frictionless: the contact force is normal to the plane, so the mean velocity
    # along the slope (cos, sin) is -g sin(theta) t exactly, up to the solver tolerance
    # (for both materials: the internal forces sum to zero)
    h = histories[name]
    th = np.radians(10)
    along = h["v1_mean"] * np.cos(th) + h["v2_mean"] * np.sin(th)
    assert np.abs(along + G * np.sin(th) * h["t"]).max() < 1e-6
    assert h["max_penetration"].max() <= 1e-8 and (h["active_nodes"][1:] > 0).any()


@pytest.mark.parametrize("name", ["oblique", "svk_oblique"])
def test_oblique_impact_conserves_horizontal_momentum(histories, name):
    h = histories[name]
    assert (h["active_nodes"] > 0).any()
    assert np.abs(h["v1_mean"] - 0.5).max() < 1e-6
    assert h["max_penetration"].max() <= 1e-8


def test_bump_user_foundation_pushes_the_disk_aside(histories):
    """A user-written fixed psi: the disk lands left of the bump's peak and is pushed to -x;
    with a fixed foundation, u^n is in K^{n+1}, so the modified energy never increases."""
    h = histories["bump"]
    assert h["v1_mean"][-1] < -0.05
    m = h["modified_energy"]
    assert np.diff(m).max() <= 1e-8 * abs(m[0])
    assert h["max_penetration"].max() <= 1e-8


@pytest.mark.parametrize("name", ["rising", "wave", "bump"])
def test_moving_foundations_stay_stable(histories, name):
    h = histories[name]
    assert np.isfinite(np.column_stack(list(h.values()))).all()
    assert h["max_penetration"].max() <= 1e-8 and h["contact_pressure_low"].min() >= 0
    assert (h["active_nodes"] > 0).any()


def test_rising_foundation_adds_energy(histories):
    """Outside Prop. 2 (u^n is not in K^{n+1}): the rising foundation does work on the
    body, so the modified energy grows. This records it and does not hide it."""
    m = histories["rising"]["modified_energy"]
    print(f"rising: modified energy {m[0]:.2f} -> {m[-1]:.2f}, largest one-step gain {np.diff(m).max():.3f}")
    assert m[-1] > m[0]
