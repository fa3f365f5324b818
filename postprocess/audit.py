"""A run checked against the physics its own files claim: `python3 postprocess/audit.py RUN [RUN ...]`.

Each check reads only the run's files (history.csv, parameters.txt, summary.txt, the mesh it saved, its
snapshots) and recomputes what they must satisfy from the paper's equations, independently of the code that wrote
them; a failure names the check, the column, the step and the size of the difference (docs/errors.md, "The audit"):

  columns    no column name twice; exactly the documented columns of this run (docs/outputs.md), in their order;
             every value a number, finite (max_strain and min_J may be empty between -diagnostics_every's steps)
  grid       step = 0, 1, ..., t = step dt; with summary.txt: the last row is step T/dt at t = T, and summary.txt's
             T, dt, steps, qp_steps and max_penetration are parameters.txt's and the history's
  momentum   (1) summed over a translation (K and the material's force have none along it, (2) gives v):
             rho |body| (v_k^{n+1} - v_k^n) / dt = |body| f_k + contact_force_k^{n+1} in every component k
             (Newmark, Verlet: the force at gamma between t_n and t_{n+1}); |body| from the saved mesh; not checked
             on a clamped body (Gamma_D's reaction is not a column)
  energy     Prop. 2: on a foundation fixed in time, under (10) with the mid-point scheme, E - (f, u) + D - W never
             rises from a step to the next (D friction's work, W a belt's), to round-off (IPOPT: its -tol;
             Newton: -newton_tol)
  bodies     several bodies: E^{n+1} - E^n = rows_work (the mid-point identity with the step's rows at u^n) to
             round-off (IPOPT: its -tol, as energy); without load and foundation the momentum_x and momentum_y constant to 1e-12 of the bodies'
  friction   D never decreases; Coulomb |T| <= F N and Tresca |T| <= g |Gamma_C| in totals, in the foundation's
             frame where it is flat (tilted or not)
  snapshots  a snapshot_t<t>.csv for every snapshot time up to the last row, its displacement at the reference
             point the history's u1_low, u2_low (3D: and u3_low) at that time; its .vtu's pressed, sticking and
             slipping nodes the history's active_nodes, stick_nodes, slip_nodes (serial, P1)

Exit status: 0 every check passes; 1 a check fails (one line each, `audit: RUN: ...`); 2 a run's files cannot be
read. Pure Python (no numpy), so that edp/run.sh can afford it after every run (python3 -S: 25 ms on Test 1).
"""
import csv
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from keyed import read_keyed  # noqa: E402

# The relative size of round-off in a check of sums over the body (a history value is written to 15 digits)
ROUND_OFF = 1e-10
# The mid-point's energy identity holds to the solve's round-off; per step, against the run's energy scale
ENERGY_ROUND_OFF = 1e-10
PRINTED = 1e-14         # the relative precision of a number in history.csv (15 significant digits)
MOMENTUM_ROUND_OFF = 1e-12   # of a sum over the nodes of rho v, relative to the body's speed


class Failure(Exception):
    pass


def read_options(path):
    """parameters.txt as key (without its -) -> value."""
    return {key.lstrip("-"): value for key, value in read_keyed(path).items()}


def read_history(path):
    """(header, rows): the rows as lists of floats (an empty cell is None)."""
    with open(path, newline="") as f:
        reader = csv.reader(f)
        try:
            header = next(reader)
        except StopIteration:
            raise Failure("history.csv is empty")
        rows = []
        for k, row in enumerate(reader):
            if len(row) != len(header):
                raise Failure(f"history.csv: row {k + 1} has {len(row)} cells, the header {len(header)}")
            values = []
            for name, cell in zip(header, row):
                if cell == "":
                    values.append(None)
                    continue
                try:
                    values.append(float(cell))
                except ValueError:
                    raise Failure(f"history.csv: column {name} at row {k + 1} is not a number: {cell!r}")
            rows.append(values)
    return header, rows


