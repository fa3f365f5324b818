"""postprocess/animate.py: the animation of a run from its run.pvd (issue 24), on a tiny run, and the
3D view (a side view of the section X2 = 0) on a short ball run."""
import os
import shutil
import subprocess

import matplotlib.collections
import matplotlib.colors
import matplotlib.lines
import matplotlib.quiver
import meshio
import numpy as np
import pytest
from PIL import Image

import animate as animate_module
from conftest import ROOT, files_of, make, run_scene
from animate import Refused, body_3d, colour_scale, draw, load_frames, main, series

ANIMATE = [os.path.join(ROOT, "postprocess", "animate.py")]
PYTHON = "/usr/bin/python3"
DPI = 40


@pytest.fixture(scope="module")
def tiny_run(tmp_path_factory):
    """Test 1 to T = 2 with a snapshot every 0.5: five times in run.pvd, each with a foundation."""
    out = tmp_path_factory.mktemp("animation") / "run"
    run_scene("test1", out, ["-T", "2", "-snapshots", "every:0.5", "-progress", "0"])
    return str(out)


@pytest.fixture(scope="module")
def ball_run(tmp_path_factory):
    """The ball (Test 1 in 3D) to T = 12 with a snapshot every 4: it falls from 4 above the foundation
    X3 = 0 and touches it at t = 8.9 (t = 12 is in the impact)."""
    out = tmp_path_factory.mktemp("animation3d") / "ball"
    run_scene("ball", out, ["-T", "12", "-solver", "activeset", "-snapshots", "every:4", "-progress", "0"])
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


def polygon_area(p):
    x, y = np.asarray(p).T
    return 0.5 * abs(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))


def test_3d_section(ball_run):
    """A 3D frame is the ball's section by the plane X2 = 0, seen along X2, at the deformed position: at
    t = 0 a disk of radius 20 (to the mesh's facets) from X3 = 4 to 44, each piece coloured by its
    tetrahedron's von Mises (the colour scale's top is the section's largest), its outline on the disk's
    circle; the foundation X3 = 0 is its section,
    a polyline in increasing X1 under the ball."""
    frames = load_frames(ball_run)
    assert [f["t"] for f in frames] == [0, 4, 8, 12] and {f["dim"] for f in frames} == {3}
    f = frames[0]
    assert f["xy"][:, 1].min() == pytest.approx(4, abs=1e-9) and f["xy"][:, 1].max() == pytest.approx(44, abs=0.1)
    assert f["xy"][:, 0].min() == pytest.approx(-20, abs=0.1) and f["xy"][:, 0].max() == pytest.approx(20, abs=0.1)
    assert sum(polygon_area(p) for p in f["polys"]) == pytest.approx(np.pi * 20 ** 2, rel=0.02)
    assert len(f["vonmises"]) == len(f["polys"])
    tets = meshio.vtu.read(os.path.join(ball_run, "vonmises_t0.vtu")).cell_data_dict["vonmises"]["tetra"]
    assert set(f["vonmises"]) <= set(tets.ravel())
    assert colour_scale(frames)[1] == max(f["vonmises"].max() for f in frames)      # the section's largest
    radius = np.hypot(f["segments"][..., 0], f["segments"][..., 1] - 24)
    assert radius.max() == pytest.approx(20, abs=1e-5) and radius.min() > 19.5     # the facets of the sphere
    for f in frames:
        fx, fz = f["foundation"].T
        assert np.all(np.diff(fx) > 0) and np.all(fz == 0) and fx[0] < -20 and fx[-1] > 20


def test_3d_frames_show_the_fall_and_impact(ball_run):
    """Drawn, the ball's lowest point moves down the frame as it falls (X3 = 4 at t = 0) until it reaches
    the foundation's line (X3 = 0 at t = 12, in the impact); the foundation is one line, horizontal and
    at the same height in every frame, and the axes are the same in every frame."""
    frames = load_frames(ball_run)
    fig, frame = draw(frames)
    ax = fig.axes[0]
    lowest, foundation, limits = [], [], set()
    for k in range(len(frames)):
        frame(k)
        fig.canvas.draw()
        body = np.vstack([ax.transData.transform(p.vertices) for p in ax.collections[0].get_paths()])
        lowest.append(body[:, 1].min())       # display pixels, upwards
        lines = [a for a in ax.get_children() if isinstance(a, matplotlib.lines.Line2D)]
        assert len(lines) == 1
        foundation.append(ax.transData.transform(lines[0].get_xydata()))
        limits.add((ax.get_xlim(), ax.get_ylim()))
    assert len(limits) == 1
    (x0, x1), (y0, y1) = limits.pop()
    assert x0 < -20 and x1 > 20 and y0 < 0 and y1 > 44
    scale = ax.transData.transform((0, 1))[1] - ax.transData.transform((0, 0))[1]     # pixels a unit of X3
    ground = foundation[0][:, 1]
    assert all(np.ptp(g[:, 1]) < 1e-6 and g[0, 1] == pytest.approx(ground[0]) for g in foundation)
    assert lowest[0] - ground[0] == pytest.approx(4 * scale, rel=1e-6)
    assert lowest[0] > lowest[1] > lowest[2] > lowest[3]
    assert abs(lowest[3] - ground[0]) < 0.1 * scale


