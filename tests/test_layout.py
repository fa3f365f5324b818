"""The layout keeps its promises (docs/internals.md): edp/lib is folders by concern, with no file at its top;
each file says in its first line what it is and stays short enough to read; and every file of edp/lib that the
code, the tests or the docs name exists (a moved file leaves no stale pointer behind)."""
import os
import re
import subprocess

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
LIB = os.path.join(ROOT, "edp", "lib")
MOST_LINES = 260          # "about 250 lines" (issue 33)
FOLDERS = ["run", "dimension", "body", "mass", "material", "scheme", "contact", "solve", "watch", "io"]


def lib_files():
    return sorted(os.path.join(d, f) for d in os.listdir(LIB) if os.path.isdir(os.path.join(LIB, d))
                  for f in os.listdir(os.path.join(LIB, d)) if not f.startswith("."))


def test_edp_lib_is_folders_by_concern():
    top = sorted(os.listdir(LIB))
    assert [f for f in top if not os.path.isdir(os.path.join(LIB, f))] == [], "a file at the top of edp/lib"
    assert sorted(f for f in top if not f.startswith(".")) == sorted(FOLDERS), "docs/internals.md lists the folders"


def test_every_file_names_itself_first_and_stays_short():
    for rel in lib_files():
        lines = open(os.path.join(LIB, rel)).read().split("\n")
        head = lines[1] if lines[0].startswith("#!") else lines[0]
        if rel.endswith((".opt", ".txt")):
            continue
        assert rel in head and " -- " in head, f"edp/lib/{rel}: its first line is '{head}', not '{rel} -- what it is'"
        assert len(lines) <= MOST_LINES, f"edp/lib/{rel}: {len(lines)} lines, more than {MOST_LINES}"


def test_every_named_lib_file_exists():
    files = subprocess.run(["git", "ls-files", "edp", "docs", "tests", "postprocess", "README.md", "Makefile"],
                           cwd=ROOT, capture_output=True, text=True).stdout.split()
    named = re.compile(r"(?<![\w/.-])(?:edp/)?(?:lib/)?((?:%s)/[A-Za-z0-9_-]+\.(?:idp|awk|sh|txt|opt|edp))" % "|".join(FOLDERS))
    missing = []
    for f in files:
        if not f.endswith((".idp", ".edp", ".awk", ".sh", ".md", ".py", "Makefile", ".txt")):
            continue
        for n, line in enumerate(open(os.path.join(ROOT, f), errors="replace"), 1):
            missing += [f"{f}:{n}: {m}" for m in named.findall(line) if not os.path.exists(os.path.join(LIB, m)) and "NAME" not in m]   # (NAME: a placeholder)
    assert not missing, "names of files that do not exist:\n" + "\n".join(missing)
