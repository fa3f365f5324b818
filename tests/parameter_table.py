#!/usr/bin/env python3
"""The table of docs/parameters.md, generated from edp/lib/run/parameter_table.idp (the one table of the
parameters: key, type, default, range, when it has an effect, whether a restart may change it, doc).

    /usr/bin/python3 tests/parameter_table.py           rewrite the table between the markers of docs/parameters.md
    /usr/bin/python3 tests/parameter_table.py --check   exit 1 if docs/parameters.md is not what this gives

tests/test_parameters_table.py runs the check in make check."""
import os
import re
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
TABLE = os.path.join(ROOT, "edp", "lib", "run", "parameter_table.idp")
DOC = os.path.join(ROOT, "docs", "parameters.md")
BEGIN = ("<!-- the parameter table: generated from edp/lib/run/parameter_table.idp by tests/parameter_table.py; "
         "edit the table there -->")
END = "<!-- end of the parameter table -->"

COLUMNS = {
    "Real": ["variable", "key", "default", "ok", "range", "applies", "restart", "dimensions", "doc"],
    "Int": ["variable", "key", "default", "lo", "hi", "applies", "restart", "dimensions", "doc"],
    "Str": ["variable", "key", "default", "ok", "range", "recorded", "applies", "restart", "dimensions", "doc"],
}
STRING = r'"(?:[^"\\]|\\.)*"'


def split_arguments(text):
    """The top-level comma-separated arguments of text (parentheses and string literals kept whole)."""
    args, depth, start, i = [], 0, 0, 0
    while i < len(text):
        c = text[i]
        if c == '"':
            i = re.match(STRING, text[i:]).end() + i
            continue
        if c == "(":
            depth += 1
        elif c == ")":
            depth -= 1
        elif c == "," and depth == 0:
            args.append(text[start:i].strip())
            start = i + 1
        i += 1
    args.append(text[start:i].strip())
    return args


def after_call(text, i):
    """The index just past the parenthesis that closes the one opened before text[i]."""
    depth = 1
    while depth:
        if text[i] == '"':
            i += re.match(STRING, text[i:]).end()
            continue
        depth += {"(": 1, ")": -1}.get(text[i], 0)
        i += 1
    return i


def literal(text):
    """The value of a string literal, or of literals joined by +."""
    parts = re.findall(STRING, text)
    if not parts or re.sub(r"\s|\+", "", re.sub(STRING, "", text)):
        raise ValueError("not a string literal: " + text)
    return "".join(re.sub(r'\\(.)', r"\1", p[1:-1]) for p in parts)


def conditions(applies):
    """The conditions of `when(condition, reason) ...`, or [] for `always`."""
    if applies == "always":
        return []
    found, rest = [], applies
    while rest:
        m = re.match(r"\s*when\(", rest)
        if not m:
            raise ValueError("applies must be `always` or when(condition, reason)...: " + applies)
        i = after_call(rest, m.end())
        found.append(split_arguments(rest[m.end():i - 1])[0])
        rest = rest[i:].strip()
    return found


def rows(path=TABLE):
    """Every row of the table, in its order, as a dict of its columns (and "kind": Real, Int or Str)."""
    text = open(path, encoding="utf-8").read()
    m = re.search(r"^macro parameterTable\(Real, Int, Str\)\n(.*?)^// EOM", text, re.M | re.S)
    body, out, i = m.group(1), [], 0
    while i < len(body):
        r = re.compile(r"\s*(Real|Int|Str)\(").match(body, i)
        if not r:
            if body[i:].strip():
                raise ValueError("unexpected text in the table: " + body[i:i + 60])
            break
        j = after_call(body, r.end())
        args = split_arguments(body[r.end():j - 1])
        kind = r.group(1)
        if len(args) != len(COLUMNS[kind]):
            raise ValueError("%s row %s: %d columns, not %d" % (kind, args[:2], len(args), len(COLUMNS[kind])))
        row = dict(zip(COLUMNS[kind], args), kind=kind)
        row["key"], row["doc"] = literal(row["key"]), literal(row["doc"])
        if kind != "Int":
            row["range"] = literal(row["range"])
        row["conditions"] = conditions(row["applies"])
        out.append(row)
        i = j
    return out


def cell(text):
    return text.replace("|", "\\|")


def range_text(row):
    if row["kind"] == "Int":
        lo, hi = int(row["lo"]), int(row["hi"])
        return "%d, %d" % (lo, hi) if hi - lo == 1 else "%d to %d" % (lo, hi)
    return row["range"]


def default_text(row):
    d = row["default"]
    if row["kind"] == "Str":
        d = literal(d)
        return "`%s`" % d if d else '`""`'
    return d


def table(path=TABLE):
    lines = ["| key | type | default | range | has an effect when | restart | meaning |",
             "| --- | --- | --- | --- | --- | --- | --- |"]
    kinds = {"Real": "real", "Int": "integer", "Str": "string"}
    for row in rows(path):
        effect = ["`%s`" % c for c in row["conditions"]]
        if row["dimensions"] == "only3D":
            effect.append("a 3D body")
        lines.append("| `-%s` | %s | %s | %s | %s | %s | %s |" % (
            row["key"], kinds[row["kind"]], default_text(row), cell(range_text(row)), cell(" and ".join(effect)),
            "may change" if row["restart"] == "mayChange" else "", cell(row["doc"])))
    return "\n".join(lines) + "\n"


def generated(doc_text, path=TABLE):
    """doc_text with the table between the markers replaced by the one the table file gives."""
    begin, end = doc_text.index(BEGIN) + len(BEGIN), doc_text.index(END)
    return doc_text[:begin] + "\n" + table(path) + doc_text[end:]


def main():
    text = open(DOC, encoding="utf-8").read()
    new = generated(text)
    if "--check" in sys.argv[1:]:
        if new != text:
            print("docs/parameters.md is not what tests/parameter_table.py gives from edp/lib/run/parameter_table.idp: "
                  "run /usr/bin/python3 tests/parameter_table.py")
            return 1
        return 0
    if new != text:
        open(DOC, "w", encoding="utf-8").write(new)
    return 0


if __name__ == "__main__":
    sys.exit(main())
