"""`make accuracy`: what accuracy costs in time (work-precision study).

Test 1 to T = 40 (first bounce and the flight after it) over
  dt in {0.2, 0.1, 0.05, 0.025, 0.0125} x meshes {coarse, paper, fine}
  x solvers {IPOPT tol 1e-6, 1e-8, 1e-10, activeset}
(on the fine mesh only activeset at every dt and IPOPT 1e-8 at dt >= 0.05),
plus the twice-refined mesh (refine 4) with activeset at dt <= 0.05, and
Test 2 (t1 = 18) on a smaller grid. The reference solution is the finest
run (refine-4 mesh, dt = 0.0125, activeset). For each run, against it:
  - max and L2-in-time error of u2_low(t), on the times all runs share (t = 0.2 k);
  - error of the first contact interval's start and end;
  - the modified energy lost over the first bounce, and its error;
and the cost: wall and CPU seconds per run and per step, peak memory.
Observed orders: in dt on each mesh (against that mesh's dt = 0.0125 run),
in h at dt = 0.0125 (coarse, paper and fine against the refine-4 mesh).
St Venant-Kirchhoff (-material svk, paper Section 3), on the paper's mesh:
  - the model error, SVK against linear, beside the dt and h errors of the same
    case: (i) Test 1 with the paper's lambda = mu = 30 on t <= 15 only (the SVK
    body collapses at t = 16.8), u2 of the top vertex (0, 40), since u2_low is
    pinned at 0 in contact; (ii) the stiff Test 1 (lambda = mu = 300, no
    collapse) to T = 40, u2_low (it holds the rebound);
  - SVK's observed order in dt (self-convergence: dt = 0.1, 0.05, 0.025 against
    dt = 0.0125) on the spin scene (no contact: the smooth case, error of the
    lowest point's displacement vector) and on the stiff Test 1 (with an impact).
P2 against refining P1 (-order 2; p2.md): Test 1 to T = 40, activeset, at the
h-study's dt = 0.0125, with P1 and with P2 on the coarse, paper, fine, refine-4
and refine-8 meshes, the top vertex (0, 40) as a probe (-probes 0,40). Every run
against P2 on the refine-8 mesh (the most accurate run), on windows:
free fall (t <= 8.8, a rigid motion: round-off), the first contact (8.8 < t <= 24,
top vertex u2, since u2_low is pinned), the flight after it (u2_low) and the whole
run (u2_low, the h-study's measure); wall/CPU seconds and memory of each run;
observed orders in h (h = 1/sqrt(vertices)) per window; for each P2 run, the
cheapest P1 run as accurate. P2 on the paper's mesh at dt = 0.00625 gives the size
of the time error at dt = 0.0125. A run that fails is left out with its error line.
Per method (the methods of make methods, docs/methods.md): Test 1 to T = 40 on the paper's
mesh at dt = 0.1, 0.05, 0.025, 0.0125 (explicit Verlet: 0.01, 0.005, 0.0025), each against
the same method at a 4x smaller dt than its finest (its time error) and against the paper's
method's such run (the model difference), versus wall time; for explicit Verlet the least
wall time of a stable run, T / dt_c steps at its measured cost per step.
The Neo-Hookean body (-material neohookean, nh.md; --nh-only: that part alone, with the linear and
SVK runs it needs), on the paper's mesh: the model differences Neo-Hookean - linear and Neo-Hookean
- SVK at the same dt (0.0125 and 0.05) on the SVK study's two cases (Test 1 on t <= 15, top vertex;
the stiff Test 1 to T = 40), and Neo-Hookean - linear on Test 1 to T = 40 with the paper's body (which
the Neo-Hookean body runs through); its own dt error beside the linear one; its observed order in dt
(dt = 0.1, 0.05, 0.025 against 0.0125) on the spin scene (no contact), the stiff Test 1 and Test 1.
Writes results/accuracy/table.csv, table.md, orders.md, svk.md, nh.md, work_precision.png/pdf,
p2.md, p2_table.csv, p2_work_precision.png/pdf (--p2-only: the P2 part alone), methods.md,
methods_table.csv, methods_work_precision.png/pdf (--methods-only: that part alone).
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import jobs  # noqa: E402
from accuracy_grid import grid_study  # noqa: E402
from accuracy_methods import methods_study  # noqa: E402
from accuracy_nh import nh_study  # noqa: E402
from accuracy_p2 import p2_study  # noqa: E402
from accuracy_svk import svk_study  # noqa: E402
from driver import ROOT  # noqa: E402


def main():
    p = jobs.ArgumentParser(description=__doc__)
    p.add_argument("--out", default=os.path.join(ROOT, "results", "accuracy"))
    p.add_argument("--quick", action="store_true", help="a small grid, to try the script")
    p.add_argument("--reuse", action="store_true",
                   help="rebuild the tables and the plot from the runs and costs already in --out, running only what is missing")
    p.add_argument("--p2-only", action="store_true", help="run only the P2-against-P1 part (p2.md)")
    p.add_argument("--methods-only", action="store_true", help="run only the per-method part (methods.md)")
    p.add_argument("--nh-only", action="store_true", help="run only the Neo-Hookean part (nh.md), with the linear "
                   "and SVK runs it compares with")
    jobs.add_processes_option(p)
    a = p.parse_args()
    jobs.use_processes(a.np)
    os.makedirs(a.out, exist_ok=True)
    # what this invocation rewrites (--quick: only the main tables and figure)
    if a.p2_only or a.methods_only:
        part = "p2" if a.p2_only else "methods"
        stale = [f"{part}.md", f"{part}_work_precision.png", f"{part}_work_precision.pdf"]
    elif a.nh_only:
        stale = ["nh.md"]
    elif a.quick:
        stale = ["table.md", "orders.md", "work_precision.png", "work_precision.pdf"]
    else:
        stale = ["*.md", "*work_precision.png", "*work_precision.pdf"]
    jobs.stop_on_interrupt("make accuracy", a.out, stale)
    if a.p2_only:
        print("\n".join(p2_study(a.out, a.reuse)))
        print(f"written to {a.out}/")
        return
    if a.methods_only:
        print("\n".join(methods_study(a.out, a.reuse)))
        print(f"written to {a.out}/")
        return
    if a.nh_only:
        print("\n".join(nh_study(a.out, a.reuse)))
        print(f"written to {a.out}/")
        return
    md, orders, finest_mesh = grid_study(a.out, a.reuse, a.quick)
    svk_md = []
    if not a.quick:
        svk_md, svk_histories = svk_study(a.out, a.reuse, finest_mesh)
        with open(os.path.join(a.out, "svk.md"), "w") as f:
            f.write("\n".join(svk_md) + "\n")
        svk_md += [""] + nh_study(a.out, a.reuse, svk_histories)
        p2_md = p2_study(a.out, a.reuse)
        p2_md += [""] + methods_study(a.out, a.reuse)
    print("\n".join(md))
    print()
    print("\n".join(orders))
    print()
    print("\n".join(svk_md))
    if not a.quick:
        print()
        print("\n".join(p2_md))
    print(f"written to {a.out}/")


if __name__ == "__main__":
    main()
