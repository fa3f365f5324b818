#!/usr/bin/python3
"""An independent numpy + scipy implementation of the mid-point scheme (1)-(2) of Murea (2023) for two plane
elastic bodies in contact with each other: the prototype and the future cross-check of bodies against bodies.

The discretisation:
  - P1 Lagrange vector displacement on the triangles of a gmsh MSH 2.2 mesh; a triangle's physical tag is its
    body (1 or 2), and the bodies have their own nodes (a node that two bodies' triangles share is doubled);
    a boundary line with physical tag 1 is its body's contact boundary;
  - for each body, the consistent mass M (int rho u.w), the stiffness K of plane strain (lambda div u div w +
    2 mu eps(u):eps(w)); no load, no foundation; A = 2 M / dt^2 + K / 2 (block-diagonal by body), factorised once;
  - constraint (10) between bodies, node to segment ("nts"), or mortar's weighted gaps with standard ("mortar")
    or biorthogonal ("dual") multipliers (contact_rows_mortar); node to segment, one pass: each contact node s of
    body 1 against the closest contact segment [a, b] of body 2 in the current configuration, the gap
        g = (x_s - (1 - xi) x_a - xi x_b) . n  >= 0,   n the segment's outward normal (of body 2),
    imposed at t_{n+1} with xi and n frozen: a linear row (n on s, -(1 - xi) n on a, -xi n on b) whose
    coefficients sum to zero in each component, so the contact forces are equal and opposite and the total
    momentum is conserved to round-off. The step re-linearises about its result until xi and n hold (as
    -gap exact does with the foundation), so that the true gap holds at its end;
  - each step's QP (4), min 1/2 x'Ax - L'x under the rows, by the primal-dual active set on S = G A^-1 G';
    the multiplier of a row is the nodal contact force;
  - v^{n+1} = 2 (x - u^n) / dt - v^n, u^{n+1} = x.

Use: /usr/bin/python3 tests/reference/scipy_bodies.py --lengths 10,10 --v0 0.01 --T 3 --dt 0.05
or, from another script, bars(...) then run(...).
"""
import argparse
import os
import subprocess
import tempfile

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla


def bars_mesh(path, lengths=(10.0, 10.0), height=1.0, size=0.5):
    """Two bars end to end and touching at X1 = 0: body 1 on [-L1, 0] x [0, h], body 2 on [0, L2] x [0, h],
    each its own points (the touching ends are not shared), the touching ends labelled 1 (the contact
    boundary), the rest 2. Meshed with gmsh (MSH 2.2) into path."""
    l1, l2 = lengths
    pts = [(-l1, 0), (0, 0), (0, height), (-l1, height), (0, 0), (l2, 0), (l2, height), (0, height)]
    geo = "Geometry.AutoCoherence=0;" + "".join(f"Point({i + 1})={{{x},{y},0,{size}}};" for i, (x, y) in enumerate(pts))
    geo += ("Line(1)={1,2};Line(2)={2,3};Line(3)={3,4};Line(4)={4,1};Line(5)={5,6};Line(6)={6,7};Line(7)={7,8};"
            "Line(8)={8,5};Curve Loop(1)={1,2,3,4};Plane Surface(1)={1};Curve Loop(2)={5,6,7,8};Plane Surface(2)={2};"
            "Physical Surface(1)={1};Physical Surface(2)={2};Physical Curve(1)={2,8};Physical Curve(2)={1,3,4,5,6,7};\n")
    return gmsh_mesh(path, geo)


def gmsh_mesh(path, geo):
    """gmsh -2 of the .geo text geo (written beside path) into path, MSH 2.2; returns path."""
    geo_path = str(path)[:-4] + ".geo"
    with open(geo_path, "w") as f:
        f.write(geo)
    subprocess.run(["gmsh", "-2", "-format", "msh22", geo_path, "-o", str(path)], check=True, capture_output=True)
    return path


