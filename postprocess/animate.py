"""Animate a run: the deformed body coloured by von Mises, over the foundation, at every time of its run.pvd.

    postprocess/animate.py --run DIR [--out FILE.gif] [--mp4] [--fps N] [--dpi N] [--vmax V]

One frame per snapshot time of DIR/run.pvd (a run with -vtk 1 and snapshots, e.g. -snapshots every:0.25):
the body at its deformed position (points + displacement of vonmises_t<t>.vtu) coloured by the von Mises
stress per triangle, its boundary, the foundation polyline of that time (foundation_t<t>.vtu) with the
ground below it, and the time. A 3D body is seen along X2: its section by the plane X2 = 0 in (X1 + u1,
X3 + u3), coloured per tetrahedron, and the foundation's section by that plane. The colour scale (0 to
the largest von Mises of all frames, or --vmax) and the axes (the body over all frames and the
foundation under it) are the same in every frame. A plane run with friction also marks Gamma_C's pressed
nodes, sticking (blue) or slipping (red), with an arrow for the tangential traction on the body along the
foundation (one scale for every frame).

Writes DIR/animation.gif (Pillow), and with --mp4 also the .mp4 beside it when ffmpeg is on PATH (without
it, a `note:` line says it is skipped). Each file is written under a temporary name in its directory and
renamed when complete, so a failure leaves no half file. On stdout, a line `animation: frame K/N` every
10 frames, then one naming the files written, the frame count, their sizes and the time taken; on stderr,
only `note:` and `error:` lines.

Exit status: 0 written; 2 bad usage (an option out of its range: --fps 1 to 50, --dpi 10 to 300, --vmax
positive and finite; an empty path); 3 bad input (no run.pvd, a listed .vtu, or a -np N run's .pvtu or one
of its pieces, missing or unreadable, fewer than 2 frames, a 3D body that the plane X2 = 0 misses, an --out
that is not a .gif, frames of more than 500 million pixels in all); 7 a file could not be written.
"""
import argparse
import math
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
from PIL import Image  # noqa: E402

import jobs  # noqa: E402

BAD_INPUT, WRITE_FAILED = 3, 7
MAX_FPS = 50                 # a GIF's frame delay is in hundredths of a second; browsers slow 0.01 s to 0.1 s
MAX_DPI = 300                # a frame of at most 1500 x 1920 px (the figure is 5 in wide, at most 6.4 in high)
MAX_PIXELS = 500_000_000     # the GIF's frames in all (a byte each in memory, twice while Pillow writes them)


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


def read_vtu(path, listed_by="run.pvd"):
    """A .vtu, or a -np N run's .pvtu (its pieces merged: read_pvtu)."""
    if not os.path.isfile(path):
        raise Refused(BAD_INPUT, f"{listed_by} lists {os.path.basename(path)}, which is missing from {os.path.dirname(path)}")
    if path.endswith(".pvtu"):
        return read_pvtu(path)
    try:
        return meshio.vtu.read(path)   # not meshio.read, which prints and exits on a damaged file
    except Exception as err:  # meshio raises many kinds on a damaged file
        raise Refused(BAD_INPUT, f"cannot read {path}: {str(err) or 'not a complete .vtu'}")


def read_pvtu(path):
    """The body of a .pvtu (-np N, docs/parallel.md): its pieces, one a process, merged into one mesh. Every cell is
    in one piece; a vertex on the border of two is in both with the same values (merged by its coordinates). The
    faces between two pieces are a boundary face of each, so a boundary cell (a line in 2D, a triangle in 3D) that
    two pieces hold is dropped: what is left is the body's boundary, as in a serial run's .vtu."""
    try:
        sources = [e.get("Source") for e in ET.parse(path).getroot().iter("Piece")]
    except ET.ParseError as err:
        raise Refused(BAD_INPUT, f"{path} is not a readable .pvtu ({err})")
    if not sources or None in sources:
        raise Refused(BAD_INPUT, f"{path} names no piece")
    pieces = [read_vtu(os.path.join(os.path.dirname(path), s), listed_by=os.path.basename(path)) for s in sources]
    points, inverse = np.unique(np.vstack([p.points for p in pieces]), axis=0, return_inverse=True)
    inverse = inverse.ravel()
    start = np.cumsum([0] + [len(p.points) for p in pieces])
    point_data = {}
    for name, first in pieces[0].point_data.items():
        point_data[name] = np.zeros((len(points),) + first.shape[1:], dtype=first.dtype)
        for k, p in enumerate(pieces):
            point_data[name][inverse[start[k]:start[k + 1]]] = p.point_data[name]
    volume = "tetra" if any("tetra" in p.cells_dict for p in pieces) else "triangle"
    types = [volume] + sorted({c.type for p in pieces for c in p.cells} - {volume})
    cells, cell_data = [], {name: [] for name in pieces[0].cell_data}
    for kind in types:
        conn = np.vstack([inverse[start[k] + p.cells_dict[kind]] for k, p in enumerate(pieces) if kind in p.cells_dict])
        data = {name: np.concatenate([p.cell_data_dict[name][kind] for p in pieces if kind in p.cells_dict])
                for name in cell_data}
        if kind != volume:      # boundary cells: those of one piece only
            _, which, count = np.unique(np.sort(conn, axis=1), axis=0, return_inverse=True, return_counts=True)
            keep = count[which.ravel()] == 1
            conn, data = conn[keep], {name: v[keep] for name, v in data.items()}
        cells.append((kind, conn))
        for name in cell_data:
            cell_data[name].append(data[name])
    return meshio.Mesh(points, cells, point_data=point_data, cell_data=cell_data)


