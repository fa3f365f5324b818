"""`make bench`: cost measured side by side in one run (no timed tests anywhere).

For each case: wall seconds, CPU seconds of the FreeFEM process, peak memory
(max RSS), steps, steps that needed a QP, and milliseconds per step. Then the
ratios asked for:
  - Test 1 with -skip_free 1 (default) against -skip_free 0: same answer, how much faster;
  - -solver activeset against ipopt on Test 1 and Test 2;
  - the cost per step on three meshes of the same disk, for both solvers.
Cases run one at a time, so they do not compete for the 2 cores. Writes
results/bench/bench.md and bench.csv.
"""
import argparse
import os
import subprocess
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from history import read_run  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
RUN = os.path.join(ROOT, "edp", "run.sh")


def run_case(out_base, name, scene, args):
    out = os.path.join(out_base, name)
    t0 = time.perf_counter()
    p = subprocess.Popen([RUN, scene, out, "-progress", "0", "-snapshots", "none"] + args,
                         stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, env=dict(os.environ, FORCE="1"))
    log = p.stdout.read()
    # wait4: this case's own CPU time and peak memory, FreeFEM included (Linux counts reaped descendants)
    _, status, usage = os.wait4(p.pid, 0)
    wall = time.perf_counter() - t0
    if os.waitstatus_to_exitcode(status) != 0:
        sys.exit(f"bench case {name} failed:\n{log}")
    h = read_run(out)
    steps = len(h["t"]) - 1
    return {"case": name, "scene": scene, "args": " ".join(args), "wall_s": wall,
            "cpu_s": usage.ru_utime + usage.ru_stime, "peak_MiB": usage.ru_maxrss / 1024, "steps": steps, "qp_steps": int(h["qp_solved"].sum()),
            "ms_per_step": 1000 * wall / steps, "history": h}


def main():
    p = argparse.ArgumentParser(description=__doc__)
    p.add_argument("--out", default=os.path.join(ROOT, "results", "bench"))
    p.add_argument("--T", default="120", help="horizon of the Test 1 / Test 2 cases")
    a = p.parse_args()
    os.makedirs(a.out, exist_ok=True)
    cases = [
        ("test1 ipopt", "test1", ["-T", a.T]),
        ("test1 ipopt skip_free=0", "test1", ["-T", a.T, "-skip_free", "0"]),
        ("test1 activeset", "test1", ["-T", a.T, "-solver", "activeset"]),
        ("test2 ipopt", "test2", ["-T", a.T, "-t1", "18"]),
        ("test2 activeset", "test2", ["-T", a.T, "-t1", "18", "-solver", "activeset"]),
    ]
    meshes = [("coarse", "meshes/disk_coarse.msh"), ("paper", "meshes/disk.msh"), ("fine", "meshes/disk_fine.msh")]
    for solver in ("ipopt", "activeset"):
        for mesh, path in meshes:
            cases.append((f"test1 {solver} {mesh} mesh T=40", "test1", ["-T", "40", "-mesh", path, "-solver", solver]))
    rows = []
    for name, scene, args in cases:
        print(f"bench: {name} ...", flush=True)
        rows.append(run_case(a.out, name.replace(" ", "_").replace("=", ""), scene, args))
        rows[-1]["case"] = name
    by = {r["case"]: r for r in rows}
    lines = ["| case | wall s | CPU s | peak MiB | steps | QP steps | ms/step |",
             "| --- | ---: | ---: | ---: | ---: | ---: | ---: |"]
    for r in rows:
        lines.append(f"| {r['case']} | {r['wall_s']:.1f} | {r['cpu_s']:.1f} | {r['peak_MiB']:.0f} | {r['steps']} | "
                     f"{r['qp_steps']} | {r['ms_per_step']:.2f} |")

    def u2_gap(x, y):
        return np.abs(by[x]["history"]["u2_low"] - by[y]["history"]["u2_low"]).max()

    def ratio(slow, fast):
        return by[slow]["wall_s"] / by[fast]["wall_s"]

    lines += ["",
              f"- skip_free: -skip_free 1 is {ratio('test1 ipopt skip_free=0', 'test1 ipopt'):.2f}x faster than "
              f"-skip_free 0 on Test 1 (T = {a.T}); max |u2_low difference| {u2_gap('test1 ipopt', 'test1 ipopt skip_free=0'):.2g}",
              f"- activeset against ipopt, Test 1 (T = {a.T}): {ratio('test1 ipopt', 'test1 activeset'):.1f}x less wall time; "
              f"max |u2_low difference| {u2_gap('test1 ipopt', 'test1 activeset'):.2g} (IPOPT's own error at tol 1e-8)",
              f"- activeset against ipopt, Test 2 t1 = 18 (T = {a.T}): {ratio('test2 ipopt', 'test2 activeset'):.1f}x less wall time; "
              f"max |u2_low difference| {u2_gap('test2 ipopt', 'test2 activeset'):.2g}"]
    for solver in ("ipopt", "activeset"):
        c, m, f = (by[f"test1 {solver} {mesh} mesh T=40"] for mesh, _ in meshes)
        lines.append(f"- mesh scaling, {solver} (ms per step, T = 40): coarse (277) {c['ms_per_step']:.2f}, "
                     f"paper (989) {m['ms_per_step']:.2f} ({m['ms_per_step'] / c['ms_per_step']:.1f}x), "
                     f"fine (3750) {f['ms_per_step']:.2f} ({f['ms_per_step'] / m['ms_per_step']:.1f}x)")
    text = "\n".join(lines)
    print(text)
    with open(os.path.join(a.out, "bench.md"), "w") as fh:
        fh.write(text + "\n")
    with open(os.path.join(a.out, "bench.csv"), "w") as fh:
        keys = ["case", "wall_s", "cpu_s", "peak_MiB", "steps", "qp_steps", "ms_per_step"]
        fh.write(",".join(keys) + "\n")
        for r in rows:
            fh.write(",".join(str(r[k]) for k in keys) + "\n")


if __name__ == "__main__":
    main()