def blocks_mesh(path, sizes=(1 / 3, 1 / 4)):
    """The contact patch test's two blocks (Taylor and Papadopoulos 1991): body 2 on [0, 1] x [0, 1] (element size
    sizes[1]), body 1 on [0, 1] x [1, 2] (sizes[0]), non-matching on their common side X2 = 1 (labelled 1, the
    contact boundary); body 2's bottom labelled 3 (on rollers), body 1's top 4 (the pressure), the sides 2."""
    s1, s2 = sizes
    pts = [(0, 1, s1), (1, 1, s1), (1, 2, s1), (0, 2, s1), (0, 0, s2), (1, 0, s2), (1, 1, s2), (0, 1, s2)]
    geo = "Geometry.AutoCoherence=0;" + "".join(f"Point({i + 1})={{{x},{y},0,{h}}};" for i, (x, y, h) in enumerate(pts))
    geo += ("Line(1)={1,2};Line(2)={2,3};Line(3)={3,4};Line(4)={4,1};Line(5)={5,6};Line(6)={6,7};Line(7)={7,8};"
            "Line(8)={8,5};Curve Loop(1)={1,2,3,4};Plane Surface(1)={1};Curve Loop(2)={5,6,7,8};Plane Surface(2)={2};"
            "Physical Surface(1)={1};Physical Surface(2)={2};Physical Curve(1)={1,7};Physical Curve(2)={2,4,6,8};"
            "Physical Curve(3)={5};Physical Curve(4)={3};\n")
    return gmsh_mesh(path, geo)


def read_bodies(path, contact_label=1):
    """The MSH 2.2 file's bodies: (X (nodes x 2), triangles (node indices; a triangle's physical tag is its body),
    contact edges (node index pairs: the lines of physical tag contact_label), body of each node, and every labelled
    line's edges by label: {label: [(node, node), ...]}). A node of several bodies' triangles is doubled."""
    with open(path) as f:
        lines = [line.strip() for line in f]
    k = lines.index("$Nodes")
    n = int(lines[k + 1])
    ids, coords = [], []
    for line in lines[k + 2:k + 2 + n]:
        p = line.split()
        ids.append(int(p[0]))
        coords.append((float(p[1]), float(p[2])))
    k = lines.index("$Elements")
    triangles, edges = [], []
    for line in lines[k + 2:k + 2 + int(lines[k + 1])]:
        p = [int(x) for x in line.split()]
        kind, tags = p[1], p[3:3 + p[2]]
        if kind == 2:
            triangles.append((tags[0], p[-3:]))
        elif kind == 1:
            edges.append((tags[0], p[-2:]))
    index = {}                                  # (body, gmsh node id) -> node
    X, node_body = [], []
    position = dict(zip(ids, coords))

    def node(body, gid):
        if (body, gid) not in index:
            index[(body, gid)] = len(X)
            X.append(position[gid])
            node_body.append(body)
        return index[(body, gid)]
    tris = np.array([[node(b, g) for g in t] for b, t in triangles])
    # a contact edge belongs to the body whose triangle has both its nodes
    owner = {}
    for b, t in triangles:
        for i in range(3):
            owner.setdefault(frozenset((t[i], t[(i + 1) % 3])), set()).add(b)
    by_label = {}
    for label, (a, b) in edges:
        for body in owner[frozenset((a, b))]:
            by_label.setdefault(label, []).append((node(body, a), node(body, b)))
    return np.array(X), tris, np.array(by_label[contact_label]), np.array(node_body), by_label


def assemble(X, tris, lam, mu, rho):
    """P1 plane-strain K and consistent M on dofs (2 i, 2 i + 1)."""
    n = 2 * len(X)
    rows, cols, kv, mv = [], [], [], []
    for t in tris:
        x, y = X[t, 0], X[t, 1]
        area = 0.5 * ((x[1] - x[0]) * (y[2] - y[0]) - (x[2] - x[0]) * (y[1] - y[0]))
        b = np.array([y[1] - y[2], y[2] - y[0], y[0] - y[1]]) / (2 * area)
        c = np.array([x[2] - x[1], x[0] - x[2], x[1] - x[0]]) / (2 * area)
        B = np.zeros((3, 6))
        B[0, 0::2], B[1, 1::2], B[2, 0::2], B[2, 1::2] = b, c, c, b
        D = np.array([[lam + 2 * mu, lam, 0], [lam, lam + 2 * mu, 0], [0, 0, mu]])
        ke = area * B.T @ D @ B
        me = np.zeros((6, 6))
        for i in range(3):
            for j in range(3):
                me[2 * i, 2 * j] = me[2 * i + 1, 2 * j + 1] = rho * area / 12 * (2 if i == j else 1)
        dofs = np.ravel([[2 * i, 2 * i + 1] for i in t])
        rows.extend(np.repeat(dofs, 6))
        cols.extend(np.tile(dofs, 6))
        kv.extend(ke.ravel())
        mv.extend(me.ravel())
    K = sp.csc_matrix((kv, (rows, cols)), shape=(n, n))
    M = sp.csc_matrix((mv, (rows, cols)), shape=(n, n))
    return K, M


