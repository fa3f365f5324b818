"""Hertz's impact theory of postprocess/hertz_analysis.py (docs/hertz.md) and make hertz's
analysis, on exact Hertz histories: fast, no FreeFEM."""
import csv
import math
import os
import subprocess
import sys

import numpy as np
import pytest

from conftest import ROOT

import hertz_analysis

# the history.csv columns of the 3D driver (the agreed spec)
HEADER = ("step,t,u1_low,u2_low,u3_low,v3_low,contact_pressure_low,contact_force_z,contact_area,energy,modified_energy,"
          "active_nodes,max_penetration,qp_solved,solver_status,v1_mean,v2_mean,v3_mean,u3_mean,newton_iterations,"
          "angular_momentum_1,angular_momentum_2,angular_momentum_3,max_strain,max_penetration_outside,max_penetration_exact,"
          "max_held_off_exact,contact_force_x,contact_force_y").split(",")


def impact(ratio=1e-3):
    """Hertz's values at v0/c* = ratio for the scene's ball (lambda = mu = 30, rho = 1, R = 20)."""
    return hertz_analysis.hertz(ratio * hertz_analysis.wave_speed())


def test_material_and_formulas():
    """lambda = mu = 30 gives E = 75, nu = 0.25, E* = 80; delta* is where the elastic energy 2/5 K delta^(5/2)
    equals the kinetic m v0^2/2; F* = K delta*^(3/2), a*^2 = R delta*, m = 4/3 pi rho R^3."""
    h = impact()
    assert (h["E"], h["nu"], h["E_star"]) == pytest.approx((75, 0.25, 80), rel=1e-15)
    assert h["c_star"] == pytest.approx(math.sqrt(80), rel=1e-15)
    assert h["m"] == pytest.approx(4 / 3 * math.pi * 8000, rel=1e-15)
    assert 0.4 * h["K"] * h["delta_star"] ** 2.5 == pytest.approx(h["m"] * h["v0"] ** 2 / 2, rel=1e-12)
    assert h["F_star"] == pytest.approx(h["K"] * h["delta_star"] ** 1.5, rel=1e-15)
    assert h["a_star"] ** 2 == pytest.approx(h["R"] * h["delta_star"], rel=1e-14)


def test_contact_time_constant():
    """The ODE m delta'' = -K delta^(3/2) integrated by RK4 (in physical units, v0/c* = 1e-3) leaves the flat
    after 2.9433 delta*/v0 (to 1e-4 relative: Johnson's constant), which is 4/5 B(2/5, 1/2) = 2.943275 (to 1e-9)."""
    h = impact()
    t, delta, rate, contact = hertz_analysis.integrate_impact(h["m"], h["K"], h["v0"])
    constant = contact * h["v0"] / h["delta_star"]
    print(f"contact time from the ODE: {constant:.10f} delta*/v0")
    assert constant == pytest.approx(2.9433, rel=1e-4)
    assert constant == pytest.approx(hertz_analysis.CONTACT_TIME_CONSTANT, rel=1e-9)
    assert hertz_analysis.CONTACT_TIME_CONSTANT == pytest.approx(2.943275184, rel=1e-9)
    assert h["T_H"] == pytest.approx(contact, rel=1e-9)


def test_peak_force_and_approach():
    """Along the ODE's solution the largest approach is delta* and the largest force K delta^(3/2) is F*
    (to 1e-8), reached at half the contact time, when delta' = 0."""
    h = impact()
    t, delta, rate, contact = hertz_analysis.integrate_impact(h["m"], h["K"], h["v0"], steps=20000)
    k = int(np.argmax(delta))
    assert delta[k] == pytest.approx(h["delta_star"], rel=1e-8)
    assert h["K"] * delta[k] ** 1.5 == pytest.approx(h["F_star"], rel=1e-8)
    assert t[k] == pytest.approx(contact / 2, abs=2 * (t[1] - t[0]))
    assert abs(rate[k]) < 1e-3 * h["v0"]