def body_2d(m, body):
    """A 2D body: its triangles at the deformed position, their von Mises, its boundary lines."""
    try:
        xy = m.points[:, :2] + m.point_data["displacement"][:, :2]
        vm = m.cell_data_dict["vonmises"]["triangle"].ravel()
        tri = m.cells_dict["triangle"]
    except KeyError as err:
        raise Refused(BAD_INPUT, f"{body} has no {err} (not a body .vtu of this suite?)")
    lines = m.cells_dict.get("line")
    frame = {"xy": xy, "polys": xy[tri], "vonmises": vm, "segments": xy[lines] if lines is not None else []}
    if "contact_state" in m.point_data:      # a run with friction: Gamma_C's nodes, their state and traction
        state = m.point_data["contact_state"].ravel()
        on = state > 0
        frame["friction"] = {"xy": xy[on], "state": state[on], "traction": m.point_data["tangential_traction"].ravel()[on]}
    return frame


# the edges of a tetrahedron (a triangle) whose vertices, sorted negative side first, are split k | rest
# by the plane, in the order of a cycle around their section (a triangle or a quadrilateral)
CUT_EDGES = {4: {1: [(0, 1), (0, 2), (0, 3)], 2: [(0, 2), (0, 3), (1, 3), (1, 2)], 3: [(0, 3), (1, 3), (2, 3)]},
             3: {1: [(0, 1), (0, 2)], 2: [(0, 2), (1, 2)]}}


def cut(cells, X2, *fields):
    """The sections of cells (tetrahedra or triangles: vertex indices) by the plane X2 = 0: a list, one
    item per number k of vertices on the negative side, of (the indices of the cells cut, and for each of
    fields (point arrays) its values at the section's corners, shape (cells, corners, ...)). A vertex on
    the plane counts as on the positive side, so a face in the plane is cut once. Every field is linear
    on a P1 cell, so its value at a corner, on an edge, is the edge's linear interpolation: exact."""
    neg = X2[cells] < 0
    order = np.argsort(~neg, axis=1, kind="stable")
    ordered = np.take_along_axis(cells, order, axis=1)
    out = []
    for k, edges in CUT_EDGES[cells.shape[1]].items():
        sel = np.flatnonzero(neg.sum(axis=1) == k)
        i = ordered[sel][:, [a for a, _ in edges]]
        j = ordered[sel][:, [b for _, b in edges]]
        s = (X2[i] / (X2[i] - X2[j]))[..., None]
        out.append((sel, [f[i] + s * (f[j] - f[i]) for f in fields]))
    return out


def boundary_faces(tets):
    """The faces of a tetrahedral mesh that belong to one tetrahedron only: its boundary triangles."""
    faces = np.sort(np.vstack([tets[:, [0, 1, 2]], tets[:, [0, 1, 3]], tets[:, [0, 2, 3]], tets[:, [1, 2, 3]]]), axis=1)
    unique, count = np.unique(faces, axis=0, return_counts=True)
    return unique[count == 1]


def body_3d(m, body):
    """A 3D body seen along X2: its section by the plane X2 = 0 of the reference configuration at the
    deformed position (X1 + u1, X3 + u3), each piece (the section of a tetrahedron) coloured by the
    tetrahedron's von Mises, and the section of its boundary as segments."""
    try:
        X, tets = m.points, m.cells_dict["tetra"]
        xz = (X + m.point_data["displacement"])[:, [0, 2]]
        vm = m.cell_data_dict["vonmises"]["tetra"].ravel()
    except KeyError as err:
        raise Refused(BAD_INPUT, f"{body} has no {err} (not a body .vtu of this suite?)")
    polys, values = [], []
    for sel, (corners,) in cut(tets, X[:, 1], xz):
        polys += list(corners)
        values.append(vm[sel])
    if not polys:
        raise Refused(BAD_INPUT, f"the plane X2 = 0, the 3D view of the animation, does not cut the body of {body}")
    segments = np.vstack([c for _, (c,) in cut(boundary_faces(tets), X[:, 1], xz)])
    return {"xy": np.vstack(polys), "polys": polys, "vonmises": np.concatenate(values), "segments": segments}