def outward_normal(X, tris, edge):
    """The outward unit normal of a boundary edge (a, b) of its body (the triangle's third node is inside)."""
    a, b = edge
    for t in tris:
        if a in t and b in t:
            inside = [i for i in t if i != a and i != b][0]
            break
    d = X[b] - X[a]
    n = np.array([d[1], -d[0]]) / np.hypot(*d)
    return n if n @ (X[inside] - X[a]) < 0 else -n


def closest(point, segments):
    """The closest point of the segments (list of (a, b, xa, xb)) to point: (index, xi)."""
    best = (np.inf, 0, 0.0)
    for k, (_, _, xa, xb) in enumerate(segments):
        d = xb - xa
        xi = min(1.0, max(0.0, float((point - xa) @ d / (d @ d))))
        dist = np.hypot(*(point - xa - xi * d))
        if dist < best[0] - 1e-14:
            best = (dist, k, xi)
    return best[1], best[2]


def contact_rows(X, tris, contact, node_body, x):
    """The rows of the gap between bodies about the configuration X + x: slave nodes of body 1 against body 2's
    segments; returns (G, h), the constraint G y <= h for y = u^{n+1} (-g <= 0)."""
    current = X + x.reshape(-1, 2)
    slaves = sorted({i for e in contact for i in e if node_body[i] == 1})
    masters = [e for e in contact if node_body[e[0]] == 2]
    normals = [outward_normal(current, tris, e) for e in masters]
    segments = [(a, b, current[a], current[b]) for a, b in masters]
    n_dofs = 2 * len(X)
    G = np.zeros((len(slaves), n_dofs))
    h = np.zeros(len(slaves))
    for r, s in enumerate(slaves):
        k, xi = closest(current[s], segments)
        a, b = masters[k]
        nrm = normals[k]
        # g(y) = (X_s + y_s - (1 - xi)(X_a + y_a) - xi (X_b + y_b)) . n >= 0  <=>  -n.(y_s - ...) <= n.(X_s - ...)
        for node, w in ((s, 1.0), (a, -(1 - xi)), (b, -xi)):
            G[r, 2 * node:2 * node + 2] -= w * nrm
        h[r] = nrm @ (X[s] - (1 - xi) * X[a] - xi * X[b])
    return G, h


def contact_rows_mortar(X, tris, contact, node_body, x, dual=False):
    """The mortar rows (segment to segment) of the gap between bodies about X + x: for each contact node j of body
    1, the weighted gap  int_{Gamma_1} N_j (x_1 - x_2(pi)) . n ds >= 0  over body 1's contact segments, x_2(pi)
    the closest point of body 2's segment and n its outward normal, by 3-point Gauss quadrature on each piece of a
    body-1 segment that a body-2 segment covers. Its coefficients sum to the same int N_j n on both bodies, so the
    forces are equal and opposite; a uniform pressure p has the multipliers lm_j = p (the patch test). Returns (G,
    h) as contact_rows, the constraint G y <= h (-weighted gap <= 0)."""
    current = X + x.reshape(-1, 2)
    slave_edges = [e for e in contact if node_body[e[0]] == 1]
    slaves = sorted({i for e in slave_edges for i in e})
    row = {s: r for r, s in enumerate(slaves)}
    masters = [e for e in contact if node_body[e[0]] == 2]
    normals = [outward_normal(current, tris, e) for e in masters]
    G = np.zeros((len(slaves), 2 * len(X)))
    h = np.zeros(len(slaves))
    gauss = ((0.5 - np.sqrt(0.15), 5 / 18), (0.5, 8 / 18), (0.5 + np.sqrt(0.15), 5 / 18))
    for sa, sb in slave_edges:
        xa, xb = current[sa], current[sb]
        d = xb - xa
        length = np.hypot(*d)
        for (ma, mb), nrm in zip(masters, normals):
            ya, yb = current[ma], current[mb]
            # the master segment's ends projected onto the slave segment (its parameter s), clipped to [0, 1]
            s0, s1 = sorted(float((y - xa) @ d / (d @ d)) for y in (ya, yb))
            s0, s1 = max(s0, 0.0), min(s1, 1.0)
            if s1 - s0 <= 1e-14:
                continue
            e = yb - ya
            for q, w in gauss:
                sq = s0 + (s1 - s0) * q
                point = xa + sq * d
                eta = min(1.0, max(0.0, float((point - ya) @ e / (e @ e))))
                weight = w * (s1 - s0) * length
                gap = float(((X[sa] + sq * (X[sb] - X[sa])) - (X[ma] + eta * (X[mb] - X[ma]))) @ nrm)
                # (dual: the biorthogonal multipliers 2 N_a - N_b, 2 N_b - N_a, whose slave block is diagonal)
                tests = ((sa, 2 - 3 * sq), (sb, 3 * sq - 1)) if dual else ((sa, 1 - sq), (sb, sq))
                for j, nj in tests:
                    r = row[j]
                    for k, nk in ((sa, 1 - sq), (sb, sq)):
                        G[r, 2 * k:2 * k + 2] -= weight * nj * nk * nrm
                    for m, nm in ((ma, 1 - eta), (mb, eta)):
                        G[r, 2 * m:2 * m + 2] += weight * nj * nm * nrm
                    h[r] += weight * nj * gap
    return G, h


