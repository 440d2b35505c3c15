"""The front's tables in the docs, each as front_table.py makes it from front.csv: the
opening table of docs/study.md, and every table of one flag and size's configurations (between
`<!-- front-matrix FLAG SIZE -->` and `<!-- /front-matrix -->`) in the docs."""
import os
import re

from flagstudy import front_table
from flagstudy.checks.common import ROOT, need

# The markers around the table in docs/study.md (HTML comments: Markdown shows nothing of them).
START, END = "<!-- front-table -->", "<!-- /front-table -->"


def table_lines(block):
    """The Markdown table's lines in a block of text."""
    return [line.strip() for line in block.splitlines() if line.strip().startswith("|")]


def doc_table(path):
    """The table's lines between the markers in the file at path, or None without the markers."""
    with open(path) as f:
        text = f.read()
    start = text.find(START)
    end = text.find(END, start + 1) if start >= 0 else -1
    if end < 0:
        return None
    return table_lines(text[start + len(START):end])


MATRIX = re.compile(r"<!-- front-matrix (\w+) (\d+) -->(.*?)<!-- /front-matrix -->", re.S)
MATRIX_DOCS = ["study.md", "stiff_flag.md", "solvers.md"]


def cells(line):
    """A table line's cells, each stripped (so the columns may be aligned with spaces)."""
    return [c.strip() for c in line.strip().strip("|").split("|")]


def first_difference(shown, want):
    """The first row where the doc's table and the regenerated one differ, in words; None if none."""
    for i in range(max(len(shown), len(want))):
        a = cells(shown[i]) if i < len(shown) else None
        b = cells(want[i]) if i < len(want) else None
        if a != b:
            where = "header" if i == 0 else "rule" if i == 1 else f"row {i - 1}"
            doc = " | ".join(a) if a is not None else "(no such row)"
            csv = " | ".join(b) if b is not None else "(no such row)"
            return f"{where}: the doc has '{doc}', front.csv gives '{csv}'"
    return None


def c_front_table_matches_csv(docs):
    path = os.path.join(docs.d, "front.csv")
    need(os.path.isfile(path), f"{path}: missing")
    want = front_table.table(docs.rows("front.csv"))
    doc = os.path.join(ROOT, "docs", "study.md")
    need(os.path.isfile(doc), "docs/study.md: missing")
    shown = doc_table(doc)
    need(shown is not None, f"docs/study.md: no front table between {START} and {END}")
    diff = first_difference(shown, want)
    need(diff is None, f"docs/study.md's front table, {diff} (regenerate it: tools/study/study.py front-table {docs.d})")
    return f"docs/study.md's front table ({len(want) - 2} rows) is front_table.py's from front.csv"


def c_front_matrices_match_csv(docs):
    rows = docs.rows("front.csv")
    seen = []
    for name in MATRIX_DOCS:
        path = os.path.join(ROOT, "docs", name)
        if not os.path.isfile(path):
            continue
        with open(path) as f:
            text = f.read()
        for flag, size, block in MATRIX.findall(text):
            diff = first_difference(table_lines(block), front_table.matrix(rows, flag, size))
            need(diff is None, f"docs/{name}'s table of {flag} at {size}x{size}, {diff} "
                               f"(regenerate it: tools/study/study.py front-table {docs.d} --matrix {flag} {size})")
            seen.append(f"{name} {flag} {size}")
    need(seen, "no front-matrix table in the docs")
    return "the configuration tables (" + ", ".join(seen) + ") are front_table.py's from front.csv"


FRONT_FINDINGS = [
    ("front_table_matches_csv", c_front_table_matches_csv),
    ("front_matrices_match_csv", c_front_matrices_match_csv),
]