def foundation_line(f, dim):
    """The foundation's polyline (X1, X2) in 2D; in 3D, the section of its surface X3 = psi by the plane
    X2 = 0 as the polyline (X1, X3), in increasing X1 (None when the plane misses it)."""
    if dim == 2:
        return f.points[:, :2]
    pieces = cut(f.cells_dict.get("triangle", np.zeros((0, 3), int)), f.points[:, 1], f.points[:, [0, 2]])
    points = np.unique(np.vstack([c.reshape(-1, 2) for _, (c,) in pieces]), axis=0)
    return points if len(points) > 1 else None


def load_frames(run_dir):
    """Every frame of the run: dicts with t, dim, xy (every point drawn of the body), polys (the pieces of
    the body drawn, at the deformed position), vonmises (per piece), segments (its boundary) and
    foundation (its polyline's points, or None). A 2D body is drawn whole; a 3D one by its section X2 = 0."""
    frames = []
    for t, body, foundation in series(run_dir):
        m = read_vtu(body)
        dim = 3 if "tetra" in m.cells_dict else 2
        frame = body_3d(m, body) if dim == 3 else body_2d(m, body)
        frame.update(t=t, dim=dim, foundation=foundation_line(read_vtu(foundation), dim) if foundation else None)
        frames.append(frame)
    if len(frames) < 2:
        raise Refused(BAD_INPUT, f"{run_dir}/run.pvd has {len(frames)} snapshot time(s); an animation needs 2 or more "
                                 "(e.g. -snapshots every:0.25)")
    if len({f["dim"] for f in frames}) > 1:
        raise Refused(BAD_INPUT, f"{run_dir}/run.pvd mixes 2D and 3D bodies")
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
    if frames[0]["dim"] == 3:
        ax.set_title("section X2 = 0, seen along X2", loc="right", fontsize=9)
        ax.set(xlabel="X1", ylabel="X3")
    what, whose = ("section's von Mises", "its") if frames[0]["dim"] == 3 else ("von Mises stress", "the")
    label = f"{what} (fixed scale: 0 to " + (f"{vmax_:.3g}, --vmax)" if vmax is not None
                                              else f"{whose} max over all frames, {vmax_:.3g})")
    fig.colorbar(body, ax=ax, orientation="horizontal", fraction=0.04, shrink=0.9, aspect=36,
                 extend="max" if vmax is not None else "neither").set_label(label, fontsize=9)

    marks, arrows = friction_layer(ax, frames, x1 - x0)

    def frame(k):
        f = frames[k]
        if marks is not None:
            draw_friction(f, marks, arrows)
        body.set_verts(f["polys"])
        body.set_array(f["vonmises"])
        outline.set_segments(f["segments"])
        if f["foundation"] is not None:
            fx, fy = f["foundation"][:, 0], f["foundation"][:, 1]
            line.set_data(fx, fy)
            ground.set_xy(np.column_stack([np.r_[fx, fx[-1], fx[0]], np.r_[fy, y0 - 1, y0 - 1]]))
        clock.set_text(f"t = {f['t']:g}")
    frame(len(frames) - 1)
    fig.canvas.draw()
    fig.set_layout_engine("none")   # the layout of the last frame, kept for every frame
    return fig, frame


def friction_layer(ax, frames, width):
    """The markers and arrows of Gamma_C's friction (None, None for a run without it): the arrows' scale makes
    the largest traction of every frame a tenth of the axes' width."""
    if not any("friction" in f for f in frames):
        return None, None
    top = max([np.abs(f["friction"]["traction"]).max() for f in frames if len(f.get("friction", {}).get("traction", []))]
              or [1.0])
    marks = ax.scatter([], [], s=9, zorder=4)
    arrows = {"ax": ax, "scale": (top or 1.0) / (0.1 * width), "width": width, "quiver": None}     # (redrawn each frame: its count varies)
    ax.text(0.99, 0.01, "\u25cf slip", transform=ax.transAxes, ha="right", va="bottom", fontsize=8, color="tab:red")
    ax.text(0.83, 0.01, "\u25cf stick", transform=ax.transAxes, ha="right", va="bottom", fontsize=8, color="tab:blue")
    return marks, arrows


