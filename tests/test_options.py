"""Bad input: one clear line naming the parameter, non-zero exit, nothing written."""
import os
import subprocess

import pytest

from conftest import ROOT, run_scene

BAD = [
    (["-dt", "0"], "-dt must be > 0"),
    (["-dt", "-0.1"], "-dt must be > 0"),
    (["-T", "0"], "-T must be > 0"),
    (["-rho", "0"], "-rho must be > 0"),
    (["-mu", "0"], "-mu must be > 0"),
    (["-lambda", "-40"], "-lambda must be > -mu"),
    (["-foundation", "cosine", "-t0", "9", "-t1", "9"], "-t1 must be > t0"),
    (["-dtt", "0.1"], "unknown option -dtt"),
    (["-dt", "0.1x"], "-dt must be a number, got '0.1x'"),
    (["-skip_free", "1.5"], "-skip_free must be an integer"),
    (["-snapshots", "200"], "-snapshots must be in [0, T]"),
    (["-solver", "magic"], "-solver must be ipopt or activeset"),
    (["-factorization", "qr"], "-factorization must be cholesky or lu"),
    (["-material", "svk"], "-material must be linear"),
    (["-probes", "0,40,17"], "-probes must be x,y pairs"),
    (["-angle", "75"], "-angle must be in (-60, 60)"),
    (["-checkpoint_every", "0"], "-checkpoint_every must be >= 1"),
    (["-foundation", "user"], "-foundation user needs the scene to define"),
    (["-mesh", "meshes/no-such-file.msh"], "-mesh meshes/no-such-file.msh: file missing or unreadable"),
]


@pytest.mark.parametrize("args,message", BAD, ids=[" ".join(a) for a, _ in BAD])
def test_bad_input_is_one_clear_error(tmp_path, args, message):
    out = tmp_path / "out"
    short = [] if "-T" in args else ["-T", "2"]      # should a check be missing, the run stays short
    p = run_scene("test1", str(out), args + short, check=False)
    assert p.returncode != 0
    errors = [line for line in p.stderr.splitlines() if line.strip()]
    assert len(errors) == 1 and message in errors[0], p.stderr
    assert not (out / "history.csv").exists()


def test_mesh_without_contact_label(tmp_path):
    geo = tmp_path / "square.geo"
    geo.write_text('Point(1)={0,0,0,1};Point(2)={1,0,0,1};Point(3)={1,1,0,1};Point(4)={0,1,0,1};'
                   'Line(1)={1,2};Line(2)={2,3};Line(3)={3,4};Line(4)={4,1};Curve Loop(1)={1,2,3,4};'
                   'Plane Surface(1)={1};Physical Curve(2)={1,2,3,4};Physical Surface(1)={1};\n')
    msh = tmp_path / "square.msh"
    subprocess.run(["gmsh", "-2", "-format", "msh22", str(geo), "-o", str(msh)], check=True, capture_output=True)
    p = run_scene("test1", str(tmp_path / "out"), ["-mesh", str(msh)], check=False)
    assert p.returncode != 0 and "has no boundary label 1" in p.stderr, p.stderr


def test_mesh_that_is_not_msh22(tmp_path):
    bad = tmp_path / "bad.msh"
    bad.write_text("not a mesh\n")
    p = run_scene("test1", str(tmp_path / "out"), ["-mesh", str(bad)], check=False)
    assert p.returncode == 3 and "not a gmsh MSH 2.2 file" in p.stderr, p.stderr


def test_unwritable_output_directory(tmp_path):
    blocker = tmp_path / "file"
    blocker.write_text("")
    p = run_scene("test1", str(blocker / "out"), [], check=False)
    assert p.returncode != 0 and "cannot be written" in p.stderr, p.stderr


def test_existing_results_are_not_overwritten(tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    (out / "history.csv").write_text("precious\n")
    p = subprocess.run([os.path.join(ROOT, "edp", "run.sh"), "test1", str(out)], capture_output=True, text=True,
                       env={k: v for k, v in os.environ.items() if k != "FORCE"})
    assert p.returncode != 0 and "FORCE=1" in p.stderr
    assert (out / "history.csv").read_text() == "precious\n"


def test_bad_input_leaves_an_earlier_run_untouched(tmp_path):
    out = tmp_path / "out"
    run_scene("test1", str(out), ["-T", "0.2", "-progress", "0"])
    before = {f: (out / f).read_bytes() for f in ("history.csv", "parameters.txt", "mesh.msh")}
    bad = tmp_path / "bad.msh"
    bad.write_text("not a mesh\n")
    for args in (["-dt", "-1"], ["-mesh", str(bad)], ["-foundation", "user"]):
        p = run_scene("test1", str(out), args, check=False)      # FORCE=1: it may overwrite, but must fail first
        assert p.returncode == 3, p.stderr
        assert {f: (out / f).read_bytes() for f in before} == before, f"{args} touched the earlier results"
