"""The one table of the parameters (edp/lib/run/parameter_table.idp): docs/parameters.md's table is what
tests/parameter_table.py generates from it, every key of it is documented, read by the driver (its
"known options") and recorded in parameters.txt, in the table's order (3D-only keys only in 3D)."""
import os
import re
import subprocess

import pytest

from conftest import ROOT
import parameter_table

RUN = os.path.join(ROOT, "edp", "run.sh")
ROWS = parameter_table.rows()
KEYS = [row["key"] for row in ROWS]


def test_docs_table_is_generated_from_the_table():
    text = open(parameter_table.DOC, encoding="utf-8").read()
    assert text == parameter_table.generated(text), "run /usr/bin/python3 tests/parameter_table.py"


def test_every_key_is_documented_once_with_a_doc_line():
    text = open(parameter_table.DOC, encoding="utf-8").read()
    for row in ROWS:
        assert text.count("| `-%s` |" % row["key"]) == 1, row["key"]
        assert row["doc"].strip(), row["key"]


def test_rows_are_consistent():
    assert len(set(KEYS)) == len(KEYS)
    assert len({row["variable"] for row in ROWS}) == len(ROWS)
    for row in ROWS:
        assert re.fullmatch(r"[a-z][a-z0-9_]*|T", row["key"]), row["key"]
        assert row["restart"] in ("mayChange", "fixed") and row["dimensions"] in ("anyDim", "only3D"), row["key"]
        if row["kind"] == "Int":
            assert int(row["lo"]) <= int(row["default"]) <= int(row["hi"]), row["key"]
        if row["dimensions"] == "only3D":
            assert row["kind"] == "Real", row["key"] + ": run/warnings.idp names the 3D settings as reals"


def run(tmp_path, name, *args):
    out = tmp_path / name
    p = subprocess.run([RUN, "test1", str(out), "-progress", "0", "-snapshots", "none", *args],
                       capture_output=True, text=True, timeout=300, env=dict(os.environ, FORCE="1"))
    return p, out


def test_every_key_is_read(tmp_path):
    p, _ = run(tmp_path, "unknown", "-no_such_key", "1")
    m = re.search(r"^error: unknown option -no_such_key; known options: (.*)$", p.stderr, re.M)
    assert p.returncode == 3 and m, p.stderr
    assert m.group(1).split() == KEYS


def test_every_key_is_recorded_in_the_tables_order(tmp_path):
    p, out = run(tmp_path, "short", "-T", "0.1")
    assert p.returncode == 0, p.stderr
    recorded = [line.split(" ", 1)[0][1:] for line in open(out / "parameters.txt").read().splitlines()]
    assert recorded == [row["key"] for row in ROWS if row["dimensions"] != "only3D"]