def vtu_array(text, name):
    """A Float64 point or cell array of a VTK XML file that FreeFEM's savevtk wrote (binary: base64 of a UInt32 byte
    count and the little-endian values), or None. (Its modules are imported here: most runs write no .vtu.)"""
    import base64
    import re
    import struct
    m = re.search(r'<DataArray[^>]*Name="%s"[^>]*format="binary"[^>]*>\s*([^<]*)<' % name, text)
    if not m or 'type="Float64"' not in m.group(0):
        return None
    raw = base64.b64decode(m.group(1).strip())
    size = struct.unpack("<I", raw[:4])[0]
    return struct.unpack("<%dd" % (size // 8), raw[4:4 + size])


def mesh_measures(run):
    """(|body|, its boundary, dimension, {label: area} of its bodies) from the mesh the run saved: mesh.msh (FreeFEM's
    2D format: the bodies by their triangles' region labels, docs/bodies.md) or mesh.mesh (medit, 3D: one body,
    {1: |body|})."""
    if os.path.exists(os.path.join(run, "mesh.mesh")):
        volume, faces = medit_measures(os.path.join(run, "mesh.mesh"))
        return volume, faces, 3, {1: volume}
    xy, cells, edges = freefem_mesh(os.path.join(run, "mesh.msh"))
    areas, area = {}, 0.0
    for i, j, k, label in cells:
        a, b, c = xy[i], xy[j], xy[k]
        cell = abs((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])) / 2
        area += cell
        areas[label] = areas.get(label, 0.0) + cell
    return area, [(xy[i], xy[j], label) for i, j, label in edges], 2, dict(sorted(areas.items()))


def freefem_mesh(path):
    """FreeFEM's 2D mesh file: the vertices (x, y), the triangles (i, j, k, region label) and the boundary edges
    (i, j, label), numbered from 0."""
    with open(path) as f:
        nv, nt, ne = (int(x) for x in f.readline().split())
        xy = [tuple(float(x) for x in f.readline().split()[:2]) for _ in range(nv)]
        cells = [tuple(int(x) - (1 if n < 3 else 0) for n, x in enumerate(f.readline().split()[:4])) for _ in range(nt)]
        edges = [tuple(int(x) - (1 if n < 2 else 0) for n, x in enumerate(f.readline().split()[:3])) for _ in range(ne)]
    return xy, cells, edges


def medit_sections(path):
    """A medit mesh's Vertices, Tetrahedra and Triangles, each a list of its lines' tokens."""
    with open(path) as f:
        tokens = f.read().split()
    sections, k = {}, 0
    while k < len(tokens):
        word = tokens[k]
        if word in ("Vertices", "Tetrahedra", "Triangles"):
            n, width = int(tokens[k + 1]), {"Vertices": 4, "Tetrahedra": 5, "Triangles": 4}[word]
            sections[word] = [tokens[k + 2 + width * i:k + 2 + width * (i + 1)] for i in range(n)]
            k += 2 + width * n
        else:
            k += 1
    return sections


def medit_measures(path):
    sections = medit_sections(path)
    xyz = [tuple(float(x) for x in v[:3]) for v in sections["Vertices"]]
    volume = 0.0
    for t in sections.get("Tetrahedra", []):
        a, b, c, d = (xyz[int(x) - 1] for x in t[:4])
        u, v, w = [[p[i] - a[i] for i in range(3)] for p in (b, c, d)]
        volume += abs(u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0])
                      + u[2] * (v[0] * w[1] - v[1] * w[0])) / 6
    faces = [(tuple(xyz[int(x) - 1] for x in t[:3]), int(t[3])) for t in sections.get("Triangles", [])]
    return volume, faces


