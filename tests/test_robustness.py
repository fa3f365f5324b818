"""No run loses or mixes data (docs/errors.md): flushed history, checkpoints and
-restart, refused restarts, write failures (a full disk), one run per output
directory, the IPOPT retry and a clean stop."""
import os
import resource
import shutil
import signal
import subprocess
import time

import numpy as np
import pytest

from conftest import RUN, error_lines, files_of, refused_into_copy, run_scene, square_mesh
from history import read_run

SHORT = ["-progress", "0", "-vtk", "0"]


def start(scene, out, args):
    return subprocess.Popen([RUN, scene, str(out)] + args, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                            start_new_session=True, env=dict(os.environ, FORCE="1"))


def wait_for_rows(history, rows, seconds=120):
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        if os.path.exists(history) and sum(1 for _ in open(history)) > rows:
            return
        time.sleep(0.05)
    raise AssertionError(f"{history} did not reach {rows} rows")


def same_history(a, b, n=None):
    for column in a:
        diff = np.abs(a[column][:n] - b[column][:n]).max()
        assert diff <= 1e-12, f"column {column} differs by {diff:.3g}"


def test_killed_run_restarts_to_the_same_history(tmp_path, histories):
    out = tmp_path / "killed"
    proc = start("test1", out, ["-T", "20", "-checkpoint_every", "50"] + SHORT)
    wait_for_rows(out / "history.csv", 260)        # kill it on purpose, past a checkpoint, mid-run
    os.killpg(proc.pid, signal.SIGKILL)
    proc.wait()
    rows_at_kill = sum(1 for _ in open(out / "history.csv")) - 1
    step = int(open(out / "checkpoint.txt").readline().split()[3])
    assert 200 <= step <= rows_at_kill < 400, (step, rows_at_kill)

    p = run_scene("test1", out, ["-restart", str(out)])
    assert "was left by a run that was killed" in p.stdout          # the stale lock is noticed
    restarted, whole = read_run(str(out)), histories["test1"]
    n = len(restarted["t"])
    assert n == 401 and (restarted["step"] == np.arange(n)).all()
    same_history(restarted, whole, n)


@pytest.fixture(scope="module")
def finished(tmp_path_factory):
    """A finished run to T = 10 with checkpoints every 50 steps."""
    out = tmp_path_factory.mktemp("finished") / "run"
    run_scene("test1", out, ["-T", "10", "-checkpoint_every", "50", "-snapshots", "0,5"] + SHORT)
    return str(out)


