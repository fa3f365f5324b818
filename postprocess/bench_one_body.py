"""`make bench-one-body`: a mesh of one body pays nothing for contact between bodies (docs/bodies.md). The same runs
of this tree and of REV (default b78442c^, the driver before bodies), side by side in one run: each case alternately
on the one and the other, --repeat times, the medians kept (wall seconds and the loop's CPU seconds, summary.txt's
cpu_seconds), the ratio this / REV, and whether the histories are the same bytes. REV is checked out into a git
worktree under OUT (its plugins built there). Writes OUT/bench_one_body.md and .csv.

    /usr/bin/python3 postprocess/bench_one_body.py [--out results/bench] [--rev b78442c^] [--repeat 3]
"""
import os
import shutil
import statistics
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import jobs  # noqa: E402
from driver import ROOT, timed_process  # noqa: E402
from history import read_summary  # noqa: E402

QUIET = ["-progress", "0", "-snapshots", "none"]
# name: (scene, args): the paper's Test 1 with each solver, Test 2, the stiff svk body and the 3D ball
CASES = {
    "test1 activeset": ("test1", ["-T", "40", "-solver", "activeset"]),
    "test1 ipopt": ("test1", ["-T", "40"]),
    "test2 activeset": ("test2", ["-T", "40", "-solver", "activeset"]),
    "test1 svk stiff": ("test1", ["-T", "20", "-material", "svk", "-lambda", "300", "-mu", "300"]),
    "ball activeset": ("ball", ["-T", "14", "-solver", "activeset"]),
}


def tree_of(rev, out):
    """A worktree of rev under out (made again each time), its plugins built."""
    where = os.path.join(out, "rev_tree")
    subprocess.run(["git", "-C", ROOT, "worktree", "remove", "--force", where], capture_output=True)
    shutil.rmtree(where, ignore_errors=True)
    p = subprocess.run(["git", "-C", ROOT, "worktree", "add", "--detach", where, rev], capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit(f"error: --rev {rev}: git worktree add failed: {p.stderr.strip()}")
    for mesh in os.listdir(os.path.join(ROOT, "meshes")):
        if mesh.endswith(".msh") and not os.path.exists(os.path.join(where, "meshes", mesh)):
            shutil.copy(os.path.join(ROOT, "meshes", mesh), os.path.join(where, "meshes", mesh))
    p = subprocess.run(["make", "-s", "plugins"], cwd=where, capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit(f"error: --rev {rev}: its plugins do not build: {p.stderr.strip()[:300]}")
    return where


def one_run(tree, scene, args, out):
    r = timed_process([os.path.join(tree, "edp", "run.sh"), scene, out] + QUIET + args, merge=True,
                      env=dict(os.environ, FORCE="1"), cwd=tree)
    if r.returncode != 0:
        sys.exit(f"error: {scene} {' '.join(args)} in {tree} failed (exit {r.returncode}):\n{r.stdout[-2000:]}")
    return r.wall, float(read_summary(out)["cpu_seconds"])


def main():
    ap = jobs.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", default="results/bench")
    ap.add_argument("--rev", default="b78442c^")
    ap.add_argument("--repeat", type=jobs.positive_int, default=3)
    a = ap.parse_args()
    out = os.path.abspath(a.out)
    os.makedirs(out, exist_ok=True)
    rev_tree = tree_of(a.rev, out)
    lines = [f"| case | wall s, this | wall s, {a.rev} | ratio | loop CPU s, this | loop CPU s, {a.rev} | ratio | "
             "same history |", "| --- | ---: | ---: | ---: | ---: | ---: | ---: | --- |"]
    csv = ["case,wall_this,wall_rev,cpu_this,cpu_rev,same_history"]
    try:
        for name, (scene, args) in CASES.items():
            times = {"this": [], "rev": []}
            dirs = {k: os.path.join(out, "one_body", name.replace(" ", "_") + "_" + k) for k in times}
            for _ in range(a.repeat):
                for key, tree in (("this", ROOT), ("rev", rev_tree)):
                    times[key].append(one_run(tree, scene, args, dirs[key]))
            med = {k: (statistics.median(w for w, _ in v), statistics.median(c for _, c in v)) for k, v in times.items()}
            same = open(os.path.join(dirs["this"], "history.csv"), "rb").read() == \
                open(os.path.join(dirs["rev"], "history.csv"), "rb").read()
            lines.append(f"| {name} | {med['this'][0]:.2f} | {med['rev'][0]:.2f} | {med['this'][0] / med['rev'][0]:.3f} | "
                         f"{med['this'][1]:.3f} | {med['rev'][1]:.3f} | {med['this'][1] / med['rev'][1]:.3f} | "
                         f"{'yes' if same else 'no'} |")
            csv.append(f"{name},{med['this'][0]:.4f},{med['rev'][0]:.4f},{med['this'][1]:.4f},{med['rev'][1]:.4f},{int(same)}")
            print(lines[-1], flush=True)
    finally:
        subprocess.run(["git", "-C", ROOT, "worktree", "remove", "--force", rev_tree], capture_output=True)
    jobs.write_files(out, {"bench_one_body.md": "\n".join(lines) + f"\n\nMedians of {a.repeat} runs each, the two trees "
                                                                     "alternated.\n",
                           "bench_one_body.csv": "\n".join(csv) + "\n"})


if __name__ == "__main__":
    main()
