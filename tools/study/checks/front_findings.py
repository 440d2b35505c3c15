"""The findings of docs/study.md's opening: the front table (tools/study/front_table.py), each row
as front.csv gives it."""
import os

import front_table
from checks.common import ROOT, need

# The markers around the table in docs/study.md (HTML comments: Markdown shows nothing of them).
START, END = "<!-- front-table -->", "<!-- /front-table -->"


def doc_table(path):
    """The table's lines between the markers in the file at path, or None without the markers."""
    with open(path) as f:
        text = f.read()
    start = text.find(START)
    end = text.find(END, start + 1) if start >= 0 else -1
    if end < 0:
        return None
    block = text[start + len(START):end]
    return [line.strip() for line in block.splitlines() if line.strip().startswith("|")]


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
    need(diff is None, f"docs/study.md's front table, {diff} (regenerate it: tools/study/front_table.py {docs.d})")
    return f"docs/study.md's front table ({len(want) - 2} rows) is front_table.py's from front.csv"


FRONT_FINDINGS = [
    ("front_table_matches_csv", c_front_table_matches_csv),
]
