"""Energy and displacement histories against tests/golden (tolerance per column in each file)."""
import os

import pytest

from conftest import ROOT
from golden import compare


@pytest.mark.parametrize("name", ["test1", "test2_t1_18"])
def test_history_matches_golden(histories, name):
    failures = compare(os.path.join(ROOT, "tests", "golden", f"{name}.csv"), histories[name])
    assert not failures, "\n".join(failures)
