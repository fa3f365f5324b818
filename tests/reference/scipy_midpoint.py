#!/usr/bin/python3
"""An independent numpy + scipy implementation of the 3D mid-point scheme (1)-(2) of Murea (2023) with the
linearised obstacle constraint (10), each step's QP (4) solved exactly by the primal-dual active-set
iteration of edp/lib/contact/active_set.idp (solveStepActiveSet): a benchmark reference for, and a cross-check
of, the FreeFEM driver (edp/contact.edp with -solver activeset, -mass consistent, -material linear,
-scheme midpoint, -skip_free 1) on the scene `ball` (docs/3d.md) or any ball-like P1 tetrahedral body over
the flat, fixed foundation X3 = 0.

The discretisation, exactly as the driver's:
  - P1 Lagrange vector displacement on the tetrahedra of a gmsh MSH 2.2 mesh (element type 4; boundary
    triangles, type 2, with physical tag 1 are Gamma_C), only the vertices used by tetrahedra kept;
  - consistent mass M (int rho u.w, the exact P1 element mass), stiffness K of
    lambda div u div w + 2 mu eps(u):eps(w), load F = int f.w, f = (0, 0, fz) per unit volume;
  - A = 2 M / dt^2 + K / 2, factorised once (SuperLU, scipy.sparse.linalg.splu);
  - step n -> n+1: L = (2 / dt^2) M (u + dt v) - K u / 2 + F, x_free = A^-1 L; the contact nodes are the
    vertices of Gamma_C's triangles (its closure), constraint (10) on the flat X3 = 0 is
    -x3_j <= X3_j (rows C: -1 at the X3 dof, g_j = X3_j); x = x_free when C x_free <= g (and the active set
    is then emptied, as the driver's skip_free branch does), else the QP min 1/2 x'Ax - L'x s.t. Cx <= g by the
    active set on S = C A^-1 C' (columns computed when a node first enters the set, cached for the run;
    S_jj = 1 for unknown columns), warm-started from the previous step's set, x = x_free - A^-1 C' lm;
  - v^{n+1} = 2 (x - u^n) / dt - v^n, u^{n+1} = x; u^0 = (0, 0, u0z), v^0 = 0;
  - history: u3 at the reference node (the vertex of Gamma_C with the smallest X3, ties towards the axis
    X1 = X2 = 0: the ball's lowest point (0, 0, 0)), the energy E = v'Mv / 2 + u'Ku / 2 (material/interface.idp,
    discreteEnergy), the modified energy E - F'u (io/history.idp), the active nodes
    (lm_j > 1e-6 int_{Gamma_C} phi_j, contact/rows.idp countActive) and whether the step solved the QP.

Use: /usr/bin/python3 tests/reference/scipy_midpoint.py --mesh meshes/ball.msh --T 120 --dt 0.05 --out history.csv
or, from another script, run(mesh, T, dt, ...) (returns the history arrays and the timings).
"""
import argparse
import csv
import json
import sys
import time

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

# the scene `ball` (edp/scenes/ball.idp and the driver's defaults)
BALL = dict(rho=1.0, lam=30.0, mu=30.0, fz=-0.1, u0z=4.0, dt=0.05, T=120.0)
HISTORY_COLUMNS = ("step", "t", "u3_low", "energy", "active_nodes", "qp_solved")
ACTIVE_PRESSURE = 1e-6          # contact/rows.idp: a node is active when lm_j > 1e-6 int_{Gamma_C} phi_j
MAX_ACTIVE_SET_ITERATIONS = 100  # contact/active_set.idp, activeSetMaxIterations


# ---- mesh