def corrupt(path, how):
    text = open(path).read()
    if how == "empty":
        text = ""
    elif how == "truncated":
        text = text[:len(text) // 2]
    elif how == "a corrupt number":
        lines = text.split("\n")
        lines[3] = lines[3].replace(lines[3].split()[1], "1.2.3", 1)
        text = "\n".join(lines)
    elif how == "cut mid-number":          # issue 19: said "'-' is not a finite number"
        text = text[:text.index("\n", len(text) // 2) + 3]
    elif how == "a hand-edited value":     # issue 19: one u value set to 1234.5 was taken (energy 6.3 -> 7.9e7)
        lines = text.split("\n")
        fields = lines[2].split("\t")
        fields[1] = "1234.5"
        lines[2] = "\t".join(fields)
        text = "\n".join(lines)
    elif how == "an edited -fy":           # (damages parameters.txt: see test_refused_restart_...)
        pass
    elif how == "an overflowing header":
        head, rest = text.split("\n", 1)
        fields = head.split()
        fields[4] = "1e999"
        text = " ".join(fields) + "\n" + rest
    open(path, "w").write(text)


def damage_history(path, how):
    lines = open(path).read().split("\n")
    if how == "other columns":
        lines[0] = lines[0] + ",extra"
    elif how == "an incomplete row":
        lines[50] = lines[50].rsplit(",", 3)[0]
    elif how == "rows missing":
        lines = lines[:120]
    open(path, "w").write("\n".join(lines))


REFUSED = [
    ([], None, "the run already reached step 200 (t = 10); give a -T larger than 10 to extend it"),
    (["-T", "20", "-dt", "nan"], None, "-dt must be a number, got 'nan'"),
    (["-T", "20", "-dt", "0.025"], None, "-dt 0.025 differs from the run's -dt 0.05; a restart continues the same "
                                         "discrete problem and may change only -T and the output options"),
    (["-T", "20", "-probes", "0,40"], None, "-probes 0,40 differs from the run's -probes none"),
    (["-T", "20", "-lambda", "31"], None, "-lambda 31 differs from the run's -lambda 30"),
    (["-T", "20", "-solver", "activeset"], None, "-solver activeset differs from the run's -solver ipopt"),
    # issue 19: the material is named first, not a solver that follows from it
    (["-T", "20", "-material", "svk"], None, "-restart: -material svk differs from the run's -material linear"),
    (["-T", "20", "-reference", "5,5"], None, "-restart: -reference 5,5 names the vertex at (4.82535, 5.12991), not the run's "
                                              "reference vertex at (0, 0)"),
    (["-T", "20", "-mesh", "meshes/disk_coarse.msh"], None,
     "its checkpoint is for a mesh with 989 vertices and 1864 triangles; -mesh meshes/disk_coarse.msh has 277 and 496"),
    (["-T", "20", "-snapshots", "3"], None, "-snapshots 3 is before the checkpoint (t = 10), and the run did not write it"),
    (["-T", "20"], "empty", "checkpoint.txt is empty"),
    (["-T", "20"], "truncated", "checkpoint.txt is truncated (no end marker)"),
    (["-T", "20"], "a corrupt number", "checkpoint.txt is corrupt: '1.2.3' is not a finite number"),
    (["-T", "20"], "an overflowing header", "checkpoint.txt header field 5 is not a finite number ('1e999')"),
    (["-T", "20"], "cut mid-number", "checkpoint.txt is truncated (no end marker)"),
    (["-T", "20"], "a hand-edited value", "its checkpoint.txt was changed after the run wrote it (its checksum does not match "
                                          "its values)"),
    (["-T", "20"], "an edited -fy", "its parameters.txt was changed after the run wrote it (its checksum does not match "
                                    "the checkpoint's)"),
    # a key that a later version added (FreeFEM crashed after this line, exit 1)
    (["-T", "20"], "an older version's parameters.txt", "its parameters.txt does not record -traction_label (written by an "
                                                        "older version?); start a new run"),
]


@pytest.mark.parametrize("args,damage,message", REFUSED,
                         ids=[" ".join(a) + (f" ({d} checkpoint)" if d else "") for a, d, _ in REFUSED])
def test_refused_restart_leaves_the_run_byte_identical(tmp_path, finished, args, damage, message):
    out = tmp_path / "run"
    shutil.copytree(finished, out)
    if damage == "an edited -fy":
        text = (out / "parameters.txt").read_text()
        (out / "parameters.txt").write_text(text.replace("\n-fy -0.10000000000000001\n", "\n-fy -0.2\n"))
        assert text != (out / "parameters.txt").read_text()
    elif damage == "an older version's parameters.txt":
        text = (out / "parameters.txt").read_text()
        (out / "parameters.txt").write_text("".join(line for line in text.splitlines(True)
                                                    if not line.startswith("-traction_label ")))
    elif damage:
        corrupt(out / "checkpoint.txt", damage)
    before = files_of(out)
    p = run_scene("test1", out, ["-restart", str(out)] + args, check=False)
    errors = [line for line in p.stderr.splitlines() if line.strip()]
    assert p.returncode == 3 and len(errors) == 1 and message in errors[0], p.stderr
    assert files_of(out) == before, "the refused restart changed the run's files"


def test_restart_on_the_same_nodes_with_other_labels_is_refused(tmp_path):
    """Issue 19: a unit square meshed with Gamma_C (label 1) on its bottom, run, re-meshed in place with
    label 1 on its top (the same nodes), restarted: it ran on with the body inside the foundation.
    The checkpoint's fingerprint now covers the triangles and the boundary labels: exit 3, one line."""
    msh, out = tmp_path / "square.msh", tmp_path / "run"

    def mesh(contact, free):
        square_mesh(msh, f"Physical Curve(1)={{{contact}}};Physical Curve(2)={{{free}}};", side=10, size=2)
    mesh("1", "2,3,4")
    run_scene("test1", out, ["-mesh", str(msh), "-T", "1", "-checkpoint_every", "10", "-snapshots", "none"] + SHORT)
    nodes = open(msh).read().split("$Elements")[0]
    mesh("3", "1,2,4")
    assert open(msh).read().split("$Elements")[0] == nodes           # the same nodes
    before = files_of(out)
    p = run_scene("test1", out, ["-restart", str(out), "-T", "2"], check=False)
    assert p.returncode == 3 and error_lines(p) == [f"error: -restart {out}: the mesh (-mesh {msh}) is not the one the run used "
                                                    "(the same vertices, other triangles or boundary labels)"], p.stderr
    assert files_of(out) == before


def test_restart_accepts_the_reference_it_was_given(tmp_path, finished):
    """Issue 19: a run's -reference is recorded as its node's coordinates; a restart given the original
    -reference 0.3,0.2 (whose nearest vertex is (0, 0)) or -reference auto names the same node, and
    continues (before, both were refused as differing from -reference 0,0)."""
    out = tmp_path / "run"
    shutil.copytree(finished, out)
    run_scene("test1", out, ["-restart", str(out), "-T", "10.5", "-reference", "0.3,0.2"])
    run_scene("test1", out, ["-restart", str(out), "-T", "11", "-reference", "auto"])
    h = read_run(str(out))
    assert h["t"][-1] == 11 and (h["step"] == np.arange(221)).all()


@pytest.mark.parametrize("how,message", [
    ("other columns", "its history.csv has other columns than this run writes"),
    ("an incomplete row", "its history.csv is incomplete or out of order at line 51 (step 49)"),
    ("rows missing", "its history.csv stops at step 118, before the checkpoint (step 200)"),
])
def test_restart_from_a_damaged_history_is_refused(tmp_path, finished, how, message):
    out = tmp_path / "run"
    shutil.copytree(finished, out)
    damage_history(out / "history.csv", how)
    before = files_of(out)
    p = run_scene("test1", out, ["-restart", str(out), "-T", "20"], check=False)
    errors = [line for line in p.stderr.splitlines() if line.strip()]
    assert p.returncode == 3 and len(errors) == 1 and message in errors[0], p.stderr
    assert files_of(out) == before


def test_restart_needs_the_runs_snapshots(tmp_path, finished):
    """The snapshots up to the checkpoint are kept: one that is missing is refused, and a
    killed run's temporary file is not carried over."""
    out = tmp_path / "run"
    shutil.copytree(finished, out)
    os.remove(out / "snapshot_t5.csv")
    before = files_of(out)
    p = run_scene("test1", out, ["-restart", str(out), "-T", "20"], check=False)
    assert p.returncode == 3 and "its snapshot_t5.csv is missing" in p.stderr and files_of(out) == before
    shutil.rmtree(out)
    shutil.copytree(finished, out)
    (out / "vonmises_t3.part.vtu").write_text("half a file")
    run_scene("test1", out, ["-restart", str(out), "-T", "11"])
    assert not (out / "vonmises_t3.part.vtu").exists()


def test_restart_of_another_scene_is_refused(tmp_path, finished):
    p, changed = refused_into_copy(tmp_path, finished, "test2", ["-restart", finished, "-T", "20"])
    assert p.returncode == 3 and "it is a run of scene test1, not test2" in p.stderr and not changed


def test_restart_into_a_directory_holding_another_run_needs_force(tmp_path, finished, earlier_run):
    out = tmp_path / "other"
    shutil.copytree(earlier_run, out)
    before = files_of(out)
    p = subprocess.run([RUN, "test1", str(out), "-restart", finished, "-T", "20"], capture_output=True, text=True,
                       env={k: v for k, v in os.environ.items() if k != "FORCE"})
    assert p.returncode == 3 and "already holds a run (history.csv); use FORCE=1" in p.stderr
    assert files_of(out) == before


def test_extending_T_continues_the_same_history(tmp_path, finished):
    """-restart with a larger -T, into another directory: it holds the whole run, equal
    to one run straight to the new T; the original run is untouched."""
    before = files_of(finished)
    out = tmp_path / "extended"
    run_scene("test1", out, ["-restart", finished, "-T", "15"])
    straight = tmp_path / "straight"
    run_scene("test1", straight, ["-T", "15", "-checkpoint_every", "50", "-snapshots", "0,5"] + SHORT)
    a, b = read_run(str(out)), read_run(str(straight))
    assert len(a["t"]) == 301 and (a["step"] == np.arange(301)).all()
    same_history(a, b)
    assert sorted(f for f in os.listdir(out) if f.startswith("snapshot")) == ["snapshot_t0.csv", "snapshot_t5.csv"]
    assert files_of(finished) == before


@pytest.fixture(scope="module")
def finished_past_checkpoint(tmp_path_factory):
    """A finished run to T = 12 (step 240) whose last checkpoint is at step 200, with a snapshot (CSV and
    VTU) at 11.5, after the checkpoint."""
    out = tmp_path_factory.mktemp("past") / "run"
    run_scene("test1", out, ["-T", "12", "-snapshots", "11.5", "-progress", "0"])
    assert open(out / "checkpoint.txt").readline().split()[3] == "200"
    return str(out)


NEVER_SHORTENED = [
    (["-T", "11"], "the run already reached step 240 (t = 12); give a -T larger than 12 to extend it"),
    (["-T", "12"], "the run already reached step 240 (t = 12); give a -T larger than 12 to extend it"),
    (["-T", "13", "-snapshots", "12.5"], "-snapshots leaves out t = 11.5, which the run wrote (snapshot_t11.5.csv); a restart "
                                         "never removes its run's files"),
    (["-T", "13", "-vtk", "0"], "-vtk 0 would remove the .vtu files the run wrote from t = 11.5 on"),
]


@pytest.mark.parametrize("args,message", NEVER_SHORTENED, ids=[" ".join(a) for a, _ in NEVER_SHORTENED])
def test_a_restart_into_its_own_directory_never_removes_what_the_run_wrote(tmp_path, finished_past_checkpoint, args, message):
    """Issue 32: a finished run restarted into its own directory with a -T below its own (but above its last
    checkpoint) exited 0 with history.csv cut from 241 to 221 rows and snapshot_t11.5.* deleted. A restart
    into the run's directory is compared with the run's last history row, not its checkpoint: one that would
    shorten the run, or drop a file the run wrote after its checkpoint, is refused (exit 3, one line, every
    file byte-identical), FORCE=1 or not (run_scene passes FORCE=1)."""
    p, changed = refused_into_copy(tmp_path, finished_past_checkpoint, "test1", ["-restart", str(tmp_path / "copy")] + args)
    lines = [line for line in p.stderr.splitlines() if line.strip()]
    assert p.returncode == 3 and len(lines) == 1 and lines[0].startswith(f"error: -restart {tmp_path / 'copy'}: {message}")
    assert not changed


@pytest.mark.parametrize("fail_step,kept", [(220, True), (250, False)], ids=["before its last row", "past it"])
def test_a_restart_into_its_own_directory_that_stops_keeps_the_run(tmp_path, finished_past_checkpoint, fail_step, kept):
    """An extending restart into the run's own directory that stops with an error (here a non-finite step, exit 4;
    as for Ctrl-C, a full disk) before it has gone past the run's last row (step 240) leaves the run as it was,
    byte for byte, summary.txt and the snapshot after the checkpoint included (they were removed, so that a later
    restart could shorten the finished run); one that stops past that row keeps its own longer history."""
    out = tmp_path / "run"
    shutil.copytree(finished_past_checkpoint, out)
    before = files_of(out)
    p = subprocess.run([RUN, "test1", str(out), "-restart", str(out), "-T", "14",
                        "-progress", "0"], capture_output=True, text=True,
                       env=dict(os.environ, CONTACT_TEST_NAN_STEP=str(fail_step)))
    assert p.returncode == 4 and len(error_lines(p)) == 1, p.stderr
    after = files_of(out)
    assert not (out / ".restart_kept").exists()
    if kept:
        assert after == before and "the restart stopped before it passed the run's last row" in p.stdout
    else:
        assert len(after["history.csv"].decode().splitlines()) == fail_step + 1
        assert after["history.csv"].startswith(before["history.csv"][:-1].rsplit(b"\n", 1)[0])
        assert "snapshot_t11.5.csv" in after and "summary.txt" not in after


def test_a_restart_of_a_stopped_run_may_finish_it_but_not_shorten_it(tmp_path, finished_past_checkpoint):
    """A run stopped after step 240 without its summary (killed: rows past its checkpoint at 200): a restart into
    its directory to a -T below that row is refused (exit 3, files unchanged); to that row, it finishes the
    run, with the same history, byte for byte."""
    out = tmp_path / "run"
    shutil.copytree(finished_past_checkpoint, out)
    os.remove(out / "summary.txt")
    before = files_of(out)
    p = run_scene("test1", out, ["-restart", str(out), "-T", "11.95"], check=False)
    assert p.returncode == 3 and files_of(out) == before and error_lines(p) == [
        f"error: -restart {out}: its history.csv holds steps up to 240 (t = 12), beyond -T 11.95; a restart never shortens "
        "its run: give a -T of at least 12 (or restart into another directory)"], p.stderr
    run_scene("test1", out, ["-restart", str(out), "-T", "12"])
    after = files_of(out)
    assert after["history.csv"] == before["history.csv"] and "summary.txt" in after
    assert {f for f in after if f.startswith(("snapshot", "vonmises"))} == {"snapshot_t11.5.csv", "vonmises_t11.5.vtu"}


def test_a_restart_into_another_directory_may_stop_earlier(tmp_path, finished_past_checkpoint):
    """A restart into another OUT only reads the run: any -T past its checkpoint is allowed (to recompute its end,
    e.g. with another -np), and gives the run's own rows; the run is untouched."""
    before = files_of(finished_past_checkpoint)
    out = tmp_path / "other"
    run_scene("test1", out, ["-restart", finished_past_checkpoint, "-T", "11", "-progress", "0"])
    rows = (out / "history.csv").read_text().splitlines()
    assert len(rows) == 222 and rows == before["history.csv"].decode().splitlines()[:222]
    assert files_of(finished_past_checkpoint) == before


def test_a_restart_keeps_the_snapshots_it_keeps_in_the_runs_list(tmp_path, finished):
    """The snapshots up to the checkpoint are kept; a restart whose -snapshots leaves one out would record a list
    without it, and a later restart would remove the file: refused, as is -vtk 0 on a run that wrote .vtu files
    up to its checkpoint. Into another directory too (exit 3, one line, files unchanged)."""
    vtk = tmp_path / "vtk"
    run_scene("test1", vtk, ["-T", "1", "-snapshots", "0.5", "-checkpoint_every", "10", "-progress", "0"])
    for run, args, message in [
            (finished, ["-T", "12", "-snapshots", "5,11"], "-snapshots leaves out t = 0, a snapshot of the run before its "
                                                            "checkpoint (t = 10), which the restart keeps: list it too"),
            (str(vtk), ["-T", "2", "-vtk", "0"], "-vtk 0, but the run wrote .vtu files up to its checkpoint (t = 1), which "
                                                 "the restart keeps: leave out -vtk 0")]:
        for into in ("itself", "another"):
            out = tmp_path / into
            shutil.rmtree(out, ignore_errors=True)
            if into == "itself":
                shutil.copytree(run, out)
            before = files_of(out) if into == "itself" else None
            p = run_scene("test1", out, ["-restart", str(out) if into == "itself" else run] + args, check=False)
            assert p.returncode == 3 and len(error_lines(p)) == 1 and message in error_lines(p)[0], p.stderr
            assert (files_of(out) == before) if into == "itself" else not out.exists()


def test_restart_without_checkpoint_is_a_clear_error(tmp_path):
    p = run_scene("test1", tmp_path / "out", ["-restart", str(tmp_path)], check=False)
    assert p.returncode == 3 and "no checkpoint.txt there" in p.stderr


# ---- a full disk: RLIMIT_FSIZE makes every write beyond the limit fail (EFBIG), as a
# full disk does (ENOSPC); SIGXFSZ is ignored so that the write fails instead of killing.

def disk_limit(kib):
    def limit():
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
        resource.setrlimit(resource.RLIMIT_FSIZE, (kib * 1024, kib * 1024))
    return limit


@pytest.mark.parametrize("kib,args,message", [
    (40, [], "cannot write mesh.msh in the output directory (disk full?); the output directory is unchanged"),
    (100, ["-snapshots", "0", "-vtk", "1"], "cannot write vonmises_t0.vtu in the output directory (disk full?); "
                                            "the output directory is unchanged"),
], ids=["mesh", "vtu"])
def test_full_disk_before_the_first_step_changes_nothing(tmp_path, earlier_run, kib, args, message):
    p, changed = refused_into_copy(tmp_path, earlier_run, "test1", ["-T", "1", "-progress", "0"] + args,
                                   preexec_fn=disk_limit(kib))
    assert p.returncode == 7 and error_lines(p) == [f"error: {message}"], p.stderr
    assert not changed


def test_full_disk_mid_run_keeps_complete_rows_and_a_consistent_checkpoint(tmp_path):
    """history.csv outgrows the limit at about step 580: the run stops with exit 7, the
    history keeps its complete rows (a partial last row is removed), the last checkpoint
    is complete, and once there is room again the restart gives the uninterrupted history."""
    out = tmp_path / "full"
    args = ["-T", "80", "-solver", "activeset", "-snapshots", "none", "-checkpoint_every", "100"] + SHORT
    p = run_scene("test1", out, args, check=False, preexec_fn=disk_limit(100))
    assert p.returncode == 7 and len(error_lines(p)) == 1
    assert "cannot write history.csv in the output directory (disk full?); history.csv keeps every complete step" \
        in error_lines(p)[0]
    text = open(out / "history.csv").read()
    assert text.endswith("\n")
    h = read_run(str(out))
    assert 400 < len(h["t"]) < 800 and (h["step"] == np.arange(len(h["t"]))).all()
    assert np.isfinite(np.column_stack(list(h.values()))).all()
    assert not (out / "summary.txt").exists() and not (out / "checkpoint.txt.part").exists()
    run_scene("test1", out, ["-restart", str(out)])
    straight = tmp_path / "straight"
    run_scene("test1", straight, args)
    same_history(read_run(str(out)), read_run(str(straight)))


def test_full_disk_at_a_checkpoint_leaves_no_partial_file(tmp_path):
    out = tmp_path / "full"
    p = run_scene("test1", out, ["-T", "5", "-solver", "activeset", "-snapshots", "none", "-checkpoint_every", "50"]
                  + SHORT, check=False, preexec_fn=disk_limit(80))
    assert p.returncode == 7 and "cannot write checkpoint.txt in the output directory (disk full?)" in p.stderr
    assert sorted(f for f in os.listdir(out) if "checkpoint" in f) == []
    assert len(read_run(str(out))["t"]) >= 51


# ---- one run per output directory

def test_second_run_into_a_busy_directory_is_refused(tmp_path):
    out = tmp_path / "busy"
    first = start("test1", out, ["-T", "20"] + SHORT)
    wait_for_rows(out / "history.csv", 20)
    p = run_scene("test1", out, ["-T", "1", "-solver", "activeset"] + SHORT, check=False)
    assert p.returncode == 3 and len(error_lines(p)) == 1
    assert f"is in use by another run (pid {first.pid}, started " in error_lines(p)[0]
    assert first.poll() is None                       # the first run goes on
    os.killpg(first.pid, signal.SIGKILL)
    first.wait()
    h = read_run(str(out))
    assert (h["step"] == np.arange(len(h["t"]))).all() and len(h["t"]) > 21   # one run's rows, in order


def test_restart_from_a_run_that_is_still_going_is_refused(tmp_path):
    busy = tmp_path / "busy"
    first = start("test1", busy, ["-T", "20", "-checkpoint_every", "20"] + SHORT)
    wait_for_rows(busy / "history.csv", 30)
    p = run_scene("test1", tmp_path / "other", ["-restart", str(busy), "-T", "30"], check=False)
    assert p.returncode == 3 and len(error_lines(p)) == 1 and "that run is still going (pid" in error_lines(p)[0]
    assert not (tmp_path / "other").exists()
    os.killpg(first.pid, signal.SIGKILL)
    first.wait()


# ---- IPOPT failures

def test_ipopt_failure_is_retried_from_u_n(tmp_path, histories):
    # max_iter 1 makes every first IPOPT attempt fail; the retry must give the same step
    out = tmp_path / "retry"
    run_scene("test1", out, ["-T", "12", "-ipopt_max_iter", "1"] + SHORT)
    h = read_run(str(out))
    n = len(h["t"])
    assert np.abs(h["u2_low"] - histories["test1"]["u2_low"][:n]).max() < 1e-6
    summary = dict(line.split(None, 1) for line in open(out / "summary.txt"))
    assert int(summary["ipopt_retries"]) == int(h["qp_solved"].sum()) > 0


def test_failed_step_stops_cleanly_and_keeps_the_history(tmp_path):
    out = tmp_path / "fail"
    p = run_scene("test1", out, ["-T", "12", "-ipopt_max_iter", "1", "-ipopt_retry", "0", "-progress", "0"],
                  check=False)
    assert p.returncode == 4
    errors = [line for line in p.stderr.splitlines() if line.strip()]
    assert len(errors) == 1 and "ipopt failed at step" in errors[0] and "t = " in errors[0] and "status -1" in errors[0]
    h = read_run(str(out))
    failed_step = int(errors[0].split("step ")[1].split(",")[0])
    assert (h["step"] == np.arange(failed_step)).all()     # every step before the failure is there
