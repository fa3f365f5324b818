"""`make bench`: cost measured side by side in one run (no timed tests anywhere).

For each case: wall seconds, CPU seconds of the FreeFEM process, peak memory
(max RSS), steps, steps that needed a QP, and milliseconds per step. Then the
ratios asked for:
  - Test 1 with -skip_free 1 (default) against -skip_free 0: same answer, how much faster;
  - the cost per step on three meshes of the same disk.
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
        ("test1 skip_free=1", "test1", ["-T", a.T]),
        ("test1 skip_free=0", "test1", ["-T", a.T, "-skip_free", "0"]),
        ("test2 t1=18", "test2", ["-T", a.T, "-t1", "18"]),
        ("test1 coarse mesh T=40", "test1", ["-T", "40", "-mesh", "meshes/disk_coarse.msh"]),
        ("test1 paper mesh T=40", "test1", ["-T", "40"]),
        ("test1 fine mesh T=40", "test1", ["-T", "40", "-mesh", "meshes/disk_fine.msh"]),
    ]
    rows = []
    for name, scene, args in cases:
        print(f"bench: {name} ...", flush=True)
        rows.append(run_case(a.out, name.replace(" ", "_").replace("=", ""), scene, args))
        rows[-1]["case"] = name
    by = {r["case"]: r for r in rows}
    lines = ["| case | wall s | CPU s | peak MiB | steps | QP steps | ms/step |", "| --- | ---: | ---: | ---: | ---: | ---: | ---: |"]
    for r in rows:
        lines.append(f"| {r['case']} | {r['wall_s']:.1f} | {r['cpu_s']:.1f} | {r['peak_MiB']:.0f} | {r['steps']} | "
                     f"{r['qp_steps']} | {r['ms_per_step']:.2f} |")
    s1, s0 = by["test1 skip_free=1"], by["test1 skip_free=0"]
    du = np.abs(s1["history"]["u2_low"] - s0["history"]["u2_low"]).max()
    lines += ["", f"skip_free: -skip_free 1 is {s0['wall_s'] / s1['wall_s']:.2f}x faster than -skip_free 0 on Test 1 "
                  f"(T = {a.T}), max |u2_low difference| = {du:.2g}"]
    c, m, f = by["test1 coarse mesh T=40"], by["test1 paper mesh T=40"], by["test1 fine mesh T=40"]
    lines.append("mesh scaling (ms per step, T = 40): coarse {:.2f}, paper {:.2f} ({:.2f}x), fine {:.2f} ({:.2f}x)".format(
        c["ms_per_step"], m["ms_per_step"], m["ms_per_step"] / c["ms_per_step"], f["ms_per_step"],
        f["ms_per_step"] / m["ms_per_step"]))
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