def read_msh22(path, contact_label=1):
    """A gmsh MSH 2.2 (ASCII) mesh: (vertices (nv, 3), tetrahedra (nt, 4), Gamma_C triangles (nc, 3)),
    numbered over the vertices used by tetrahedra, in file order."""
    with open(path) as f:
        lines = f.read().split("\n")
    k = lines.index("$MeshFormat")
    if not lines[k + 1].split()[0].startswith("2.") or lines[k + 1].split()[1] != "0":
        raise ValueError(f"{path}: not an ASCII MSH 2.x file")
    k = lines.index("$Nodes")
    nn = int(lines[k + 1])
    nodes = np.array(" ".join(lines[k + 2:k + 2 + nn]).split(), dtype=float).reshape(nn, 4)
    tags = nodes[:, 0].astype(np.int64)
    xyz = nodes[:, 1:]
    k = lines.index("$Elements")
    ne = int(lines[k + 1])
    tets, tris = [], []
    for line in lines[k + 2:k + 2 + ne]:
        p = line.split()
        etype, ntags = int(p[1]), int(p[2])
        if etype == 4:
            tets.append(p[3 + ntags:7 + ntags])
        elif etype == 2 and int(p[3]) == contact_label:      # the first tag is the physical one
            tris.append(p[3 + ntags:6 + ntags])
    if not tets:
        raise ValueError(f"{path}: no tetrahedra (element type 4)")
    index = np.full(tags.max() + 1, -1, dtype=np.int64)
    index[tags] = np.arange(nn)
    tets = index[np.array(tets, dtype=np.int64)]
    tris = index[np.array(tris, dtype=np.int64).reshape(-1, 3)]
    used = np.zeros(nn, dtype=bool)
    used[tets.ravel()] = True
    if not used.all():        # keep only the vertices of the tetrahedra (FreeFEM's mesh3 has no others)
        renumber = np.full(nn, -1, dtype=np.int64)
        renumber[used] = np.arange(used.sum())
        xyz, tets, tris = xyz[used], renumber[tets], renumber[tris]
        if (tris < 0).any():
            raise ValueError(f"{path}: a Gamma_C triangle has a vertex that is on no tetrahedron")
    return xyz, tets, tris


# ---- assembly (vectorised over the elements; COO -> CSR)

def assemble(xyz, tets, rho, lam, mu, fz):
    """M, K (CSR, dofs interleaved: 3 i + c for vertex i, component c) and F."""
    nv, nt = len(xyz), len(tets)
    P = np.ones((nt, 4, 4))
    P[:, :, 1:] = xyz[tets]                                    # rows [1, x_i, y_i, z_i]
    det = np.linalg.det(P)                                    # 6 x the signed volume
    vol = np.abs(det) / 6
    if (vol <= 0).any():
        raise ValueError("a degenerate tetrahedron")
    G = np.linalg.inv(P)[:, 1:, :]                            # G[e, a, i] = d lambda_i / d x_a
    # stiffness: K_(ia),(jb) = vol (lam g_i[a] g_j[b] + mu (delta_ab g_i.g_j + g_i[b] g_j[a]))
    gg = np.einsum("eai,eaj->eij", G, G)                       # g_i . g_j
    Ke = (lam * np.einsum("eai,ebj->eiajb", G, G)
          + mu * np.einsum("ebi,eaj->eiajb", G, G)
          + mu * np.einsum("eij,ab->eiajb", gg, np.eye(3)))
    Ke *= vol[:, None, None, None, None]
    dofs = (3 * tets[:, :, None] + np.arange(3)).reshape(nt, 12)   # element dof (i, a) -> 3 tets[e, i] + a
    rows = np.repeat(dofs, 12, axis=1).ravel()
    cols = np.tile(dofs, (1, 12)).ravel()
    n = 3 * nv
    K = sp.coo_matrix((Ke.reshape(nt, 144).ravel(), (rows, cols)), shape=(n, n)).tocsr()
    # consistent mass: rho vol / 20 (1 + delta_ij) per component
    me = (np.ones((4, 4)) + np.eye(4)) / 20
    Me = np.einsum("e,ij,ab->eiajb", rho * vol, me, np.eye(3))
    M = sp.coo_matrix((Me.reshape(nt, 144).ravel(), (rows, cols)), shape=(n, n)).tocsr()
    # load: fz vol / 4 at each vertex's X3 dof
    F = np.zeros(n)
    np.add.at(F, 3 * tets[:, :].ravel() + 2, np.repeat(fz * vol / 4, 4))
    return M, K, F


def contact_weights(xyz, tris):
    """int_{Gamma_C} phi_j at every vertex (body/forms.idp, vContactWeight): a third of each triangle's area."""
    a, b, c = (xyz[tris[:, i]] for i in range(3))
    area = 0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1)
    w = np.zeros(len(xyz))
    np.add.at(w, tris.ravel(), np.repeat(area / 3, 3))
    return w


def reference_vertex(xyz, contact):
    """body/space.idp: the vertex of Gamma_C with the smallest X3, ties (1e-9 of the size) broken towards the axis."""
    size = max(1.0, np.ptp(xyz, axis=0).max())
    tie = 1e-9 * size
    low = xyz[contact, 2].min()
    axis = np.sqrt(xyz[:, 0] * xyz[:, 0] + xyz[:, 1] * xyz[:, 1])
    ref = -1
    for s in contact:
        if xyz[s, 2] <= low + tie and (ref < 0 or axis[s] < axis[ref] - tie):
            ref = s
    return ref


