#!/usr/bin/env python3
"""make hostile: tests/test_hostile.py's generative test, run again and again with fresh seeds for MINUTES (30),
EXAMPLES cases a round (docs/tests.md). Each round prints its seed; a round that finds a case breaking the contract
stops the loop and prints Hypothesis's shrunk counterexample, with the command that runs that seed again. Exit 0:
nothing found; 1: a counterexample."""
import argparse
import os
import random
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--minutes", type=float, default=30)
    ap.add_argument("--examples", type=int, default=40, help="cases a round")
    a = ap.parse_args()
    start = time.time()
    deadline, rounds = start + 60 * a.minutes, 0
    while time.time() < deadline:
        seed = random.SystemRandom().randrange(2 ** 31)
        env = dict(os.environ, HOSTILE_SEED=str(seed), HOSTILE_EXAMPLES=str(a.examples))
        p = subprocess.run([sys.executable, "-m", "pytest", "-q", "-x", "-p", "no:cacheprovider", "tests/test_hostile.py",
                            "-k", "keep_the_contract"], cwd=ROOT, env=env, capture_output=True, text=True)
        rounds += 1
        minutes = (time.time() - start) / 60
        if p.returncode != 0:
            print(p.stdout[-12000:] + p.stderr[-2000:])
            print(f"hostile: seed {seed} found a case that breaks the contract (above, shrunk), after {minutes:.1f} min; "
                  f"again: HOSTILE_SEED={seed} HOSTILE_EXAMPLES={a.examples} {sys.executable} -m pytest -q "
                  "tests/test_hostile.py -k keep_the_contract", flush=True)
            return 1
        print(f"hostile: seed {seed}: {a.examples} cases kept the contract ({minutes:.1f} min)", flush=True)
    print(f"hostile: {rounds * a.examples} cases in {rounds} rounds of fresh seeds, {a.minutes:g} minutes: nothing found")
    return 0


if __name__ == "__main__":
    sys.exit(main())
