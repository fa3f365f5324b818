"""A file of "key value" lines (a run's summary.txt or parameters.txt) as a dict of strings. Pure Python: the audit
(postprocess/audit.py, after every run) reads it without numpy."""


def read_keyed(path):
    out = {}
    with open(path) as f:
        for line in f:
            parts = line.split(None, 1)
            if len(parts) == 2:
                out[parts[0]] = parts[1].strip()
    return out