# ---- the run

def run(mesh, T=BALL["T"], dt=BALL["dt"], rho=BALL["rho"], lam=BALL["lam"], mu=BALL["mu"], fz=BALL["fz"],
        u0z=BALL["u0z"], permc_spec="MMD_AT_PLUS_A", symmetric=True, contact_label=1, strategy="gathered",
        cg_tol=1e-12):
    """The scheme from u^0 = (0, 0, u0z), v^0 = 0 to T on the flat foundation X3 = 0. Returns a dict: the
    history arrays (step, t, u3_low, energy, modified_energy, active_nodes, qp_solved, active_set_iterations),
    the sizes (vertices, dofs, contact_nodes, reference_vertex), the Schur columns computed, and the timings
    (read_seconds, setup_seconds = assembly + factorisation, loop_seconds, ms_per_step: wall clock,
    time.perf_counter; setup_cpu_seconds, loop_cpu_seconds, cpu_ms_per_step: this process's CPU time, which a
    busy machine disturbs less) and the solves with A in the time loop (solves: one a step, one more a QP step,
    one a Schur column).
    SuperLU's options: A is symmetric positive definite, so by default (symmetric=True) the factorisation
    keeps the symmetric ordering of A + A' (permc_spec MMD_AT_PLUS_A) with diagonal pivots (SymmetricMode,
    diag_pivot_thresh 0); symmetric=False, permc_spec="COLAMD" is splu's own default (more fill: slower
    solves on the ball's meshes).
    strategy: how the QP's active set gets its Schur products (docs/parallel.md). "gathered" (the driver's): S's
    columns, one solve with A each, computed as nodes first enter the set and cached for the run. "matrix-free":
    S is never formed; each active-set iteration solves S_aa lm_a = r_a by conjugate gradients to cg_tol
    (relative residual), one solve with A a product S p = P_z' A^-1 P_z p, warm-started from the previous lm;
    y = A^-1 P_z lm is accumulated along CG (one more solve only when the warm start drops a node), so
    w = y[zd] - r and x = x_free + y need none; the update keeps lm_j > 0 on the set and w_j < 0 off it (the
    gathered rule lm_j - w_j / S_jj > 0 with w_a = 0). Both count their solves (solves, by_purpose)."""
    t0 = time.perf_counter()
    xyz, tets, tris = read_msh22(mesh, contact_label)
    t1, c1_cpu = time.perf_counter(), time.process_time()
    M, K, F = assemble(xyz, tets, rho, lam, mu, fz)
    A = ((2.0 / dt**2) * M + 0.5 * K).tocsc()
    if symmetric:
        lu = spla.splu(A, permc_spec=permc_spec, diag_pivot_thresh=0.0, options=dict(SymmetricMode=True))
    else:
        lu = spla.splu(A, permc_spec=permc_spec)
    t2, c2_cpu = time.perf_counter(), time.process_time()

    nv, n = len(xyz), 3 * len(xyz)
    contact = np.unique(tris.ravel())                          # the closure of Gamma_C, in vertex order
    nc = len(contact)
    zd = 3 * contact + 2                                       # their X3 dofs: C = -P_z'
    g = xyz[contact, 2].copy()                                 # X3_j - psi, psi = 0
    active_threshold = ACTIVE_PRESSURE * contact_weights(xyz, tris)[contact]
    ref = reference_vertex(xyz, contact)
    kkt_tol = 1e-9 * max(1.0, np.abs(g).max())

    # S = C A^-1 C' = P_z' A^-1 P_z: its known columns, S_jj = 1 for the others (contact/active_set.idp)
    S = np.zeros((nc, nc))
    S_diag = np.ones(nc)
    known = np.zeros(nc, dtype=bool)
    columns = 0
    if strategy not in ("gathered", "matrix-free"):
        raise ValueError(f"strategy must be gathered or matrix-free; got {strategy!r}")
    by_purpose = {}
    cg_max = 0

    def solve(b, purpose):
        """A^-1 b, counted (one solve per right-hand side)."""
        by_purpose[purpose] = by_purpose.get(purpose, 0) + (1 if b.ndim == 1 else b.shape[1])
        return lu.solve(b)

    def add_columns(mask):
        nonlocal columns
        new = np.flatnonzero(mask & ~known)
        if len(new) == 0:
            return
        E = np.zeros((n, len(new)))
        E[zd[new], np.arange(len(new))] = 1.0
        Z = solve(E, "schur_columns")                          # one solve per column
        S[:, new] = Z[zd, :]
        S_diag[new] = S[new, new]
        known[new] = True
        columns += len(new)

    def schur_cg(a, rhs, lm0, y0):
        """matrix-free: CG on S_aa lm_a = rhs from lm0 (zero off a; y0 = A^-1 P_z lm0); returns lm, y."""
        nonlocal cg_max
        lm, y = lm0.copy(), y0.copy()
        res = rhs - y[zd[a]]
        p = res.copy()
        rr, tol2 = res.dot(res), (cg_tol * np.linalg.norm(rhs)) ** 2
        its, b = 0, np.zeros(n)
        while rr > tol2:
            its += 1
            if its > 10 * len(a) + 100:
                raise RuntimeError("the matrix-free active set's CG did not converge")
            b[zd[a]] = p
            z = solve(b, "cg_products")                        # S_aa p = z[zd[a]]
            q = z[zd[a]]
            alpha = rr / p.dot(q)
            lm[a] += alpha * p
            y += alpha * z
            res -= alpha * q
            rr_new = res.dot(res)
            p = res + (rr_new / rr) * p
            rr = rr_new
        cg_max = max(cg_max, its)
        return lm, y

    u = np.zeros(n)
    u[2::3] = u0z
    v = np.zeros(n)
    steps = int(round(T / dt))
    hist = {k: np.zeros(steps + 1) for k in ("step", "t", "u3_low", "energy", "modified_energy",
                                             "active_nodes", "qp_solved", "active_set_iterations")}

    def record(k, t, lm, qp, its):
        E = 0.5 * v.dot(M @ v) + 0.5 * u.dot(K @ u)
        hist["step"][k], hist["t"][k], hist["u3_low"][k] = k, t, u[3 * ref + 2]
        hist["energy"][k], hist["modified_energy"][k] = E, E - F.dot(u)
        hist["active_nodes"][k] = np.count_nonzero(lm > active_threshold)
        hist["qp_solved"][k], hist["active_set_iterations"][k] = qp, its

    # one iteration of the active set: lm on the set (zero off it), w = S lm - r, and the next set
    def gathered_iteration(active, r, lm):
        lm = np.zeros(nc)
        a = np.flatnonzero(active)
        if len(a):
            add_columns(active)
            lm[a] = np.linalg.solve(S[np.ix_(a, a)], r[a])
            w = S[:, a] @ lm[a] - r                            # (lm = 0 off the set)
        else:
            w = -r
        return lm, lm - w / S_diag > 0

    def gathered_correction(lm):
        f[zd] = -lm                                            # C' lm
        return -solve(f, "correction")

    def matrix_free_iteration(active, r, lm):
        nonlocal y
        a = np.flatnonzero(active)
        if len(a):
            lm0 = np.zeros(nc)
            lm0[a] = lm[a]
            if np.any(lm0 != lm):                              # the warm start drops a node: its image costs a solve
                b = np.zeros(n)
                b[zd] = lm0
                y = solve(b, "warm_start")
            lm, y = schur_cg(a, r[a], lm0, y)
            w = y[zd] - r
        else:
            lm, y[:] = np.zeros(nc), 0.0
            w = -r
        return lm, np.where(active, lm > 0, w < 0)

    def matrix_free_correction(lm):
        return y                                               # A^-1 P_z lm, accumulated along CG

    iteration, correction = ((gathered_iteration, gathered_correction) if strategy == "gathered"
                             else (matrix_free_iteration, matrix_free_correction))

    def check_kkt(k, x, lm):
        gap = g + x[zd]                                        # g - C x
        if (gap.min() < -kkt_tol or lm.min() < 0
                or np.abs(lm * gap).max() > kkt_tol * max(1.0, np.abs(lm).max())):
            raise RuntimeError(f"step {k}: the solution fails the KKT check of (10)")

    active = np.zeros(nc, dtype=bool)
    lm = np.zeros(nc)
    y = np.zeros(n)                                            # matrix-free: A^-1 P_z lm
    record(0, 0.0, lm, 0, 0)
    c1 = 2.0 / dt**2
    f = np.zeros(n)
    t3, c3_cpu = time.perf_counter(), time.process_time()
    for k in range(1, steps + 1):
        L = c1 * (M @ (u + dt * v)) - 0.5 * (K @ u) + F
        x = solve(L, "predictor")                              # the free predictor
        r = -x[zd] - g                                         # C x_free - g
        qp, its = 0, 0
        if r.max() <= 0:
            lm = np.zeros(nc)
            y[:] = 0.0
            active[:] = False                                  # (10) holds: the predictor solves (4)
        else:
            qp = 1
            changed = True
            while changed and its < MAX_ACTIVE_SET_ITERATIONS:
                its += 1
                lm, new = iteration(active, r, lm)
                changed = bool((new != active).any())
                active = new
            if changed:
                raise RuntimeError(f"step {k}: the active set did not settle in {MAX_ACTIVE_SET_ITERATIONS} iterations")
            x += correction(lm)                                # x_free - A^-1 C' lm
            check_kkt(k, x, lm)
        v = (2.0 / dt) * (x - u) - v
        u = x
        record(k, k * dt, lm, qp, its)
    t4, c4_cpu = time.perf_counter(), time.process_time()
    return dict(history=hist, vertices=nv, tetrahedra=len(tets), dofs=n, contact_nodes=nc, reference_vertex=ref,
                reference_xyz=xyz[ref].tolist(), steps=steps, qp_steps=int(hist["qp_solved"].sum()),
                schur_columns=columns, active_set_iterations=int(hist["active_set_iterations"].sum()),
                lu_nnz=lu.L.nnz + lu.U.nnz, read_seconds=t1 - t0, setup_seconds=t2 - t1, loop_seconds=t4 - t3,
                ms_per_step=1e3 * (t4 - t3) / max(steps, 1), setup_cpu_seconds=c2_cpu - c1_cpu,
                loop_cpu_seconds=c4_cpu - c3_cpu, cpu_ms_per_step=1e3 * (c4_cpu - c3_cpu) / max(steps, 1),
                solves=sum(by_purpose.values()), solves_by_purpose=by_purpose, strategy=strategy,
                cg_max_iterations=cg_max)


