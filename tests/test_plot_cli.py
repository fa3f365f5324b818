"""The figure scripts a user runs directly (postprocess/plot_paper.py, plot_ball.py): a bad option or a
missing run is one `error:` line, no traceback, and nothing written."""
import os
import subprocess

import pytest

from conftest import ROOT

PYTHON = "/usr/bin/python3"
SCRIPTS = {"plot_paper": "test1", "plot_ball": "ball"}


def script(name, *args):
    return subprocess.run([PYTHON, os.path.join(ROOT, "postprocess", f"{name}.py")] + list(args),
                          capture_output=True, text=True)


@pytest.mark.parametrize("name", SCRIPTS)
@pytest.mark.parametrize("bad", [["--out", ""], ["--results", ""], ["--bogus"], ["--out"]], ids=" ".join)
def test_bad_option(name, bad, tmp_path):
    """An empty path, an unknown option or a missing value: exit 2, one `error: NAME.py: ...` line."""
    p = script(name, "--results", str(tmp_path), "--out", str(tmp_path / "figures"), *bad)
    assert p.returncode == 2 and p.stdout == "", p.stderr
    assert len(p.stderr.splitlines()) == 1 and p.stderr.startswith(f"error: {name}.py: ")
    assert os.listdir(tmp_path) == []


@pytest.mark.parametrize("name", SCRIPTS)
def test_missing_run(name, tmp_path):
    """Results without the run the figures need: exit 3, one line naming its directory and the make
    target that writes it, and no figure directory created."""
    p = script(name, "--results", str(tmp_path), "--out", str(tmp_path / "figures"))
    assert p.returncode == 3 and p.stdout == "", p.stderr
    assert p.stderr.splitlines() == [p.stderr.strip()] and os.path.join(str(tmp_path), SCRIPTS[name]) in p.stderr
    assert "run make " in p.stderr and os.listdir(tmp_path) == []
