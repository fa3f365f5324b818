"""Read a run's history.csv and derive what the paper reports from it."""
import csv
import os
import re

import numpy as np

from keyed import read_keyed  # noqa: F401  (summary.txt, parameters.txt: history.read_keyed)


def read_csv(path):
    """A headed CSV as a dict of float arrays (lines starting with # are skipped; an empty cell, a value not
    computed at that step (history.csv's max_strain and min_J under -diagnostics_every), is NaN)."""
    with open(path) as f:
        rows = [line for line in f if not line.startswith("#")]
    reader = csv.reader(rows)
    header = next(reader)
    data = np.array([[float(x) if x != "" else np.nan for x in row] for row in reader if row])
    return {name: data[:, k] for k, name in enumerate(header)}


def read_run(run_dir):
    return read_csv(os.path.join(run_dir, "history.csv"))




def read_summary(run_dir):
    return read_keyed(os.path.join(run_dir, "summary.txt"))


def read_parameters(run_dir):
    """parameters.txt: "-key" -> value."""
    return read_keyed(os.path.join(run_dir, "parameters.txt"))


def energy_gain(h):
    """The energy guard's measure (edp/lib/watch/guards.idp) at every step: the modified energy's gain over
    its start, (m - m0) / S, S = max(|m0|, E0, max_k |(f, u^k - u^0)|) with (f, u) = E - m; on a friction run,
    m less the work the foundation's motion along itself has done (foundation_work: a belt's), as the guard has it."""
    e, m = h["energy"], h["modified_energy"]
    work = e - m
    if "foundation_work" in h:
        m = m - h["foundation_work"]
    scale = np.maximum(max(abs(m[0]), e[0]), np.maximum.accumulate(np.abs(work - work[0])))
    return (m - m[0]) / np.where(scale > 0, scale, 1e-300)


GUARD_RE = re.compile(r"^error: the modified energy grew from \S+ to \S+ by step (\d+) \(t = ([-+0-9.eE]+)\), ([0-9.]+)% of ")


def error_lines(text):
    """The lines of a run's output (stderr, or stdout and stderr together) that start with "error"."""
    return [line for line in text.splitlines() if line.startswith("error")]


def guard_stop(text):
    """(step, t, gain in %) of a run the energy guard stopped (edp/lib/watch/guards.idp): its output's one error
    line is "error: the modified energy grew from A to B by step N (t = X), G% of ..."; None otherwise."""
    lines = error_lines(text)
    m = GUARD_RE.match(lines[0]) if len(lines) == 1 else None
    return (int(m.group(1)), float(m.group(2)), float(m.group(3))) if m else None


THROUGH_RE = re.compile(r"^error: the body passed through the foundation at step (\d+) \(t = ([-+0-9.eE]+)\): .*, is (\S+) "
                        r"below it, ([0-9.]+)% of the body's size ")


def through_stop(text):
    """(step, t, depth, depth in % of the body's size) of a run stopped because its boundary outside Gamma_C went
    through the foundation (edp/lib/watch/guards.idp): its output's one error line is "error: the body passed through the
    foundation at step N (t = X): its boundary vertex ..., is D below it, P% of the body's size ..."; None otherwise."""
    lines = error_lines(text)
    m = THROUGH_RE.match(lines[0]) if len(lines) == 1 else None
    return (int(m.group(1)), float(m.group(2)), float(m.group(3)), float(m.group(4))) if m else None


def contact_intervals(t, in_contact, min_gap=0.5):
    """Time intervals of contact; gaps shorter than min_gap (chatter) are merged."""
    intervals = []
    start = None
    for k in range(len(t)):
        if in_contact[k] and start is None:
            start = t[k]
        if not in_contact[k] and start is not None:
            intervals.append([start, t[k - 1]])
            start = None
    if start is not None:
        intervals.append([start, t[-1]])
    merged = []
    for iv in intervals:
        if merged and iv[0] - merged[-1][1] < min_gap:
            merged[-1][1] = iv[1]
        else:
            merged.append(iv)
    return merged


def rebound_peaks(t, u2, intervals):
    """Highest u2 between consecutive contact intervals: (time, height) pairs."""
    peaks = []
    for (_, end), (start, _) in zip(intervals[:-1], intervals[1:]):
        s = (t > end) & (t < start)
        if s.any():
            k = np.argmax(np.where(s, u2, -np.inf))
            peaks.append((t[k], u2[k]))
    return peaks


def read_freefem_mesh(path):
    """FreeFEM .msh (savemesh): vertices (x, y) and triangles (0-based)."""
    with open(path) as f:
        nv, nt, _ = (int(x) for x in f.readline().split())
        xy = np.array([[float(x) for x in f.readline().split()[:2]] for _ in range(nv)])
        tri = np.array([[int(x) - 1 for x in f.readline().split()[:3]] for _ in range(nt)])
    return xy, tri
