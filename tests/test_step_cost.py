"""The step at the cost of one solve (issue 34; docs/solvers.md, "One solve a step"): on the serial Cholesky
factor the active set's step is one forward and one backward solve with CHOLMOD's halves of A (the plugin
edp/lib/solve/cholmod_columns.cpp), and S = C A^-1 C' comes from sparse columns L^-1 P C', not from solves.
What is checked here is that it is the same step: the halves give the full solve's bits, and the QP's answer
is that of the solve-based active set (-factorization lu takes it) to round-off, with the same active sets,
including on steps where a node outside the known set joins it (a body that starts in contact). The speed is
measured by make bench (bench.md, "A step against its floor"), never here."""
import os
import shutil
import subprocess

import numpy as np
import pytest

from conftest import ROOT, error_lines, files_of, run_scene
from driver import freefem_env
from history import read_run, read_summary

@pytest.mark.parametrize("mesh,dim", [("ball", 3), ("disk", 2)])
def test_the_factor_halves_are_the_full_solve_to_the_last_bit(mesh, dim):
    # x = A^-1 b from cholmodSolve and from cholmodForward then cholmodBackward (P' L^-T D^-1 L^-1 P b): the
    # step's x on a step without contact is the driver's free predictor of (4), bit for bit
    env = freefem_env()
    p = subprocess.run(["FreeFem++-nw", "-nw", "-v", "0", os.path.join(ROOT, "edp", "limit.edp"), "-mesh",
                        os.path.join(ROOT, "meshes", f"{mesh}.msh"), "-dim", str(dim), "-n", "2"],
                       capture_output=True, text=True, env=env)
    line = [ln for ln in p.stdout.splitlines() if ln.startswith("limit ")]
    assert p.returncode == 0 and line, p.stdout + p.stderr
    values = dict(kv.split("=", 1) for kv in line[0].split()[1:])
    assert values["halves_equal"] == "1"
    assert float(values["solve_ms"]) > 0 and float(values["factor_entries"]) > 0


def agree(a, b, columns, tol):
    assert (a["active_nodes"] == b["active_nodes"]).all(), "the active sets differ"
    assert (a["qp_solved"] == b["qp_solved"]).all()
    for col in columns:
        diff = np.abs(a[col] - b[col])
        k = int(np.argmax(diff))
        assert diff[k] <= tol * max(1.0, np.abs(b[col]).max()), f"{col} differs by {diff[k]:.3g} at t = {a['t'][k]}"


@pytest.mark.parametrize("case,args", [
    # Test 1 in 3D through the first impact (t = 8.95) and into the rebound
    ("fall", ["-T", "12"]),
    # the ball starting in contact at the impact speed, every step a QP from the first (-skip_free 0: the known set
    # is empty at step 1, so the nodes that (10) binds join it after the predictor; on later steps nodes join as
    # the contact spreads)
    ("impact", ["-u0z", "0", "-v0z", "-0.894", "-T", "1.5", "-skip_free", "0"]),
])
def test_the_factor_step_is_the_solve_based_active_set(tmp_path, case, args):
    # the QP of (4) under (10) has one solution: the step on the factor's halves (cholesky) and the one with S
    # from solves (lu) agree to round-off, with the same active sets at every step (Prop. 1's unique solution)
    runs = {}
    for factorization in ("cholesky", "lu"):
        out = tmp_path / factorization
        run_scene("ball", out, ["-solver", "activeset", "-factorization", factorization, "-progress", "0",
                                "-snapshots", "none"] + args)
        runs[factorization] = out
    a, b = read_run(runs["cholesky"]), read_run(runs["lu"])
    agree(a, b, ["u3_low", "v3_low", "energy", "contact_force_z", "u3_mean", "v3_mean"], 1e-9)
    assert a["active_nodes"].max() > 0
    assert a["max_penetration"].max() < 1e-12          # (10) at every node, not only the known ones
    # the factor's step computes a column per node that joins (a block of forward solves), not a solve per node
    assert int(read_summary(runs["cholesky"])["schur_solves"]) >= int(read_summary(runs["lu"])["schur_solves"])


