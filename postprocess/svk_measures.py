"""What make svk measures of a run (postprocess/svk_compare.py): metrics() from its history.csv and snapshots
(det F, energy, contact, Newton), and the uniaxial-strain stress of the three models."""
import glob
import os
import re

import numpy as np

from history import contact_intervals, read_csv, read_freefem_mesh, read_parameters, read_summary


class Failure(Exception):
    pass


def snapshots(run_dir):
    files = glob.glob(os.path.join(run_dir, "snapshot_t*.csv"))
    return sorted((float(re.search(r"snapshot_t(.*)\.csv", p).group(1)), p) for p in files)


def uniaxial_stress(s, lam=30.0, mu=30.0):
    """First Piola-Kirchhoff stress P11 under uniaxial strain F = diag(s, 1), per model."""
    k = lam + 2 * mu
    return {"linear": k * (s - 1), "svk": k * s * (s * s - 1) / 2,
            "neohookean": mu * (s - 1 / s) + lam * np.log(s) / s}


def snapshot_min_J(run_dir):
    """(t, min det F) at each snapshot: det F of a P1 triangle is its deformed over its reference area,
    what the history's min_J holds for a non-linear run; for the linear body, the only record of it."""
    xy, tri = read_freefem_mesh(os.path.join(run_dir, "mesh.msh"))

    def area(p):
        a, b = p[tri[:, 1]] - p[tri[:, 0]], p[tri[:, 2]] - p[tri[:, 0]]
        return a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]
    out = []
    for t, path in snapshots(run_dir):
        s = read_csv(path)
        X = np.column_stack([s["x"], s["y"]])
        if X.shape != xy.shape or np.abs(X - xy).max() > 1e-6:
            raise Failure(f"{path}: its rows are not the vertices of mesh.msh")
        out.append((t, float((area(X + np.column_stack([s["u1"], s["u2"]])) / area(X)).min())))
    return out


def fixed_foundation_steps(run_dir, t):
    """Steps n -> n+1 (index n+1) during which the foundation does not move."""
    p = read_parameters(run_dir)
    f = p["-foundation"]
    if f == "none" or (f == "flat" and float(p["-foundation_velocity"]) == 0):
        return np.ones(len(t) - 1, bool)
    if f == "cosine":
        return (t[1:] <= float(p["-t0"])) | (t[:-1] >= float(p["-t1"]))
    raise Failure(f"{run_dir}: no rule for when the foundation {f} is fixed")


def at_max(t, v, arg=np.argmax):
    k = int(arg(v))
    return float(v[k]), float(t[k])


def metrics(res, h):
    s = read_summary(res["dir"]) if os.path.exists(os.path.join(res["dir"], "summary.txt")) else {}
    t = h["t"]
    n = h["newton_iterations"][1:]
    m = {"steps": len(t) - 1, "t_end": t[-1], "max_strain": at_max(t, h["max_strain"]),
         "newton_mean": float(n.mean()) if len(n) else 0.0, "newton_max": int(n.max()) if len(n) else 0,
         "cpu": s.get("cpu_seconds"), "max_pen": float(h["max_penetration"].max())}
    if "u2_probe0" in h:
        comp = h["u2_low"] - h["u2_probe0"]          # shortening of the vertical diameter (40 at rest)
        m["compression"] = at_max(t, comp)
    vm = [(read_csv(p)["vonmises"].max(), t) for t, p in snapshots(res["dir"])]
    m["vm"] = max(vm) if vm else None
    snapJ = snapshot_min_J(res["dir"])
    if "min_J" in h:
        m["min_J"] = at_max(t, h["min_J"], np.argmin)
        for ts, j in snapJ:                          # the history's min_J is the snapshots' det F
            k = int(np.argmin(np.abs(t - ts)))
            if abs(h["min_J"][k] - j) > 1e-6:
                raise Failure(f"{res['case']}/{res['model']}: min_J {h['min_J'][k]:.9g} at t = {t[k]:g} but "
                              f"{j:.9g} from the snapshot")
    else:
        m["min_J"] = None                            # the linear history has no min_J
    m["snapshot_min_J"] = min(((j, ts) for ts, j in snapJ), default=None)
    e, am = h["energy"], h["angular_momentum"]
    m["energy_drift"] = float(np.abs(e - e[0]).max() / abs(e[0]))
    m["am_drift"] = float(np.abs(am - am[0]).max() / abs(am[0])) if am[0] != 0 else None
    me = h["modified_energy"]
    rise = np.diff(me)[fixed_foundation_steps(res["dir"], t)]
    m["energy"] = (float(me[0]), float(me[-1]), float(rise.max()) if len(rise) else float("nan"))
    iv = contact_intervals(t, h["active_nodes"] > 0)
    m["bounces"] = len(iv)
    m["first_contact"] = iv[0] if iv else None
    m["alpha"] = at_max(t, h["contact_pressure_low"])
    if iv and not (res["broke"] and iv[0][1] == t[-1]):
        k0, k1 = int(np.searchsorted(t, iv[0][0])), int(np.searchsorted(t, iv[0][1]))
        m["v_impact"], m["v_rebound"] = float(h["v2_mean"][k0 - 1]), (float(h["v2_mean"][k1 + 1])
                                                                       if k1 + 1 < len(t) else None)
        later = (t > iv[0][1]) & (t < (iv[1][0] if len(iv) > 1 else np.inf))
        m["rebound_height"] = at_max(t[later], h["u2_low"][later]) if later.any() else None
    return m