def test_energy_conserved_along_the_curve():
    """m/2 delta'^2 + 2/5 K delta^(5/2) = m/2 v0^2 along hertz_curves() (the interpolated curve, at times
    between its grid points), to 1e-9 of m/2 v0^2; after the contact the ball leaves at v0."""
    h = impact(1e-2)
    t = np.linspace(0, 1.3 * h["T_H"], 1001)
    delta, rate, force = hertz_analysis.hertz_curves(t, h)
    energy = h["m"] / 2 * rate ** 2 + 0.4 * h["K"] * np.maximum(delta, 0) ** 2.5
    assert np.abs(energy / (h["m"] * h["v0"] ** 2 / 2) - 1).max() < 1e-9
    assert np.all(force[t > h["T_H"]] == 0) and np.allclose(rate[t > h["T_H"]], -h["v0"], rtol=1e-12)
    assert np.allclose(force, h["K"] * np.maximum(delta, 0) ** 1.5, rtol=1e-12)


def test_curve_is_the_ode_solution():
    """hertz_curves() (the unit solution scaled by delta*, delta*/v0) agrees with the ODE integrated directly in
    physical units at another speed, to 1e-8 of delta*."""
    h = impact(1e-4)
    t, delta, rate, contact = hertz_analysis.integrate_impact(h["m"], h["K"], h["v0"], steps=3000)
    inside = t <= contact
    curve = hertz_analysis.hertz_curves(t[inside], h)[0]
    assert np.abs(curve - delta[inside]).max() < 1e-8 * h["delta_star"]


def test_scaling_laws():
    """From the ODE alone, at v0 and 10 v0: the largest approach grows as v0^(4/5), the largest force as
    v0^(6/5) and the contact time as v0^(-1/5) (to 1e-6), as delta*, F* and T_H do."""
    slow, fast = impact(1e-4), impact(1e-3)
    (t1, d1, _, c1), (t2, d2, _, c2) = (hertz_analysis.integrate_impact(h["m"], h["K"], h["v0"], steps=20000) for h in (slow, fast))
    assert d2.max() / d1.max() == pytest.approx(10 ** 0.8, rel=1e-6)
    assert (d2.max() / d1.max()) ** 1.5 == pytest.approx(10 ** 1.2, rel=1e-6)
    assert c2 / c1 == pytest.approx(10 ** -0.2, rel=1e-6)
    assert fast["delta_star"] / slow["delta_star"] == pytest.approx(10 ** 0.8, rel=1e-12)
    assert fast["T_H"] / slow["T_H"] == pytest.approx(10 ** -0.2, rel=1e-12)
    assert fast["a_star"] / slow["a_star"] == pytest.approx(10 ** 0.4, rel=1e-12)


@pytest.mark.parametrize("steps_per_contact", hertz_analysis.STEPS_PER_CONTACT)
@pytest.mark.parametrize("ratio", hertz_analysis.RATIOS)
def test_analysis_of_an_exact_history(ratio, steps_per_contact):
    """measure() of Hertz's own impact, sampled on make hertz's time grid (dt = T_H/50, T_H/100 to 3 digits,
    T = 1.3 T_H), returns Hertz's values: contact time (F^(2/3) extrapolated at both ends), peak force and
    largest approach (parabola) to 1e-4, contact radius at the peak to 1e-3 (the peak's step, not the peak),
    restitution 1, energy lost 0 and the mesh's mass m."""
    h = impact(ratio)
    dt, steps = hertz_analysis.time_grid(h, steps_per_contact)
    assert abs(dt * steps_per_contact / h["T_H"] - 1) < 0.01 and steps * dt > 1.25 * h["T_H"]
    m = hertz_analysis.measure(hertz_analysis.exact_history(h, dt, steps), h)
    r = hertz_analysis.relative(m, h)
    print({k: f"{v:.2e}" for k, v in r.items()})
    assert m["left"]
    assert abs(r["contact_time"]) < 1e-4 and abs(r["peak_force"]) < 1e-4 and abs(r["max_approach"]) < 1e-4
    assert abs(r["contact_radius"]) < 1e-3
    assert m["restitution"] == pytest.approx(1, abs=1e-9) and m["energy_lost"] == 0 and m["mass_ratio"] == pytest.approx(1)