def test_a_missing_plugin_is_one_line_and_changes_nothing(tmp_path):
    # a serial run without build/plugins/cholmod_columns.so: exit 1 before FreeFEM starts, one line naming the file
    # and how to build it; the earlier run's files are byte-identical
    root = tmp_path / "tree"
    root.mkdir()
    shutil.copytree(os.path.join(ROOT, "edp"), root / "edp", symlinks=True)
    shutil.copytree(os.path.join(ROOT, "meshes"), root / "meshes", ignore=shutil.ignore_patterns("*refine*", "*medium*"))
    earlier = tmp_path / "earlier"
    run_scene("test1", earlier, ["-T", "0.2", "-progress", "0"])
    before = files_of(earlier)
    p = subprocess.run([str(root / "edp" / "run.sh"), "test1", str(earlier), "-T", "0.4"], capture_output=True, text=True,
                       env=dict(os.environ, FORCE="1"))
    assert p.returncode == 1
    lines = error_lines(p)
    assert len(lines) == 1 and "cholmod_columns.so is missing" in lines[0] and "make plugins" in lines[0], p.stderr
    assert files_of(earlier) == before


# ---- a step pays only for the diagnostics it asks for (-diagnostics_every N; docs/outputs.md)

@pytest.mark.parametrize("scene,args", [
    ("test1", ["-T", "3", "-material", "svk"]),            # 2D, with min_J (a non-linear material's column)
    ("ball", ["-T", "10"]),                                  # 3D through the impact (t = 8.95)
])
def test_diagnostics_every_n_leaves_only_the_cells_it_skips(tmp_path, scene, args):
    # max_strain (and min_J) are computed at every N-th step, at each checkpoint and at the last step, and left
    # empty elsewhere; every other cell of every row, and the cells computed, are the default run's to the bit
    # (they do not feed the step: the scheme (1)-(2) and (10) do not see them), and so are u and v at the end
    every, checkpoint = 7, 20
    full, thin = tmp_path / "every_step", tmp_path / "every_7"
    common = ["-progress", "0", "-snapshots", "none", "-checkpoint_every", str(checkpoint)] + args
    run_scene(scene, full, common)
    run_scene(scene, thin, common + ["-diagnostics_every", str(every)])
    rows_full = open(full / "history.csv").read().splitlines()
    rows_thin = open(thin / "history.csv").read().splitlines()
    assert rows_full[0] == rows_thin[0] and len(rows_full) == len(rows_thin)
    header = rows_full[0].split(",")
    skipped = [header.index(c) for c in ("max_strain", "min_J") if c in header]
    assert len(skipped) == (2 if "svk" in args else 1)
    last = len(rows_full) - 2
    for a, b in zip(rows_full[1:], rows_thin[1:]):
        a, b = a.split(","), b.split(",")
        step = int(a[0])
        computed = step % every == 0 or step % checkpoint == 0 or step == last
        for k in range(len(header)):
            if k in skipped and not computed:
                assert b[k] == "", f"step {step}: {header[k]} is {b[k]!r}, not empty"
            else:
                assert a[k] == b[k], f"step {step}: {header[k]} {a[k]} != {b[k]}"
    assert open(full / "checkpoint.txt").read().split("\n", 1)[1] == open(thin / "checkpoint.txt").read().split("\n", 1)[1]
    # summary.txt's max_strain is over the steps computed: the largest of the cells written
    h = read_run(thin)
    assert float(read_summary(thin)["max_strain"]) == pytest.approx(np.nanmax(h["max_strain"]), rel=1e-5)
    assert np.isnan(h["max_strain"]).sum() > 0


def test_the_through_guard_names_its_steps_strain_whatever_diagnostics_every(tmp_path):
    # the step the through guard stops (watch/guards.idp; the ball at -v0z -10) computes its diagnostics: its one
    # line names that step's largest principal strain, the same as with every step's, and its row has the cells
    lines = {}
    for every in ("1", "1000"):
        out = tmp_path / f"every_{every}"
        p = run_scene("ball", out, ["-T", "4", "-solver", "activeset", "-v0z", "-10", "-progress", "0", "-snapshots", "none",
                                    "-diagnostics_every", every], check=False)
        assert p.returncode == 4, p.stderr
        lines[every] = error_lines(p)
        last = open(out / "history.csv").read().splitlines()[-1].split(",")
        header = open(out / "history.csv").readline().strip().split(",")
        assert last[header.index("max_strain")] != ""
    assert len(lines["1"]) == 1 and "largest principal strain" in lines["1"][0]
    assert lines["1"] == lines["1000"]