def traction_resultant(run, label, pressure, dimension):
    """The resultant of -traction's load, -p n integrated over Gamma_T (label): n the outward normal of each boundary
    edge (3D: face), away from its cell's other vertex; per component."""
    total = [0.0] * dimension
    if dimension == 3:
        sections = medit_sections(os.path.join(run, "mesh.mesh"))
        xyz = [tuple(float(x) for x in v[:3]) for v in sections["Vertices"]]
        other = {}
        for t in sections.get("Tetrahedra", []):
            ids = [int(x) - 1 for x in t[:4]]
            for i in range(4):
                other[tuple(sorted(ids[:i] + ids[i + 1:]))] = ids[i]
        for t in sections.get("Triangles", []):
            if int(t[3]) != label:
                continue
            ids = [int(x) - 1 for x in t[:3]]
            a, b, c = (xyz[i] for i in ids)
            u, v = [[q[i] - a[i] for i in range(3)] for q in (b, c)]
            n = [(u[1] * v[2] - u[2] * v[1]) / 2, (u[2] * v[0] - u[0] * v[2]) / 2, (u[0] * v[1] - u[1] * v[0]) / 2]
            d = xyz[other[tuple(sorted(ids))]]
            if sum(n[i] * (d[i] - a[i]) for i in range(3)) > 0:
                n = [-x for x in n]
            total = [total[i] - pressure * n[i] for i in range(3)]
        return total
    xy, cells, edges = freefem_mesh(os.path.join(run, "mesh.msh"))
    other = {}
    for cell in cells:
        for i in range(3):
            other[tuple(sorted(cell[:i] + cell[i + 1:3]))] = cell[i]
    for i, j, lab in edges:
        if lab != label:
            continue
        a, b, c = xy[i], xy[j], xy[other[tuple(sorted((i, j)))]]
        n = [b[1] - a[1], a[0] - b[0]]                  # (|n| = the edge's length)
        if n[0] * (c[0] - a[0]) + n[1] * (c[1] - a[1]) > 0:
            n = [-x for x in n]
        total = [total[0] - pressure * n[0], total[1] - pressure * n[1]]
    return total


def boundary_measure(boundary, dimension, labels):
    total = 0.0
    for item in boundary:
        if dimension == 2:
            a, b, label = item
            if label in labels:
                total += math.hypot(b[0] - a[0], b[1] - a[1])
        else:
            (a, b, c), label = item
            if label in labels:
                u, v = [[p[i] - a[i] for i in range(3)] for p in (b, c)]
                total += math.sqrt((u[1] * v[2] - u[2] * v[1]) ** 2 + (u[2] * v[0] - u[0] * v[2]) ** 2
                                   + (u[0] * v[1] - u[1] * v[0]) ** 2) / 2
    return total


def friction_acts(p):
    return p.get("friction") == "tresca" or (p.get("friction") == "coulomb" and float(p["friction_coefficient"]) > 0)


def probe_count(p, dimension):
    probes = p.get("probes", "none")
    return 0 if probes in ("none", "") else len(probes.split(",")) // dimension


def expected_columns(p, dimension, bodies=(1,)):
    """history.csv's columns for this run, as docs/outputs.md lists them (and edp/lib/io/history.idp writes them)."""
    if dimension == 3:
        cols = ("step,t,u1_low,u2_low,u3_low,v3_low,contact_pressure_low,contact_force_z,contact_area,energy,"
                "modified_energy,active_nodes,max_penetration,qp_solved,solver_status,v1_mean,v2_mean,v3_mean,u3_mean,"
                "newton_iterations,angular_momentum_1,angular_momentum_2,angular_momentum_3,max_strain,"
                "max_penetration_outside,max_penetration_exact,max_held_off_exact,contact_force_x,contact_force_y")
    else:
        cols = ("step,t,u1_low,u2_low,v2_low,contact_pressure_low,contact_force_y,energy,modified_energy,active_nodes,"
                "max_penetration,qp_solved,solver_status,v1_mean,v2_mean,newton_iterations,angular_momentum,max_strain,"
                "max_penetration_outside,max_penetration_exact,max_held_off_exact,contact_force_x")
    cols = cols.split(",")
    if p.get("material", "linear") != "linear":
        cols.append("min_J")
    if friction_acts(p) and len(bodies) == 1:
        cols += ["friction_work", "slip_nodes", "stick_nodes", "u1_mean", "u2_mean"]
        cols += (["angular_velocity_1", "angular_velocity_2", "angular_velocity_3"] if dimension == 3
                 else ["angular_velocity"])
        cols.append("foundation_work")
    for k in range(probe_count(p, dimension)):
        cols += [f"u{c}_probe{k}" for c in range(1, dimension + 1)]
    if len(bodies) > 1:
        cols += ["momentum_x", "momentum_y"]
        for b in bodies:
            cols += [f"body{b}_u1_mean", f"body{b}_u2_mean", f"body{b}_v1_mean", f"body{b}_v2_mean"]
        cols += ["body_contact_force", "body_contact_nodes", "max_penetration_bodies", "rows_work", "linearisations"]
        if friction_acts(p):          # (friction between the bodies: docs/bodies.md)
            cols += ["body_friction_work", "body_slip_nodes", "body_stick_nodes"]
    return cols


