"""The oblique impact of an elastic sphere on a rigid flat with Coulomb friction: the theory of Maw, Barber and
Fawcett (Wear 38 (1976) 101), against which make friction's 3D oblique impacts are plotted (docs/friction.md).

Its model: Hertz's normal contact; Coulomb's law point by point, |q| <= F p; the tangential traction does not change
the pressure; the sphere a rigid body outside the contact. It is solved here by Popov's method of dimensionality
reduction (MDR; Lyashenko and Popov, Sci. Rep. 5 (2015) 8479, reproduce Maw, Barber and Fawcett's curves with it):
the contact is a row of independent springs at x along a line, with the profile g(x) = x^2 / R, normal stiffness
E* dx and tangential stiffness G* dx, E* = E / (1 - nu^2), G* = 4 G / (2 - nu) (a rigid flat), so that
k_t / k_n = 2 (1 - nu) / (2 - nu). A spring in contact (|x| < a, a = sqrt(R d) at the indentation d) carries
f_n = E* dx (d - x^2 / R); it sticks, its tangential deflection following the contact point's tangential
displacement, until G* dx |w| reaches F f_n, where it slips; a spring that leaves the contact is unloaded. The
normal force is Hertz's 4/3 E* sqrt(R) d^(3/2) exactly.

The normalised angles are theirs: Psi1 = c V_t1 / (F V_n1), Psi2 = c V_t2 / (F V_n1), c = 2 (1 - nu) / (2 - nu),
V_t the tangential velocity of the contact point (v_t - h omega, h its distance from the centre of mass), V_n1 the
normal speed of approach. A rigid ball that slides throughout leaves at Psi2 = Psi1 - 2 chi (1 + e),
chi = (1 - nu) / (2 - nu) (1 + 1 / k), k = I / (m h^2) (2/5 for a sphere); its spin is then
omega_gs = F (1 + e) V_n1 / (k h), and the model's spin is given as omega / omega_gs.
"""
import math

import numpy as np


def rebound(psi1, nu, k, springs=1500, steps=6000):
    """The model's rebound for each normalised incidence psi1 (an array): (Psi2, omega / omega_gs), in the units where
    F = V_n1 = h = R = m = 1 and E* = 1 (the normalised results depend only on nu and k)."""
    psi1 = np.atleast_1d(np.asarray(psi1, dtype=float))
    c = 2 * (1 - nu) / (2 - nu)
    estar, gstar = 1.0, c                       # (G* / E* = c)
    # Hertz's impact at unit speed: the largest indentation and the contact time, to size the grid and the step
    d_max = (15 / 16 / estar) ** 0.4
    t_c = 2.943 * d_max
    x = (np.arange(springs) + 0.5) * (1.05 * math.sqrt(d_max) / springs)   # the half line (symmetric in x)
    dx = x[1] - x[0]
    dt = t_c / steps
    out_psi2, out_spin = [], []
    for p1 in psi1:
        vt = p1 / c                           # V_t1 = psi1 F V_n1 / c, no spin
        d, vn, omega, w = 0.0, 1.0, 0.0, np.zeros(springs)
        fn_springs = estar * dx * np.maximum(0.0, d - x * x)     # (then the last step's, at the same d)
        started = False
        while True:
            # the springs' forces at (d, w), then a velocity Verlet step of d and a mid-point one of the slip
            contact = fn_springs > 0
            w[~contact] = 0.0
            limit = fn_springs / (gstar * dx)           # (F = 1)
            np.clip(w, -limit, limit, out=w)
            fn, ft = 2 * fn_springs.sum(), 2 * gstar * dx * w.sum()
            vn_half = vn - 0.5 * dt * fn
            d += dt * vn_half
            slip_velocity = vt - omega                 # V_t = v_t - h omega
            w += dt * slip_velocity
            vt -= dt * ft
            omega += dt * ft / k
            fn_springs = estar * dx * np.maximum(0.0, d - x * x)
            vn = vn_half - 0.5 * dt * 2 * fn_springs.sum()
            started = started or d > 0
            if started and d <= 0:
                break
        e = -vn
        out_psi2.append(c * (vt - omega))
        out_spin.append(omega * k / (1 + e))
    return np.array(out_psi2), np.array(out_spin)


def gross_slip(psi1, nu, k, e):
    """The rigid body sliding throughout: Psi2 = Psi1 - 2 chi (1 + e), and omega / omega_gs = 1."""
    chi = (1 - nu) / (2 - nu) * (1 + 1 / k)
    return np.asarray(psi1) - 2 * chi * (1 + e)