def write_history(path, hist):
    with open(path, "w", newline="") as f:
        out = csv.writer(f)
        out.writerow(HISTORY_COLUMNS)
        for k in range(len(hist["step"])):
            out.writerow([int(hist["step"][k]), repr(float(hist["t"][k])), repr(float(hist["u3_low"][k])),
                          repr(float(hist["energy"][k])), int(hist["active_nodes"][k]), int(hist["qp_solved"][k])])


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--mesh", required=True, help="gmsh MSH 2.2 mesh (tetrahedra; Gamma_C: physical tag 1)")
    p.add_argument("-T", "--T", type=float, default=BALL["T"])
    p.add_argument("--dt", type=float, default=BALL["dt"])
    p.add_argument("--rho", type=float, default=BALL["rho"])
    p.add_argument("--lam", "--lambda", dest="lam", type=float, default=BALL["lam"])
    p.add_argument("--mu", type=float, default=BALL["mu"])
    p.add_argument("--fz", type=float, default=BALL["fz"])
    p.add_argument("--u0z", type=float, default=BALL["u0z"])
    p.add_argument("--permc", default="MMD_AT_PLUS_A", help="SuperLU's column ordering (permc_spec)")
    p.add_argument("--unsymmetric", action="store_true",
                   help="splu without SymmetricMode and diagonal pivoting (with --permc COLAMD: splu's defaults)")
    p.add_argument("--out", help="history CSV (" + ",".join(HISTORY_COLUMNS) + ")")
    p.add_argument("--json", help="the run's sizes and timings as JSON (make bench reads them)")
    a = p.parse_args(argv)
    res = run(a.mesh, T=a.T, dt=a.dt, rho=a.rho, lam=a.lam, mu=a.mu, fz=a.fz, u0z=a.u0z, permc_spec=a.permc,
              symmetric=not a.unsymmetric)
    if a.out:
        write_history(a.out, res["history"])
    if a.json:
        with open(a.json, "w") as fh:
            json.dump({k: val for k, val in res.items() if k != "history"}, fh, indent=1, default=float)
    print(f"vertices {res['vertices']}, dofs {res['dofs']}, contact nodes {res['contact_nodes']}, "
          f"set-up {res['setup_seconds']:.3f} s (assembly + factorisation), steps {res['steps']} "
          f"({res['qp_steps']} QP), {res['ms_per_step']:.3f} ms/step ({res['cpu_ms_per_step']:.3f} ms CPU), "
          f"Schur columns {res['schur_columns']}, {res['solves']} solves, nnz(L+U) {res['lu_nnz']}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
