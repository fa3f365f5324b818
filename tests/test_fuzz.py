"""A fast, seeded fuzz of the option reader: random keys (known and unknown), empty,
malformed, overflowing, NaN and inf values, and missing values. Every run must end
either with exit 0 and a finite history, or with exit 3 and one error line naming a
key it was given (docs/errors.md)."""
import random

import numpy as np
import pytest

from conftest import error_lines, run_scene
from history import read_run

KEYS = ["lambda", "mu", "rho", "fx", "fy", "u0x", "u0y", "v0x", "v0y", "spin", "dt", "foundation", "level", "angle",
        "foundation_velocity", "t0", "t1", "wave_a", "wave_k", "wave_c", "solver", "tol", "skip_free", "factorization",
        "snapshots", "probes", "checkpoint_every", "ipopt_max_iter", "max_steps", "material", "mesh",
        "Dt", "dtt", "lamda", "restart_dir", "x"]
NASTY = ["", "nan", "NaN", "-nan", "inf", "-inf", "Infinity", "1e400", "-1e400", "1e-400", "1e308", "-1e31",
         "99999999999999999999", "2147483648", "-2147483649", "9223372036854775808", "0", "-0", "-1", "1", "0.5", "+3",
         "abc", "1,2", "0x10", "1e", ".", "e5", "--", "-", " 1", "1 ", "1e5", "0.05", "flat", "none", "cosine",
         "activeset", "lu", "0,40", "3,1e400"]
CASES = 60


def fuzz_case(rng):
    args, keys = [], []
    for _ in range(rng.randint(1, 3)):
        key = rng.choice(KEYS)
        value = rng.choice(NASTY) if rng.random() < 0.8 else f"{rng.uniform(-5, 5):.3g}"
        args += ["-" + key, value]
        keys.append(key)
    if rng.random() < 0.15:
        args.pop()                      # a missing value
    return args, keys


@pytest.mark.parametrize("case", range(CASES))
def test_option_reader_fuzz(tmp_path, case):
    rng = random.Random(1000 + case)
    args, keys = fuzz_case(rng)
    out = tmp_path / "out"
    p = run_scene("test1", out, args + ["-T", "0.2", "-progress", "0", "-snapshots", "none"], check=False, timeout=300)
    if p.returncode == 0:
        h = read_run(str(out))
        assert len(h["t"]) > 1 and np.isfinite(np.column_stack(list(h.values()))).all(), args
    else:
        assert p.returncode == 3, f"{args}: exit {p.returncode}\n{p.stderr}"
        errors = error_lines(p)
        assert len(errors) == 1, f"{args}: {p.stderr}"
        assert any(f"-{k}" in errors[0] for k in keys + ["T"]), f"{args}: the error names no key: {errors[0]}"
        assert not out.exists()
