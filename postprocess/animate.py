"""Animate a run: the deformed body coloured by von Mises, over the foundation, at every time of its run.pvd.

    postprocess/animate.py --run DIR [--out FILE.gif] [--mp4] [--fps N] [--dpi N] [--vmax V]

One frame per snapshot time of DIR/run.pvd (a run with -vtk 1 and snapshots, e.g. -snapshots every:0.25):
the body at its deformed position (points + displacement of vonmises_t<t>.vtu) coloured by the von Mises
stress per triangle, its boundary, the foundation polyline of that time (foundation_t<t>.vtu) with the
ground below it, and the time. The colour scale (0 to the largest von Mises of all frames, or --vmax) and
the axes (the body over all frames and the foundation under it) are the same in every frame.

Writes DIR/animation.gif (Pillow), and with --mp4 also the .mp4 beside it when ffmpeg is on PATH (without
it, a `note:` line says it is skipped). Each file is written under a temporary name in its directory and
renamed when complete, so a failure leaves no half file. On stdout, a line `animation: frame K/N` every
10 frames, then one naming the files written, the frame count, their sizes and the time taken; on stderr,
only `note:` and `error:` lines.

Exit status: 0 written; 2 bad usage; 3 bad input (no run.pvd, a listed .vtu missing or unreadable,
fewer than 2 frames, an --out that is not a .gif); 7 a file could not be written.
"""
import argparse
import os
import shutil
import subprocess
import sys
import time
import xml.etree.ElementTree as ET

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import meshio  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib import animation  # noqa: E402
from matplotlib.collections import LineCollection, PolyCollection  # noqa: E402

BAD_INPUT, WRITE_FAILED = 3, 7


class Refused(Exception):
    """An expected failure: one `error:` line and this exit status."""

    def __init__(self, status, message):
        super().__init__(message)
        self.status = status


def series(run_dir):
    """The times of DIR/run.pvd in order: a list of (t, body .vtu, foundation .vtu or None), paths in DIR."""
    pvd = os.path.join(run_dir, "run.pvd")
    if not os.path.isfile(pvd):
        raise Refused(BAD_INPUT, f"{run_dir} has no run.pvd: run it with -vtk 1 and snapshots, "
                                 "e.g. -snapshots every:0.25")
    try:
        entries = ET.parse(pvd).getroot().iter("DataSet")
        by_time = {}
        for e in entries:
            by_time.setdefault(float(e.get("timestep")), {})[e.get("part", "0")] = os.path.join(run_dir, e.get("file"))
    except (ET.ParseError, TypeError, ValueError) as err:
        raise Refused(BAD_INPUT, f"{pvd} is not a readable VTK collection ({err})")
    if any("0" not in parts for parts in by_time.values()):
        raise Refused(BAD_INPUT, f"{pvd} lists a time without a body (part 0)")
    return [(t, parts["0"], parts.get("1")) for t, parts in sorted(by_time.items())]


def read_vtu(path):
    if not os.path.isfile(path):
        raise Refused(BAD_INPUT, f"run.pvd lists {os.path.basename(path)}, which is missing from {os.path.dirname(path)}")
    try:
        return meshio.vtu.read(path)   # not meshio.read, which prints and exits on a damaged file
    except Exception as err:  # meshio raises many kinds on a damaged file
        raise Refused(BAD_INPUT, f"cannot read {path}: {str(err) or 'not a complete .vtu'}")


def load_frames(run_dir):
    """Every frame of the run: dicts with t, xy (deformed points), tri, edges (boundary lines), vonmises
    (per triangle) and foundation (its polyline's points, or None)."""
    frames = []
    for t, body, foundation in series(run_dir):
        m = read_vtu(body)
        try:
            xy = m.points[:, :2] + m.point_data["displacement"][:, :2]
            vm = m.cell_data_dict["vonmises"]["triangle"].ravel()
            tri = m.cells_dict["triangle"]
        except KeyError as err:
            raise Refused(BAD_INPUT, f"{body} has no {err} (not a body .vtu of this suite?)")
        frames.append({"t": t, "xy": xy, "tri": tri, "edges": m.cells_dict.get("line"), "vonmises": vm,
                       "foundation": read_vtu(foundation).points[:, :2] if foundation else None})
    if len(frames) < 2:
        raise Refused(BAD_INPUT, f"{run_dir}/run.pvd has {len(frames)} snapshot time(s); an animation needs 2 or more "
                                 "(e.g. -snapshots every:0.25)")
    return frames


def colour_scale(frames, vmax=None):
    """(vmin, vmax) of every frame: 0 to the largest von Mises over all frames (or to vmax)."""
    top = max(float(f["vonmises"].max()) for f in frames) if vmax is None else vmax
    return 0.0, top if top > 0 else 1.0


def axes_limits(frames):
    """(x0, x1, y0, y1) of every frame: the body over all frames, and the foundation under it, with a margin."""
    xy = np.vstack([f["xy"] for f in frames])
    (x0, y0), (x1, y1) = xy.min(axis=0), xy.max(axis=0)
    pad = 0.08 * max(x1 - x0, y1 - y0)
    x0, x1 = x0 - pad, x1 + pad
    for f in frames:
        if f["foundation"] is not None:
            near = f["foundation"][(f["foundation"][:, 0] >= x0) & (f["foundation"][:, 0] <= x1)]
            if len(near):
                y0 = min(y0, near[:, 1].min())
    return x0, x1, y0 - pad, y1 + pad