def test_analysis_of_a_run_still_in_contact():
    """A history that ends during the contact has no contact time and no restitution (NaN), and says so."""
    h = impact()
    dt, _ = hertz_analysis.time_grid(h, 100)
    m = hertz_analysis.measure(hertz_analysis.exact_history(h, dt, 80), h)
    assert not m["left"] and math.isnan(m["contact_time"]) and math.isnan(m["restitution"])
    assert m["peak_force"] == pytest.approx(h["F_star"], rel=1e-4)


def write_history(path, columns):
    os.makedirs(path, exist_ok=True)
    n = len(columns["t"])
    with open(os.path.join(path, "history.csv"), "w") as f:
        f.write(",".join(HEADER) + "\n")
        for k in range(n):
            f.write(",".join(repr(float(columns[c][k])) if c in columns else "0" for c in HEADER) + "\n")


MESHES = [os.path.join(ROOT, m) for m in hertz_analysis.MESHES.values()]


@pytest.mark.skipif(not all(os.path.exists(m) for m in MESHES), reason="meshes/hertz*.msh not built (make meshes)")
def test_report_of_exact_runs(tmp_path):
    """make hertz's report (summary.md, hertz.csv, hertz.png/.pdf) on history.csv files with the 3D driver's
    columns holding Hertz's exact impact, one per case: every run matches Hertz, and the targets hold; a run
    the driver refused (the singular mass) is named below the tables."""
    for case, (ratio, mesh, n, mass) in hertz_analysis.CASES.items():
        h = impact(ratio)
        write_history(tmp_path / case, hertz_analysis.exact_history(h, *hertz_analysis.time_grid(h, n)))
    text = hertz_analysis.report(str(tmp_path), list(hertz_analysis.CASES))
    assert text.count("| Hertz |") == 3 and text.count("holds") == 4 and "misses" not in text
    rows = list(csv.DictReader(open(tmp_path / "hertz.csv")))
    assert len(rows) == len(hertz_analysis.CASES)
    for row in rows:
        assert float(row["contact_time"]) == pytest.approx(float(row["T_H"]), rel=1e-4)
        assert float(row["peak_force"]) == pytest.approx(float(row["F_star"]), rel=1e-4)
    for ext in ("png", "pdf"):
        assert (tmp_path / f"hertz.{ext}").stat().st_size > 0
    refused = {"1e-03_default_100_singular": "exit 3: error: -mass singular: ..."}
    text = hertz_analysis.report(str(tmp_path), [c for c in hertz_analysis.CASES if c not in refused], refused)
    assert "- 1e-03_default_100_singular: exit 3: error: -mass singular: ..." in text and text.count("holds") == 4


def test_missing_scene_is_one_error_line(tmp_path):
    """Without the scene hertz (it comes with the 3D driver), make hertz's script stops before it runs or
    removes anything: one `error:` line, exit 1, an earlier summary left as it was."""
    (tmp_path / "summary.md").write_text("earlier\n")
    p = subprocess.run([sys.executable, os.path.join(ROOT, "postprocess", "hertz.py"), "--out", str(tmp_path),
                        "--scene", str(tmp_path / "no_such_scene.idp")], capture_output=True, text=True, cwd=ROOT)
    lines = p.stderr.strip().splitlines()
    assert p.returncode == 1 and len(lines) == 1 and lines[0].startswith("error: make hertz: no scene "), p.stderr
    assert (tmp_path / "summary.md").read_text() == "earlier\n" and p.stdout == ""