class Run:
    def __init__(self, path):
        self.path = path
        self.failures = []
        for name in ("history.csv", "parameters.txt"):
            if not os.path.exists(os.path.join(path, name)):
                raise Failure(f"no {name}")
        self.p = read_options(os.path.join(path, "parameters.txt"))
        summary = os.path.join(path, "summary.txt")
        self.summary = read_keyed(summary) if os.path.exists(summary) else None
        self.header, self.rows = read_history(os.path.join(path, "history.csv"))
        if not self.rows:
            raise Failure("history.csv has no row")
        self.volume, self.boundary, self.dimension, areas = mesh_measures(path)
        label, pressure = int(self.p.get("traction_label", "0")), float(self.p.get("traction", "0"))
        self.traction = (traction_resultant(path, label, pressure, self.dimension) if label > 0 and pressure != 0
                         else [0.0] * self.dimension)
        self.bodies = list(areas)
        # the mass, rho |body| (several bodies: a -rho list gives each its own, in the order of their labels)
        rhos = [float(r) for r in self.p["rho"].split(",")]
        self.mass = (sum(r * a for r, a in zip(rhos, areas.values())) if len(rhos) > 1 else rhos[0] * self.volume)
        self.dt = float(self.p["dt"])

    def col(self, name):
        k = self.header.index(name)
        return [r[k] for r in self.rows]

    def fail(self, check, text):
        self.failures.append(f"{check}: {text}")

    def at(self, n):
        """'step N (t = T)' of row n."""
        return f"step {self.rows[n][0]:.0f} (t = {self.rows[n][1]:.15g})"

    # ---- the checks
    def check_columns(self):
        seen = set()
        for name in self.header:
            if name in seen:
                self.fail("columns", f"column {name} appears twice in history.csv's header")
            seen.add(name)
        expected = expected_columns(self.p, self.dimension, self.bodies)
        missing = [c for c in expected if c not in self.header]
        extra = [c for c in self.header if c not in expected]
        if missing:
            self.fail("columns", f"history.csv lacks the documented column(s) {', '.join(missing)}")
        if extra:
            self.fail("columns", f"history.csv has undocumented column(s) {', '.join(extra)}")
        if not missing and not extra and self.header != expected:
            self.fail("columns", "history.csv's columns are not in the documented order")
        optional = {"max_strain", "min_J"}
        for n, row in enumerate(self.rows):
            for name, value in zip(self.header, row):
                if value is None and name not in optional:
                    self.fail("columns", f"column {name} is empty at {self.at(n)}")
                    return
                if value is not None and not math.isfinite(value):
                    self.fail("columns", f"column {name} is {value} at {self.at(n)}")
                    return

    def check_grid(self):
        steps, t = self.col("step"), self.col("t")
        for n, (s, tn) in enumerate(zip(steps, t)):
            if s != n:
                self.fail("grid", f"column step is {s:.0f} at row {n + 1}, where {n} is due")
                return
            if abs(tn - n * self.dt) > 1e-9 * max(1.0, abs(n * self.dt)):
                self.fail("grid", f"column t is {tn:.15g} at step {n} (step dt = {n * self.dt:.15g} is due: differs by "
                                  f"{abs(tn - n * self.dt):.3g})")
                return
        T = float(self.p["T"])
        if t[-1] > T * (1 + 1e-12) + 1e-12:
            self.fail("grid", f"the last row is at t = {t[-1]:.15g}, past parameters.txt's T = {T:.15g}")
        if self.summary is None:
            return
        s = self.summary
        nsteps = round(T / self.dt)
        checks = [("T", float(s["T"]), T), ("dt", float(s["dt"]), self.dt), ("steps", float(s["steps"]), nsteps),
                  ("the last row's step", steps[-1], nsteps), ("the last row's t", t[-1], T)]
        for what, got, due in checks:
            if abs(got - due) > 1e-9 * max(1.0, abs(due)):
                self.fail("grid", f"summary.txt's run reached T, but {what} is {got:.15g} where parameters.txt gives "
                                  f"{due:.15g}")
        if "qp_steps" in s and float(s["qp_steps"]) != sum(self.col("qp_solved")):
            self.fail("grid", f"summary.txt's qp_steps {s['qp_steps']} is not the sum of history.csv's qp_solved, "
                              f"{sum(self.col('qp_solved')):.0f}")
        if "max_penetration" in s:
            largest = max(self.col("max_penetration"))
            recorded = float(s["max_penetration"])
            if abs(recorded - max(largest, 0.0)) > 1e-5 * max(abs(largest), 1e-300) and not (largest <= 0 and recorded == 0):
                self.fail("grid", f"summary.txt's max_penetration {recorded:.6g} is not history.csv's largest, {largest:.6g}")

    def solver_round_off(self):
        """The relative accuracy of a step's solution: IPOPT solves to -tol, Newton to -newton_tol."""
        tol = ROUND_OFF
        if self.p.get("solver") == "ipopt":
            tol = max(tol, 10 * float(self.p.get("tol", "1e-8")))
        return tol

    def check_momentum(self):
        if self.p.get("dirichlet_label", "0") not in ("0", ""):
            return          # Gamma_D's reaction is not a column
        mass = self.mass
        up = "xyz"[self.dimension - 1]
        loads = {"x": float(self.p["fx"]), "y": float(self.p["fy"])}
        if self.dimension == 3:
            loads["z"] = float(self.p["fz"])
        external = {k: self.volume * f for k, f in loads.items()}      # (f |body|, and -traction's resultant)
        for k, r in zip("xyz", self.traction):
            external[k] += r
        velocity = {"x": "v1_mean", "y": "v2_mean", "z": "v3_mean"}
        scheme = self.p.get("scheme", "midpoint")
        gamma = 0.5 if scheme == "verlet" else (float(self.p["newmark_gamma"]) if scheme == "newmark" else 1.0)
        forces = {k: self.col(f"contact_force_{k}") for k in loads}
        scale = max(max(abs(x) for x in forces[k]) for k in loads)
        scale = max(scale, max(abs(f) for f in external.values()))
        speeds = {k: self.col(velocity[k]) for k in loads}
        # the momentum's own round-off: a sum of rho v over the nodes, whose speeds the energy bounds (E >= |M v|^2 / 2m),
        # though the mean may be 0 (a spinning body)
        speed = max(max(abs(x) for x in speeds[k]) for k in loads)
        speed += math.sqrt(2 * max(max(abs(e) for e in self.col("energy")), 0.0) / mass)
        # ... and (2)'s, v^{n+1} = 2 (u^{n+1} - u^n) / dt - v^n: the round-off of u (its size U: the lift and the
        # reference point's displacement) over dt, which a body at rest under a vanishing load shows alone
        size = max(abs(float(v)) for k in ("u0x", "u0y", "u0z") for v in self.p.get(k, "0").split(","))   # (a list: per body)
        size += max(max(abs(x) for x in self.col(c)) for c in self.header if c in ("u1_low", "u2_low", "u3_low"))
        tol = (self.solver_round_off() * scale + mass * MOMENTUM_ROUND_OFF * speed / self.dt
               + mass * MOMENTUM_ROUND_OFF * 10 * size / self.dt ** 2)
        for k, f in external.items():
            v, c = speeds[k], forces[k]
            worst, where = 0.0, 0
            for n in range(1, len(v)):
                force = gamma * c[n] + (1 - gamma) * c[n - 1]
                residual = abs(mass * (v[n] - v[n - 1]) / self.dt - f - force)
                if residual > worst:
                    worst, where = residual, n
            if worst > tol:
                n = where
                due = (mass * (v[n] - v[n - 1]) / self.dt - f - (1 - gamma) * c[n - 1]) / gamma
                self.fail("momentum", f"contact_force_{k} is {c[n]:.10g} at {self.at(n)}, where (1) summed over a "
                                      f"translation gives {due:.10g} from {velocity[k]}'s change (rho |body| dv / dt - "
                                      f"|body| f_{k} - the traction's): they differ by {worst:.3g} (tolerance {tol:.3g})")

    def foundation_fixed(self):
        kind = self.p.get("foundation")
        if kind in ("none", "bowl"):
            return True
        if kind == "flat":
            return float(self.p.get("foundation_velocity", "0")) == 0
        if kind == "user":
            scene = os.path.join(self.path, "scene.idp")
            text = open(scene).read().replace(" ", "") if os.path.exists(scene) else "foundationMoving=1"
            return "foundationMoving=1" not in text
        return False

    def check_bodies(self):
        """Several bodies (docs/bodies.md): the mid-point scheme's energy identity, E^{n+1} - E^n = lm . (C u^n - g)
        (rows_work: the step's rows at u^n; <= 0 where u^n satisfies them, Prop. 2), to round-off; and without load
        and foundation, the total momentum conserved (each row's forces equal and opposite) to 1e-12 of the bodies'."""
        if len(self.bodies) < 2:
            return
        m, work = self.col("modified_energy"), list(self.col("rows_work"))
        if "body_friction_work" in self.header:     # (E^{n+1} - E^n = rows_work - the step's friction work)
            D = self.col("body_friction_work")
            work = [w - (D[n] - D[n - 1] if n > 0 else 0.0) for n, w in enumerate(work)]
        scale = max(max(abs(x) for x in m), max(abs(x) for x in self.col("energy")), 1e-300)
        allowed = ENERGY_ROUND_OFF * scale
        if self.p.get("solver") == "ipopt":     # (its stationarity and complementarity to -tol: as check_energy)
            tol = float(self.p.get("tol", "1e-8"))
            allowed = max(ENERGY_ROUND_OFF, tol) * scale + 100 * tol * max(1.0, max(self.col("body_contact_nodes")))
        worst, where = 0.0, 0
        for n in range(1, len(m)):
            if abs(m[n] - m[n - 1] - work[n]) > worst:
                worst, where = abs(m[n] - m[n - 1] - work[n]), n
        if worst > allowed:
            self.fail("energy", f"modified_energy changes by {m[where] - m[where - 1]:.6g} at {self.at(where)}, and the "
                                f"mid-point identity makes it rows_work, {work[where]:.6g}: they differ by {worst:.3g} "
                                f"(tolerance {allowed:.3g})")
        loads = [float(self.p.get(k, "0")) for k in ("fx", "fy")]
        if self.p.get("foundation") != "none" or any(loads):
            return
        mass = self.mass
        speeds = [abs(x) for b in self.bodies for k in (1, 2) for x in self.col(f"body{b}_v{k}_mean")]
        momentum_scale = mass * max(max(speeds), 1e-300)
        # ... and, as check_momentum's, (2)'s round-off of u over dt (its size: the lifts and the bodies' displacements)
        size = max(abs(float(v)) for k in ("u0x", "u0y") for v in self.p.get(k, "0").split(","))
        size += max(abs(x) for b in self.bodies for k in (1, 2) for x in self.col(f"body{b}_u{k}_mean"))
        tol = MOMENTUM_ROUND_OFF * (momentum_scale + mass * 10 * size / self.dt)
        for k in ("x", "y"):
            p = self.col(f"momentum_{k}")
            drift = max(abs(x - p[0]) for x in p)
            if drift > tol:
                n = max(range(len(p)), key=lambda i: abs(p[i] - p[0]))
                self.fail("momentum", f"momentum_{k} moves by {drift:.3g} from its start to {self.at(n)}, without load or "
                                      f"foundation (tolerance {tol:.3g}: 1e-12 of the bodies' momentum "
                                      f"{momentum_scale:.6g}, and of the round-off of u over dt)")

    def check_energy(self):
        p = self.p
        if len(self.bodies) > 1:
            return          # (check_bodies: the identity with the rows' work)
        if (p.get("scheme") != "midpoint" or p.get("contact") != "constraint" or p.get("gap", "linearised") != "linearised"
                or not self.foundation_fixed()):
            return
        e, m = self.col("energy"), self.col("modified_energy")
        total = list(m)
        if "friction_work" in self.header:
            total = [a + d - w for a, d, w in zip(m, self.col("friction_work"), self.col("foundation_work"))]
        work = [a - b for a, b in zip(e, m)]
        scale = max(abs(m[0]), e[0], max(abs(w - work[0]) for w in work), 1e-300)
        tol = ENERGY_ROUND_OFF
        if p.get("solver") == "ipopt":
            tol = max(tol, float(p.get("tol", "1e-8")))
        if p.get("material", "linear") != "linear":
            tol = max(tol, 10 * float(p.get("newton_tol", "1e-10")))
        # and the round-off of E and (f, u) themselves, which can be far larger than m (a body far from the origin)
        terms = max(max(abs(x) for x in e), max(abs(w) for w in work))
        allowed = tol * scale + 10 * PRINTED * terms
        if p.get("solver") == "ipopt":      # its complementarity, lm_j gap_j <= about tol at each pressed node (absolute)
            allowed += 100 * float(p.get("tol", "1e-8")) * max(1.0, max(self.col("active_nodes")))
        worst, where = 0.0, 0
        for n in range(1, len(total)):
            if total[n] - total[n - 1] > worst:
                worst, where = total[n] - total[n - 1], n
        if worst > allowed:
            name = "modified_energy + friction_work - foundation_work" if "friction_work" in self.header else "modified_energy"
            self.fail("energy", f"{name} rises by {worst:.3g} at {self.at(where)}, where Prop. 2 allows no rise on this "
                                f"fixed foundation (tolerance {allowed:.3g}, {allowed / scale:.2g} of the run's energy {scale:.6g})")

    def check_friction(self):
        if "friction_work" not in self.header:
            return
        D = self.col("friction_work")
        for n in range(1, len(D)):
            if D[n] < D[n - 1] - 1e-12 * max(abs(D[n - 1]), 1e-300):
                self.fail("friction", f"friction_work falls from {D[n - 1]:.10g} to {D[n]:.10g} at {self.at(n)}: "
                                      "friction only dissipates")
                break
        if self.p.get("foundation") != "flat":
            return
        theta = math.radians(float(self.p.get("angle", "0")))
        normal = (-math.sin(theta), math.cos(theta))       # the flat's upward unit normal, in the (X1, Up) plane
        comps = ["x", "y"] if self.dimension == 2 else ["x", "y", "z"]
        forces = [self.col(f"contact_force_{k}") for k in comps]
        up = len(comps) - 1
        scale = max(max(abs(x) for x in f) for f in forces) or 1e-300
        tol = self.solver_round_off() * scale
        if self.p["friction"] == "coulomb":
            coefficient, what = float(self.p["friction_coefficient"]), "F N"
        else:
            labels = {int(x) for x in self.p.get("contact_label", "1").split(",")}
            coefficient = float(self.p["friction_bound"]) * boundary_measure(self.boundary, self.dimension, labels)
            what = "g |Gamma_C|"
        worst, where, ratio = 0.0, 0, 0.0
        for n in range(len(forces[0])):
            f = [c[n] for c in forces]
            N = normal[0] * f[0] + normal[1] * f[up]
            tangential_sq = sum(x * x for x in f) - N * N
            T = math.sqrt(max(tangential_sq, 0.0))
            bound = coefficient * N if self.p["friction"] == "coulomb" else coefficient
            if T - bound > worst:
                worst, where, ratio = T - bound, n, T / N if N > 0 else math.inf
        if worst > tol:
            self.fail("friction", f"the tangential contact force exceeds {what} at {self.at(where)} by {worst:.3g} "
                                  f"(|T|/N = {ratio:.6g}; tolerance {tol:.3g}), in the frame of the flat foundation at "
                                  f"{float(self.p.get('angle', '0')):g} degrees")

    def check_snapshots(self):
        times = self.p.get("snapshots", "none")
        if times in ("none", ""):
            return
        t = self.col("t")
        last = t[-1]
        components = ["u1_low", "u2_low"] + (["u3_low"] if self.dimension == 3 else [])
        reference = [float(x) for x in self.p.get("reference", "0,0").split(",")]
        for text in times.split(","):
            ts = float(text)
            if ts > last * (1 + 1e-12) + 1e-12:
                continue
            path = os.path.join(self.path, f"snapshot_t{text}.csv")
            if not os.path.exists(path):
                self.fail("snapshots", f"no snapshot_t{text}.csv, though the history reached t = {last:.15g}")
                continue
            n = min(range(len(t)), key=lambda k: abs(t[k] - ts))
            if abs(t[n] - ts) > 1e-9 * max(1.0, ts):
                self.fail("snapshots", f"snapshot time {text} is no step time of the history")
                continue
            with open(path, newline="") as f:
                reader = csv.reader(f)
                head = next(reader)
                coords = head[:self.dimension]
                disp = head[self.dimension:2 * self.dimension]
                best, best_d = None, math.inf
                for row in reader:
                    x = [float(v) for v in row[:self.dimension]]
                    d = sum((a - b) ** 2 for a, b in zip(x, reference))
                    if d < best_d:
                        best, best_d = row, d
            if best is None:
                self.fail("snapshots", f"snapshot_t{text}.csv has no row")
                continue
            u = [float(v) for v in best[self.dimension:2 * self.dimension]]
            for name, value in zip(components, u):
                due = self.rows[n][self.header.index(name)]
                if abs(value - due) > 1e-9 * max(1.0, abs(due)):
                    self.fail("snapshots", f"snapshot_t{text}.csv gives {name.split('_')[0]} = {value:.12g} at the reference "
                                           f"point, history.csv {due:.12g} at {self.at(n)} (differs by {abs(value - due):.3g})")
            del coords, disp
            self.check_snapshot_counts(text, n)

    def check_snapshot_counts(self, text, n):
        """The snapshot's .vtu (serial, P1) against the history's counts at that step: the nodes with a contact pressure
        above 1e-6 (active_nodes), and with friction those that stick and slip (contact_state 1 and 2)."""
        path = os.path.join(self.path, f"vonmises_t{text}.vtu")
        if not os.path.exists(path) or self.p.get("order", "1") != "1":
            return
        vtu = open(path).read()
        counts = [("active_nodes", "contact_pressure", lambda x: x > 1e-6)]
        if "slip_nodes" in self.header:
            counts += [("slip_nodes", "contact_state", lambda x: x == 2), ("stick_nodes", "contact_state", lambda x: x == 1)]
        for column, field, chosen in counts:
            values = vtu_array(vtu, field)
            if values is None:
                continue
            got, due = sum(1 for x in values if chosen(x)), self.rows[n][self.header.index(column)]
            if got != due:
                self.fail("snapshots", f"vonmises_t{text}.vtu has {got} nodes of Gamma_C counted as {column} counts them "
                                       f"({field}), history.csv {due:.0f} at {self.at(n)}")

    def audit(self):
        self.check_columns()
        if self.failures:          # the other checks read the columns by name
            return self.failures
        for check in (self.check_grid, self.check_momentum, self.check_energy, self.check_bodies, self.check_friction,
                      self.check_snapshots):
            check()
        return self.failures


def audit_run(path):
    """The audit's failures of the run in path (a list of lines; empty: it passes). Raises Failure when the run's
    files cannot be read."""
    try:
        return Run(path).audit()
    except (OSError, KeyError, ValueError, IndexError) as e:
        raise Failure(f"{type(e).__name__}: {e}")


def main(argv):
    if not argv or argv[0] in ("-h", "--help"):
        print(__doc__.strip())
        return 2 if not argv else 0
    status = 0
    for path in argv:
        try:
            failures = audit_run(path)
        except Failure as e:
            print(f"audit: {path}: its files cannot be read: {e}", file=sys.stderr)
            status = max(status, 2)
            continue
        for line in failures:
            print(f"audit: {path}: {line}", file=sys.stderr)
        if failures:
            status = max(status, 1)
    return status


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