def test_3d_animation(ball_run, tmp_path):
    """The GIF of a 3D run has one frame per time, and the body's lowest coloured pixel (saturated: the
    body, not the grey ground, the black lines or the white background) is lower in the impact's frame
    than at t = 0, by the 4 units of the fall."""
    run = copy_run(ball_run, tmp_path)
    p = animate(run)
    assert p.returncode == 0 and p.stderr == "", p.stderr
    rows = []
    with Image.open(run / "animation.gif") as im:
        assert im.n_frames == 4
        for k in (0, 3):
            im.seek(k)
            rgb = np.asarray(im.convert("RGB")).astype(int)
            body = rgb.max(axis=2) - rgb.min(axis=2) > 60
            body[int(0.85 * rgb.shape[0]):] = False         # not the colour bar
            rows.append(np.flatnonzero(body.any(axis=1)).max())
    frames = load_frames(run)
    fig, _ = draw(frames)
    ax = fig.axes[0]
    scale = (ax.transData.transform((0, 1))[1] - ax.transData.transform((0, 0))[1]) * DPI / fig.dpi
    assert rows[1] - rows[0] == pytest.approx(4 * scale, abs=2)


def test_3d_plane_misses_the_body(ball_run):
    """A 3D body that the plane X2 = 0 does not cut is refused (exit 3) with a line naming the plane."""
    m = meshio.vtu.read(os.path.join(ball_run, "vonmises_t0.vtu"))
    m.points[:, 1] += 50
    with pytest.raises(Refused, match="X2 = 0") as err:
        body_3d(m, "vonmises_t0.vtu")
    assert err.value.status == 3


BAD_OPTIONS = [["--dpi", "100000"], ["--dpi", "3000"], ["--dpi", "301"], ["--dpi", "9"], ["--dpi", "1e3"],
               ["--dpi", "x"], ["--dpi"], ["--fps", "0"], ["--fps", "51"], ["--fps", "-1"], ["--fps", "2.5"],
               ["--vmax", "inf"], ["--vmax", "-inf"], ["--vmax", "nan"], ["--vmax", "0"], ["--vmax", "-1"],
               ["--vmax", "1e309"], ["--vmax", "x"], ["--out", ""], ["--run", ""], ["--bogus"]]


@pytest.fixture(scope="module")
def animated_run(tiny_run, tmp_path_factory):
    """A copy of the tiny run with its animation.gif."""
    run = copy_run(tiny_run, tmp_path_factory.mktemp("animated"))
    assert animate(run).returncode == 0
    return run


@pytest.mark.parametrize("bad", BAD_OPTIONS, ids=" ".join)
def test_bad_option(animated_run, tmp_path, bad):
    """Every option is bounded (--dpi 10 to 300, --fps 1 to 50, --vmax positive and finite, paths not
    empty): anything else is refused with exit 2 and one `error:` line naming the option, and the
    earlier animation stays byte-identical."""
    run = copy_run(animated_run, tmp_path)
    before = files_of(run)
    p = animate(run, *bad)
    assert refused(p, 2) and p.stdout == "", p.stderr
    assert bad[0] in p.stderr or "unrecognized" in p.stderr
    assert files_of(run) == before


def test_too_many_pixels(tiny_run, tmp_path, monkeypatch, capsys):
    """Frames whose pixels in all exceed MAX_PIXELS (the GIF's frames are held in memory) are refused
    before rendering: exit 3, one `error:` line naming the sizes, the earlier animation kept."""
    run = copy_run(tiny_run, tmp_path)
    assert main(["--run", str(run), "--dpi", str(DPI)]) == 0
    before = files_of(run)
    capsys.readouterr()
    monkeypatch.setattr(animate_module, "MAX_PIXELS", 5 * (5 * DPI) ** 2)     # 5 frames of 200 x ~208 px
    assert main(["--run", str(run), "--dpi", str(DPI)]) == 3
    out, err = capsys.readouterr()
    assert out == "" and len(err.splitlines()) == 1 and err.startswith("error: 5 frames of 200 x ")
    assert files_of(run) == before


def test_out_is_a_directory(tiny_run, tmp_path):
    """An --out that is a directory is refused before rendering (exit 7, one line), leaving nothing."""
    run = copy_run(tiny_run, tmp_path)
    (run / "a.gif").mkdir()
    before = files_of(run / "a.gif")
    p = animate(run, "--out", str(run / "a.gif"))
    assert refused(p, 7) and "is a directory" in p.stderr and "frame" not in p.stdout, p.stderr
    assert files_of(run / "a.gif") == before and not [f for f in os.listdir(run) if ".part" in f]


def test_a_friction_run_marks_stick_and_slip(tmp_path, tiny_run):
    """A plane run with friction (the slide scene): each frame marks Gamma_C's pressed nodes, red where they slip
    and blue where they stick, and draws the tangential traction's arrows (issue 35, item 5); skidding at t = 2 every
    marker is red and the arrows point to -X1, against the motion. A frictionless run's frames have neither."""
    out = tmp_path / "slide"
    run_scene("slide", out, ["-T", "10", "-snapshots", "2,10", "-progress", "0"])
    frames = load_frames(str(out))
    fig, frame = draw(frames)
    frame(0)
    ax = fig.axes[0]
    marks = [c for c in ax.collections if isinstance(c, matplotlib.collections.PathCollection)][0]
    assert len(frames[0]["friction"]["xy"]) > 5 and set(map(tuple, marks.get_facecolors()[:, :3].round(3))) == \
        {tuple(np.round(matplotlib.colors.to_rgb("tab:red"), 3))}
    quiver = [c for c in ax.collections if isinstance(c, matplotlib.quiver.Quiver)]
    assert len(quiver) == 1 and (quiver[0].U < 0).all()
    frame(1)
    assert 1 in frames[1]["friction"]["state"] and len([c for c in ax.collections if isinstance(c, matplotlib.quiver.Quiver)]) == 1
    assert animate(out).returncode == 0
    assert all("friction" not in f for f in load_frames(tiny_run))
