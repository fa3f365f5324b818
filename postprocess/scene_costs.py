"""The cost of every scene at its own T (the numbers of docs/scenes.md): QP steps,
steps and wall seconds, one run at a time, on the paper's mesh with the default
solver; then the same with -material svk (St Venant-Kirchhoff, solved by Newton),
where a run may stop with exit 4 when the body collapses (an inverted triangle):
the table says where, or be refused (exit 3) for what svk does not run yet (friction). Usage: python3 postprocess/scene_costs.py [--out results/scene_costs] [--scenes a,b]"""
import argparse
import glob
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import jobs  # noqa: E402
from driver import ROOT, run_case  # noqa: E402
from history import read_run  # noqa: E402


def main():
    p = argparse.ArgumentParser(description=__doc__)
    p.add_argument("--out", default=os.path.join(ROOT, "results", "scene_costs"))
    p.add_argument("--scenes", default="", help="comma-separated scene names (default: every scene)")
    a = p.parse_args()
    jobs.stop_on_interrupt("scene_costs.py", a.out, [])
    paths = sorted(glob.glob(os.path.join(ROOT, "edp", "scenes", "*.idp")))
    if a.scenes:
        paths = [os.path.join(ROOT, "edp", "scenes", name + ".idp") for name in a.scenes.split(",")]
    print("| scene | QP steps / steps | wall s |\n| --- | ---: | ---: |")
    for path in paths:
        scene = os.path.basename(path)[:-4]
        out = os.path.join(a.out, scene)
        run = run_case(scene, out, ["-progress", "0"])
        if run.returncode != 0:
            sys.exit(f"error: {scene} failed (exit {run.returncode}): {run.stderr.strip()}")
        h = read_run(out)
        print(f"| `{scene}` | {int(h['qp_solved'].sum())} / {len(h['t']) - 1} | {run.wall:.3g} |", flush=True)
    print("\nWith -material svk:\n| scene | outcome | constrained steps / steps | Newton iterations per step | wall s |\n"
          "| --- | --- | ---: | ---: | ---: |")
    for path in paths:
        scene = os.path.basename(path)[:-4]
        out = os.path.join(a.out, scene + "_svk")
        run = run_case(scene, out, ["-progress", "0", "-material", "svk"])
        if run.returncode == 0:
            outcome = "reaches T"
        elif run.returncode == 4 and "inverted" in run.stderr:
            step, t = run.stderr.split("newton failed at step ")[1].split(":")[0].split(", t = ")
            outcome = f"collapses at step {step}, t = {t} (inverted triangle, exit 4)"
        elif run.returncode == 3 and ("not supported yet" in run.stderr or "not available" in run.stderr):   # (what svk lacks: friction, bodies)
            print(f"| `{scene}` | refused: {run.stderr.strip().removeprefix('error: ')} | | | |", flush=True)
            continue
        else:
            sys.exit(f"error: {scene} with -material svk failed (exit {run.returncode}): {run.stderr.strip()}")
        h = read_run(out)
        steps = len(h["t"]) - 1
        print(f"| `{scene}` | {outcome} | {int(h['qp_solved'].sum())} / {steps} | "
              f"{h['newton_iterations'][1:].mean():.2f} | {run.wall:.3g} |", flush=True)


if __name__ == "__main__":
    main()