def rows_of(method):
    """The rows' function of a method: "nts", "mortar" or "dual" (mortar with biorthogonal multipliers)."""
    if method == "nts":
        return contact_rows
    return lambda *a: contact_rows_mortar(*a, dual=(method == "dual"))


def active_set(solve, G, h, x_free, start):
    """min 1/2 y'Ay - L'y under G y <= h, y = x_free - A^-1 G' lm: the primal-dual active set on S = G A^-1 G'."""
    S = G @ np.column_stack([solve(g) for g in G]) if len(G) else np.zeros((0, 0))
    r = G @ x_free - h
    active = start.copy()
    lm = np.zeros(len(h))
    for _ in range(100):
        lm[:] = 0
        idx = np.nonzero(active)[0]
        if len(idx):
            lm[idx] = np.linalg.solve(S[np.ix_(idx, idx)], r[idx])
        w = S @ lm - r                             # the gaps h - G y
        new = (active & (lm > 0)) | ((~active) & (w < -1e-14 * max(1.0, np.abs(h).max(initial=1))))
        if np.array_equal(new, active):
            break
        active = new
    return lm, active


def run(X, tris, contact, node_body, lam, mu, rho, v0, T, dt, method="nts"):
    """Bodies 1 and 2 approaching each other at +v0 and -v0 along X1, from rest shape, the rows of method (rows_of);
    returns the history."""
    rows = rows_of(method)
    K, M = assemble(X, tris, lam, mu, rho)
    A = (2 / dt ** 2) * M + 0.5 * K
    lu = spla.splu(A.tocsc())
    n = 2 * len(X)
    u = np.zeros(n)
    v = np.zeros(n)
    v[0::2] = np.where(node_body == 1, v0, -v0)
    ex, ey = np.zeros(n), np.zeros(n)
    ex[0::2], ey[1::2] = 1, 1
    body_x = [np.where(np.repeat(node_body, 2) == b, ex, 0) for b in (1, 2)]
    body_mass = [float(bx @ (M @ bx)) for bx in body_x]
    steps = int(round(T / dt))
    hist = {k: [] for k in ("t", "momentum_x", "momentum_y", "energy", "contact_force", "max_penetration",
                            "body1_v1_mean", "body2_v1_mean", "relinearisations")}
    active = None
    for step in range(1, steps + 1):
        L = (2 / dt ** 2) * (M @ (u + dt * v)) - 0.5 * (K @ u)
        x_free = lu.solve(L)
        G, h = rows(X, tris, contact, node_body, u)
        rounds = 0
        while True:
            if active is None or len(active) != len(h):
                active = np.zeros(len(h), bool)
            lm, active = active_set(lu.solve, G, h, x_free, active)
            x = x_free - lu.solve(G.T @ lm) if len(lm) else x_free
            G_true, h_true = rows(X, tris, contact, node_body, x)
            rounds += 1
            # the rows about the result are the step's own (to 1e-13): the true gap holds at its end
            if (np.abs(G_true - G).max(initial=0) <= 1e-13 * np.abs(G).max(initial=1)
                    and np.abs(h_true - h).max(initial=0) <= 1e-13 * max(1.0, np.abs(h).max(initial=0))) or rounds == 20:
                break
            G, h = G_true, h_true
        v = 2 * (x - u) / dt - v
        u = x
        hist["t"].append(step * dt)
        hist["momentum_x"].append(float(ex @ (M @ v)))
        hist["momentum_y"].append(float(ey @ (M @ v)))
        hist["energy"].append(0.5 * float(v @ (M @ v)) + 0.5 * float(u @ (K @ u)))
        force = -(G.T @ lm) if len(lm) else np.zeros(n)      # (the contact forces on every dof: A x = L - G' lm)
        on_body2 = force * np.repeat(node_body == 2, 2)
        hist["contact_force"].append(float(np.hypot(on_body2[0::2].sum(), on_body2[1::2].sum())))
        # the true gap at every contact node of body 1 (node to segment, whatever the method's rows)
        G_nodes, h_nodes = (G_true, h_true) if method == "nts" else contact_rows(X, tris, contact, node_body, u)
        hist["max_penetration"].append(float(max(0.0, (G_nodes @ u - h_nodes).max(initial=0.0))))
        for b in (1, 2):
            hist[f"body{b}_v1_mean"].append(float(body_x[b - 1] @ (M @ v)) / body_mass[b - 1])
        hist["relinearisations"].append(rounds)
    return {k: np.array(val) for k, val in hist.items()}