def draw(frames, vmax=None):
    """The figure and a function that draws frame k on it."""
    vmin, vmax_ = colour_scale(frames, vmax)
    x0, x1, y0, y1 = axes_limits(frames)
    fig, ax = plt.subplots(figsize=(5, np.clip(1.4 + 3.7 * (y1 - y0) / (x1 - x0), 2.6, 6.4)), layout="constrained")
    ax.set(xlim=(x0, x1), ylim=(y0, y1), aspect="equal")
    body = PolyCollection([], cmap="jet", edgecolors="face", linewidths=0.2)
    body.set_clim(vmin, vmax_)
    ax.add_collection(body)
    outline = ax.add_collection(LineCollection([], colors="k", linewidths=0.6))
    ground, = ax.fill([], [], facecolor="0.9", edgecolor="0.6", linewidth=0, hatch="//", zorder=0)
    line, = ax.plot([], [], "k-", lw=1.5)
    clock = ax.set_title(" ", loc="left", family="monospace")
    label = "von Mises stress (fixed scale: 0 to " + (f"{vmax_:.3g}, --vmax)" if vmax is not None
                                                       else f"the max over all frames, {vmax_:.3g})")
    fig.colorbar(body, ax=ax, orientation="horizontal", fraction=0.04, shrink=0.9, aspect=36,
                 extend="max" if vmax is not None else "neither").set_label(label, fontsize=9)

    def frame(k):
        f = frames[k]
        body.set_verts(f["xy"][f["tri"]])
        body.set_array(f["vonmises"])
        outline.set_segments(f["xy"][f["edges"]] if f["edges"] is not None else [])
        if f["foundation"] is not None:
            fx, fy = f["foundation"][:, 0], f["foundation"][:, 1]
            line.set_data(fx, fy)
            ground.set_xy(np.column_stack([np.r_[fx, fx[-1], fx[0]], np.r_[fy, y0 - 1, y0 - 1]]))
        clock.set_text(f"t = {f['t']:g}")
    frame(len(frames) - 1)
    fig.canvas.draw()
    fig.set_layout_engine("none")   # the layout of the last frame, kept for every frame
    return fig, frame


def write(frames, targets, fps, dpi, vmax=None):
    """Render every frame into each target (a .gif, and a .mp4 if listed), each under a temporary name
    renamed when complete; whatever happens, no temporary file is left."""
    fig, frame = draw(frames, vmax)
    writers = [animation.PillowWriter(fps=fps), animation.FFMpegWriter(fps=fps)][:len(targets)]
    parts = [t[:-4] + ".part" + t[-4:] for t in targets]
    try:
        for w, part in zip(writers, parts):
            open(part, "wb").close()      # fail before rendering when it cannot be written
            w.setup(fig, part, dpi=dpi)
        for k in range(len(frames)):
            frame(k)
            for w in writers:
                w.grab_frame()
            if (k + 1) % 10 == 0 or k + 1 == len(frames):
                print(f"animation: frame {k + 1}/{len(frames)}", flush=True)
        for w in writers:
            w.finish()
        for part, target in zip(parts, targets):
            os.replace(part, target)
    except (OSError, subprocess.CalledProcessError) as err:   # ffmpeg's failure is a CalledProcessError
        raise Refused(WRITE_FAILED, f"cannot write {' and '.join(targets)}: {err}")
    finally:
        plt.close(fig)
        for part in parts:
            if os.path.exists(part):
                os.remove(part)


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--run", required=True, help="the run directory (with run.pvd)")
    p.add_argument("--out", help="the GIF (default DIR/animation.gif); the MP4 is beside it, same name")
    p.add_argument("--mp4", action="store_true", help="also an MP4, when ffmpeg is on PATH")
    p.add_argument("--fps", type=int, default=12, help="frames per second (default 12)")
    p.add_argument("--dpi", type=int, default=100, help="pixels per inch of the figure, 5 in wide (default 100)")
    p.add_argument("--vmax", type=float, help="top of the colour scale (default: the max over all frames)")
    a = p.parse_args(argv)
    if a.fps < 1 or a.dpi < 10 or (a.vmax is not None and not a.vmax > 0):
        p.error("--fps must be at least 1, --dpi at least 10 and --vmax positive")
    started = time.time()
    targets = [a.out or os.path.join(a.run, "animation.gif")]
    try:
        if not targets[0].endswith(".gif"):
            raise Refused(BAD_INPUT, f"--out {targets[0]}: the animation is a .gif")
        frames = load_frames(a.run)
        if a.mp4 and shutil.which("ffmpeg"):
            targets.append(targets[0][:-4] + ".mp4")
        elif a.mp4:
            print("note: ffmpeg is not on PATH: no MP4, only the GIF", file=sys.stderr)
        write(frames, targets, a.fps, a.dpi, a.vmax)
    except Refused as err:
        print(f"error: {err}", file=sys.stderr)
        return err.status
    written = " and ".join(f"{t} ({os.path.getsize(t) / 1e6:.2f} MB)" for t in targets)
    print(f"animation: wrote {written}, {len(frames)} frames at {a.fps} fps, in {time.time() - started:.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
