"""postprocess/animate.py: the animation of a run from its run.pvd (issue 24), on a tiny run."""
import os
import shutil
import subprocess

import meshio
import pytest
from PIL import Image

from conftest import ROOT, files_of, make, run_scene
from animate import colour_scale, draw, load_frames, series

ANIMATE = [os.path.join(ROOT, "postprocess", "animate.py")]
PYTHON = "/usr/bin/python3"
DPI = 40


@pytest.fixture(scope="module")
def tiny_run(tmp_path_factory):
    """Test 1 to T = 2 with a snapshot every 0.5: five times in run.pvd, each with a foundation."""
    out = tmp_path_factory.mktemp("animation") / "run"
    run_scene("test1", out, ["-T", "2", "-snapshots", "every:0.5", "-progress", "0"])
    return str(out)


def animate(run_dir, *args, env=None):
    return subprocess.run([PYTHON] + ANIMATE + ["--run", str(run_dir), "--dpi", str(DPI)] + list(args),
                          capture_output=True, text=True, env=env)


def copy_run(tiny_run, tmp_path):
    out = tmp_path / "run"
    shutil.copytree(tiny_run, out)
    return out


def refused(p, status):
    """The process exited with status and wrote exactly one line on stderr, an `error:` line."""
    lines = p.stderr.splitlines()
    return p.returncode == status and len(lines) == 1 and lines[0].startswith("error: ")


def test_one_frame_per_time(tiny_run, tmp_path):
    """The GIF has one frame per time of run.pvd, in order, of the figure's size in pixels, and the last
    line names it with the frame count; no temporary file is left."""
    run = copy_run(tiny_run, tmp_path)
    times = [t for t, _, _ in series(run)]
    assert times == [0, 0.5, 1, 1.5, 2]
    p = animate(run)
    assert p.returncode == 0, p.stderr
    gif = run / "animation.gif"
    assert p.stdout.splitlines()[-1].startswith(f"animation: wrote {gif} (")
    assert f"{len(times)} frames" in p.stdout
    with Image.open(gif) as im:
        assert im.n_frames == len(times)
        assert im.size[0] == 5 * DPI and 4.5 * DPI <= im.size[1] <= 5.5 * DPI   # 5 x 5.2 in for the disk
    assert not [f for f in os.listdir(run) if ".part" in f]


def test_fixed_scale_and_axes(tiny_run):
    """The colour scale is 0 to the largest per-triangle von Mises over all the .vtu files, and drawing
    every frame changes neither it nor the axes (their limits and their place in the figure)."""
    frames = load_frames(tiny_run)
    largest = max(meshio.read(b).cell_data_dict["vonmises"]["triangle"].max() for _, b, _ in series(tiny_run))
    assert colour_scale(frames) == (0, pytest.approx(largest, rel=1e-12))
    fig, frame = draw(frames)
    ax = fig.axes[0]
    seen = set()
    for k in range(len(frames)):
        frame(k)
        fig.canvas.draw()
        seen.add((ax.collections[0].get_clim(), ax.get_xlim(), ax.get_ylim(), tuple(ax.get_position().bounds)))
    assert len(seen) == 1
    (vmin, vmax), (x0, x1), (y0, y1), _ = seen.pop()
    assert (vmin, vmax) == colour_scale(frames)
    for f in frames:      # the body of every frame, and the foundation under it, is inside the axes
        assert x0 < f["xy"][:, 0].min() and f["xy"][:, 0].max() < x1
        assert y0 < f["foundation"][:, 1].min() and f["xy"][:, 1].max() < y1


def test_no_run_pvd(tmp_path):
    """A directory without run.pvd is refused: exit 3, one `error:` line saying how to get one, no file written."""
    p = animate(tmp_path)
    assert refused(p, 3), p.stderr
    assert "-snapshots every:0.25" in p.stderr
    assert os.listdir(tmp_path) == []


