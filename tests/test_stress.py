"""The fast subset of `make stress`: hard cases pass the criteria of postprocess/stress.py."""
import pytest

from stress import FAST, evaluate


@pytest.mark.parametrize("name", list(FAST))
def test_hard_case_stays_stable(runs, name):
    metrics, failures = evaluate(name, runs[f"stress: {name}"], 0, "")
    assert not failures, f"{name}: " + "; ".join(failures)
    assert metrics["steps"] > 0
