"""postprocess/audit.py: every run checked against the physics its own files claim (docs/errors.md, "The audit").

edp/run.sh audits every run that reaches T, so every run of make check passes through it: one that fails exits 6
(conftest.py keeps the audit on, whatever the caller's environment). These tests check that the audit can fail:
a check that cannot fail is no check. Each doctors one value of a real run's files and expects the failure that
names the check, the column and the step."""
import csv
import os
import shutil
import subprocess
import sys

import pytest

from conftest import ROOT, error_lines, run_scene

sys.path.insert(0, os.path.join(ROOT, "postprocess"))
import audit  # noqa: E402

QUIET = ["-progress", "0", "-vtk", "0", "-snapshots", "none"]


@pytest.fixture(scope="module")
def audited(tmp_path_factory):
    """Two small runs that every check reads: Test 1 through its first contact (the active set, snapshots at 10 and
    12), and the disk sliding with Coulomb's friction on the 30 degree incline (the columns' vertical friction)."""
    base = tmp_path_factory.mktemp("audited")
    runs = {"contact": ("test1", ["-T", "12", "-solver", "activeset", "-snapshots", "10,12", "-vtk", "0"]),
            "friction": ("incline", ["-angle", "30", "-T", "4", "-friction", "coulomb", "-friction_coefficient", "0.1",
                                     "-snapshots", "2,4"])}
    for name, (scene, args) in runs.items():
        run_scene(scene, base / name, ["-progress", "0"] + args)
    return {name: base / name for name in runs}


def doctored(tmp_path, run, column, step, factor=1.01, file="history.csv"):
    """A copy of run with history.csv's `column` at `step` multiplied by factor; its directory."""
    out = tmp_path / "doctored"
    shutil.copytree(run, out)
    path = out / file
    rows = list(csv.reader(open(path, newline="")))
    k = rows[0].index(column)
    rows[step + 1][k] = repr(float(rows[step + 1][k]) * factor)
    with open(path, "w", newline="") as f:
        csv.writer(f, lineterminator="\n").writerows(rows)
    return out


def test_the_runs_pass_the_audit(audited):
    """The runs as they were written pass every check (their run.sh exited 0, which says so too)."""
    for run in audited.values():
        assert audit.audit_run(str(run)) == []


# (check, column, step): one value changed by 1%, at a step where it matters
DOCTORED = [
    ("momentum", "contact_force_y", 200),       # the disk pressed (t = 10): (1) summed over the vertical translation
    ("momentum", "v2_mean", 200),              # (the change of v2_mean over step 200 or over step 201)
    ("energy", "modified_energy", 100),        # free fall: Prop. 2 allows no rise
    ("grid", "t", 50),
    ("snapshots", "u1_low", 240),             # the snapshot at t = 12 (u2_low is 0 there: the disk is pressed)
]


@pytest.mark.parametrize("check,column,step", DOCTORED, ids=[f"{c}-{col}" for c, col, _ in DOCTORED])
def test_a_history_changed_by_one_percent_fails_the_audit(audited, tmp_path, check, column, step):
    """One value of Test 1's history.csv changed by 1% fails the check it breaks, naming the column and the step."""
    run = doctored(tmp_path, audited["contact"], column, step)
    failures = audit.audit_run(str(run))
    assert any(f.startswith(check + ":") and (f"step {step} " in f or f"step {step + 1} " in f and column == "v2_mean")
               for f in failures), failures
    p = subprocess.run([sys.executable, os.path.join(ROOT, "postprocess", "audit.py"), str(run)],
                       capture_output=True, text=True)
    assert p.returncode == 1 and p.stderr.startswith(f"audit: {run}: {check}: "), p.stderr


@pytest.mark.parametrize("column,step,check", [("contact_force_x", 40, "momentum"), ("contact_force_y", 40, "momentum"),
                                               ("friction_work", 60, "energy")])
def test_the_friction_columns_fail_the_audit_when_doctored(audited, tmp_path, column, step, check):
    """On the 30 degree incline with F = 0.1: the contact force's two components balance the momentum of (1), and
    Prop. 2 with friction (E - (f, u) + D never rising) holds; 1% off any of them fails."""
    run = doctored(tmp_path, audited["friction"], column, step, factor=0.99)
    failures = audit.audit_run(str(run))
    assert any(f.startswith(check + ":") for f in failures), failures