def draw_friction(f, marks, arrows):
    """Frame f's pressed nodes of Gamma_C, blue where they stick, red where they slip, and the traction's arrows
    along the foundation's tangent there (from its polyline)."""
    fr = f.get("friction", {"xy": np.zeros((0, 2)), "state": np.zeros(0), "traction": np.zeros(0)})
    xy = fr["xy"] if len(fr["xy"]) else np.zeros((0, 2))
    marks.set_offsets(xy)
    marks.set_color(["tab:blue" if s == 1 else "tab:red" for s in fr["state"]])
    tx, ty = np.ones(len(xy)), np.zeros(len(xy))
    if f["foundation"] is not None and len(xy):
        fx, fy = f["foundation"][:, 0], f["foundation"][:, 1]
        slope = np.interp(xy[:, 0], 0.5 * (fx[1:] + fx[:-1]), np.diff(fy) / np.where(np.diff(fx) == 0, 1, np.diff(fx)))
        tx, ty = 1 / np.sqrt(1 + slope**2), slope / np.sqrt(1 + slope**2)
    if arrows["quiver"] is not None:
        arrows["quiver"].remove()
        arrows["quiver"] = None
    if len(xy):     # (drawn in the ground just below the foundation, where the line and the markers do not hide them)
        below = 0.04 * arrows["width"]
        arrows["quiver"] = arrows["ax"].quiver(xy[:, 0] + below * ty, xy[:, 1] - below * tx, fr["traction"] * tx,
                                               fr["traction"] * ty, color="k",
                                               angles="xy", scale_units="xy", scale=arrows["scale"], width=0.004, zorder=5)


class GifWriter(animation.PillowWriter):
    """matplotlib's PillowWriter keeping each frame as the palette image the GIF stores (one byte a pixel)
    instead of RGBA (four), converted as Pillow's GIF writer converts it: the same file, a quarter of the
    memory."""

    def grab_frame(self, **savefig_kwargs):
        super().grab_frame(**savefig_kwargs)
        im = self._frames[-1].convert("P", palette=Image.Palette.ADAPTIVE)
        clear = [k for c, k in im.palette.colors.items() if c[3:] == (0,)]    # (as GifImagePlugin does)
        if im.palette.mode == "RGBA" and clear:
            im.info["transparency"] = clear[0]
        self._frames[-1] = im


def write(frames, targets, fps, dpi, vmax=None):
    """Render every frame into each target (a .gif, and a .mp4 if listed), each under a temporary name
    renamed when complete; whatever happens, no temporary file is left. Refused before rendering when
    the GIF's frames would exceed MAX_PIXELS in all, or a target is a directory."""
    fig, frame = draw(frames, vmax)
    width, height = (int(x * dpi) for x in fig.get_size_inches())    # as matplotlib's writers size a frame
    if len(frames) * width * height > MAX_PIXELS:
        plt.close(fig)
        raise Refused(BAD_INPUT, f"{len(frames)} frames of {width} x {height} px are "
                                 f"{len(frames) * width * height / 1e6:.0f} million pixels, more than the "
                                 f"{MAX_PIXELS / 1e6:.0f} million a GIF may hold in memory here: lower --dpi, "
                                 "or take fewer snapshots")
    writers = [GifWriter(fps=fps), animation.FFMpegWriter(fps=fps)][:len(targets)]
    parts = [t[:-4] + ".part" + t[-4:] for t in targets]
    try:
        for target in targets:
            if os.path.isdir(target):
                raise IsADirectoryError(f"{target} is a directory")
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


def bounded(kind, low, high, what):
    """argparse type: a finite number of kind (int or float) in [low, high] (what it is, for the error)."""
    def parse(text):
        try:
            value = kind(text)
        except ValueError:
            value = None
        if value is None or not low <= value <= high:      # (False for nan; inf is above any high)
            raise argparse.ArgumentTypeError(f"must be {what}, got '{text}'")
        return value
    return parse


def main(argv=None):
    p = jobs.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--run", required=True, type=jobs.path, help="the run directory (with run.pvd)")
    p.add_argument("--out", type=jobs.path, help="the GIF (default DIR/animation.gif); the MP4 is beside it, same name")
    p.add_argument("--mp4", action="store_true", help="also an MP4, when ffmpeg is on PATH")
    p.add_argument("--fps", type=bounded(int, 1, MAX_FPS, f"an integer from 1 to {MAX_FPS} (frames a second)"),
                   default=12, help=f"frames per second, 1 to {MAX_FPS} (default 12)")
    p.add_argument("--dpi", type=bounded(int, 10, MAX_DPI, f"an integer from 10 to {MAX_DPI} (pixels an inch)"),
                   default=100, help=f"pixels per inch of the figure, 5 in wide, 10 to {MAX_DPI} (default 100)")
    p.add_argument("--vmax", type=bounded(float, math.ulp(0.0), sys.float_info.max,
                                          "a positive finite number (the colour scale's top)"),
                   help="top of the colour scale (default: the max over all frames)")
    a = p.parse_args(argv)
    started = time.monotonic()
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
    print(f"animation: wrote {written}, {len(frames)} frames at {a.fps} fps, in {time.monotonic() - started:.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