def press(X, tris, contact, node_body, by_label, lam, mu, pressure, method="nts"):
    """The static contact patch test: the blocks of blocks_mesh, body 2's bottom on rollers (label 3: u2 = 0),
    one node of each body held in X1 (its leftmost lowest), the pressure on body 1's top (label 4); K u = F under
    the rows, by the KKT system of the active rows (every row, then those with a negative multiplier dropped).
    Returns (u, the multipliers, the rows' nodes, their pressures: lm_j / (half the adjacent slave segments'
    lengths) for "nts", lm_j itself for "mortar" and "dual")."""
    K, _ = assemble(X, tris, lam, mu, 1.0)
    n = 2 * len(X)
    F = np.zeros(n)
    for a, b in by_label[4]:
        half = 0.5 * np.hypot(*(X[b] - X[a]))
        F[2 * a + 1] -= pressure * half
        F[2 * b + 1] -= pressure * half
    fixed = {2 * i + 1 for e in by_label[3] for i in e}
    for body in (1, 2):
        nodes = np.nonzero(node_body == body)[0]
        fixed.add(2 * int(nodes[np.lexsort((X[nodes, 0], X[nodes, 1]))[0]]))
    free = np.array(sorted(set(range(n)) - fixed))
    G, h = rows_of(method)(X, tris, contact, node_body, np.zeros(n))
    active = np.ones(len(h), bool)
    for _ in range(50):
        Ga = G[active][:, free]
        kkt = sp.bmat([[K[free][:, free], sp.csr_matrix(Ga.T)], [sp.csr_matrix(Ga), None]]).tocsc()
        sol = spla.spsolve(kkt, np.concatenate([F[free], h[active]]))
        lm = np.zeros(len(h))
        lm[active] = sol[len(free):]
        if (lm >= 0).all():
            break
        active &= lm >= 0
    u = np.zeros(n)
    u[free] = sol[:len(free)]
    slaves = sorted({i for e in contact if node_body[e[0]] == 1 for i in e})
    if method == "nts":
        weight = {s: 0.0 for s in slaves}
        for a, b in contact:
            if node_body[a] == 1:
                half = 0.5 * np.hypot(*(X[b] - X[a]))
                weight[a] += half
                weight[b] += half
        pressures = np.array([lm[r] / weight[s] for r, s in enumerate(slaves)])
    else:
        pressures = lm.copy()
    return u, lm, np.array(slaves), pressures


def patch_test(sizes=(1 / 3, 1 / 4), method="nts", lam=30.0, mu=30.0, pressure=1.0):
    """The blocks (body 1's element size sizes[0] above, body 2's sizes[1] below) pressed by the pressure: the
    pressures at body 1's contact nodes (press())."""
    with tempfile.TemporaryDirectory() as d:
        mesh = read_bodies(blocks_mesh(os.path.join(d, "blocks.msh"), sizes))
    return press(*mesh, lam, mu, pressure, method)


def bars(lengths=(10.0, 10.0), size=0.5, mu=50.0, rho=1.0, v0=0.01, T=3.0, dt=0.05, method="nts"):
    """The two bars (lambda = 0: one-dimensional, c = sqrt(2 mu / rho)) approaching at +-v0: the history."""
    with tempfile.TemporaryDirectory() as d:
        mesh = read_bodies(bars_mesh(os.path.join(d, "bars.msh"), lengths, 1.0, size))
    return run(*mesh[:4], 0.0, mu, rho, v0, T, dt, method)


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--lengths", default="10,10")
    ap.add_argument("--size", type=float, default=0.5)
    ap.add_argument("--v0", type=float, default=0.01)
    ap.add_argument("--T", type=float, default=3.0)
    ap.add_argument("--dt", type=float, default=0.05)
    ap.add_argument("--method", choices=("nts", "mortar", "dual"), default="dual")
    a = ap.parse_args()
    h = bars(tuple(float(x) for x in a.lengths.split(",")), a.size, v0=a.v0, T=a.T, dt=a.dt, method=a.method)
    keys = list(h)
    print(",".join(keys))
    for i in range(len(h["t"])):
        print(",".join(f"{h[k][i]:.12g}" for k in keys))