@pytest.mark.parametrize("column", ["slip_nodes", "active_nodes"])
def test_a_count_that_disagrees_with_the_snapshot_fails_the_audit(audited, tmp_path, column):
    """The snapshot's .vtu at t = 4 counts the pressed and the slipping nodes (contact_pressure, contact_state): the
    history's count one more at that step fails."""
    run = doctored(tmp_path, audited["friction"], column, 80, factor=1)
    path = run / "history.csv"
    rows = list(csv.reader(open(path, newline="")))
    k = rows[0].index(column)
    rows[81][k] = str(int(float(rows[81][k])) + 1)
    with open(path, "w", newline="") as f:
        csv.writer(f, lineterminator="\n").writerows(rows)
    assert any(f.startswith(f"snapshots: vonmises_t4.vtu has ") and f"as {column} counts them" in f
               for f in audit.audit_run(str(run))), audit.audit_run(str(run))


def test_coulomb_is_read_in_the_slope_frame(audited, tmp_path):
    """|T| <= F N in totals, in the frame of the tilted flat: the tangential force scaled up by 5% (the normal one
    kept) exceeds F N where the disk slides, and the audit names it."""
    run = tmp_path / "coulomb"
    shutil.copytree(audited["friction"], run)
    path = run / "history.csv"
    rows = list(csv.reader(open(path, newline="")))
    kx, ky = rows[0].index("contact_force_x"), rows[0].index("contact_force_y")
    s, c = 0.5, 3 ** 0.5 / 2                          # sin, cos of 30 degrees; t = (c, s), n = (-s, c)
    for row in rows[1:]:
        fx, fy = float(row[kx]), float(row[ky])
        T, N = c * fx + s * fy, -s * fx + c * fy
        T *= 1.05
        row[kx], row[ky] = repr(c * T - s * N), repr(s * T + c * N)
    with open(path, "w", newline="") as f:
        csv.writer(f, lineterminator="\n").writerows(rows)
    assert any(f.startswith("friction: the tangential contact force exceeds F N") for f in audit.audit_run(str(run)))


def test_a_repeated_or_missing_column_fails_the_audit(audited, tmp_path):
    """The header must be the documented one: a name twice, or one missing, is named."""
    run = tmp_path / "columns"
    shutil.copytree(audited["contact"], run)
    path = run / "history.csv"
    lines = open(path).read().split("\n")
    lines[0] = lines[0].replace("v2_mean", "v1_mean")
    open(path, "w").write("\n".join(lines))
    failures = audit.audit_run(str(run))
    assert "columns: column v1_mean appears twice in history.csv's header" in failures
    assert any("lacks the documented column(s) v2_mean" in f for f in failures)


def test_a_summary_that_disagrees_with_the_history_fails_the_audit(audited, tmp_path):
    """summary.txt's T and steps must be parameters.txt's and the history's."""
    run = tmp_path / "summary"
    shutil.copytree(audited["contact"], run)
    text = open(run / "summary.txt").read()
    assert text.startswith("steps 240\n")
    text = text.replace("steps 240\n", "steps 241\n", 1)
    open(run / "summary.txt", "w").write(text)
    assert any(f.startswith("grid: summary.txt's run reached T, but steps is 241") for f in audit.audit_run(str(run)))


def test_a_run_whose_files_fail_the_audit_exits_6_and_keeps_them(tmp_path):
    """edp/run.sh audits the run it finished: one whose contact_force_y is written 1% off (a test-only fault) exits 6
    with the audit's line naming the column, and one error line; every file is kept."""
    out = tmp_path / "faulty"
    p = run_scene("test1", out, ["-T", "10", "-solver", "activeset"] + QUIET, check=False,
                  env={"CONTACT_TEST_FORCE_SCALE": "1.01"})
    assert p.returncode == 6, p.stderr
    assert any(line.startswith(f"audit: {out}: momentum: contact_force_y is ") for line in p.stderr.splitlines())
    assert error_lines(p) == [f"error: the run reached T, but its files fail their own audit (postprocess/audit.py, the "
                              f"lines above: 1 of them): a bug in the suite, please report it; every file of {out} is kept"]
    assert (out / "summary.txt").exists() and (out / "history.csv").exists()