@pytest.mark.parametrize("damage", ["missing", "truncated"])
def test_bad_vtu_keeps_earlier_gif(tiny_run, tmp_path, damage):
    """A run.pvd that lists a missing or truncated .vtu is refused (exit 3, one line naming the file), and
    the earlier animation.gif stays byte-identical, with no temporary file beside it."""
    run = copy_run(tiny_run, tmp_path)
    assert animate(run).returncode == 0
    vtu = run / "vonmises_t1.vtu"
    if damage == "missing":
        vtu.unlink()
    else:
        vtu.write_bytes(vtu.read_bytes()[:2000])
    before = files_of(run)
    p = animate(run)
    assert refused(p, 3) and "vonmises_t1.vtu" in p.stderr, p.stderr
    assert files_of(run) == before


def test_fewer_than_two_frames(tiny_run, tmp_path):
    """A run.pvd with one time is refused: exit 3, one `error:` line."""
    run = copy_run(tiny_run, tmp_path)
    pvd = (run / "run.pvd").read_text().splitlines()
    (run / "run.pvd").write_text("\n".join(line for line in pvd if "DataSet" not in line or 'timestep="0"' in line))
    p = animate(run)
    assert refused(p, 3) and "1 snapshot time" in p.stderr, p.stderr


def test_write_failure(tiny_run, tmp_path):
    """An output that cannot be written (its directory is a file) fails with exit 7, one `error:` line."""
    run = copy_run(tiny_run, tmp_path)
    p = animate(run, "--out", str(run / "history.csv" / "a.gif"))
    assert refused(p, 7), p.stderr


def test_mp4_without_ffmpeg(tiny_run, tmp_path):
    """--mp4 without ffmpeg on PATH writes the GIF, says in a `note:` line that the MP4 is skipped, exits 0."""
    run = copy_run(tiny_run, tmp_path)
    p = animate(run, "--mp4", env=dict(os.environ, PATH=str(tmp_path / "empty")))
    assert p.returncode == 0, p.stderr
    assert any(line.startswith("note: ffmpeg is not on PATH") for line in p.stderr.splitlines())
    assert (run / "animation.gif").exists() and not (run / "animation.mp4").exists()


def fake_ffmpeg(directory, status):
    """A stand-in for ffmpeg in directory: it copies its input (the raw frames) into its last argument,
    the output file, and exits with status. Returns an environment with it first on PATH."""
    os.makedirs(directory, exist_ok=True)
    path = os.path.join(directory, "ffmpeg")
    with open(path, "w") as f:
        f.write(f'#!/bin/sh\nfor last; do :; done\ncat > "$last"\nexit {status}\n')
    os.chmod(path, 0o755)
    return dict(os.environ, PATH=f"{directory}:{os.environ['PATH']}")


def test_mp4(tiny_run, tmp_path):
    """With ffmpeg on PATH, --mp4 writes the MP4 beside the GIF (ffmpeg is given a temporary name in the
    same directory, renamed when it succeeds) and names both on the last line."""
    run = copy_run(tiny_run, tmp_path)
    p = animate(run, "--mp4", env=fake_ffmpeg(tmp_path / "bin", 0))
    assert p.returncode == 0, p.stderr
    assert (run / "animation.mp4").stat().st_size > 0 and (run / "animation.gif").exists()
    assert f"and {run / 'animation.mp4'} (" in p.stdout.splitlines()[-1]
    assert not [f for f in os.listdir(run) if ".part" in f]


def test_ffmpeg_failure(tiny_run, tmp_path):
    """When ffmpeg fails, the run fails with exit 7 and one `error:` line, and writes neither file."""
    run = copy_run(tiny_run, tmp_path)
    before = files_of(run)
    p = animate(run, "--mp4", env=fake_ffmpeg(tmp_path / "bin", 1))
    assert refused(p, 7), p.stderr
    assert files_of(run) == before


def test_make_animation(tiny_run, tmp_path):
    """make animation OUT=DIR writes DIR/animation.gif; without OUT (or with an empty one), make refuses in
    one line naming OUT=DIR, exit 2, before it builds anything."""
    run = copy_run(tiny_run, tmp_path)
    p = make(["animation", f"OUT={run}"])
    assert p.returncode == 0, p.stderr
    assert (run / "animation.gif").exists()
    for args in (["animation"], ["animation", "OUT="]):
        p = make(args)
        assert p.returncode == 2 and p.stdout == ""
        assert len(p.stderr.splitlines()) == 1 and "make animation needs OUT=DIR" in p.stderr
