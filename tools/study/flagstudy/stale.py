"""The committed rows that today's code no longer computes, in one place: docs/study/stale.csv.

A change that moves a solver's bits either re-runs the committed rows it affects or marks them
here, one line per group of rows: the CSV, the rows' key (column=value pairs separated by ';', a
value may be a shell pattern: config=newton_*), and why. `study.py evidence` expects a marked
row to differ from the run and fails on one that no longer does; `study.py check-docs` fails a
finding that reads any column of a marked row beyond its key (the row is not evidence)."""
import csv
import fnmatch
import os

NAME = "stale.csv"
# The columns that name a row of each CSV the study writes (a finding may read these of a stale
# row: they only find it).
KEYS = {
    "front.csv": ("flag", "path", "size", "config"),
    "error_vs_runtime.csv": ("scene", "size", "stiffness", "h", "duration", "family", "solver"),
}
FRONT_FORM = ("teleports_demo.csv", "teleports_stiff.csv", "small_steps_margin.csv", "front_contact.csv")  # front.csv's form
for _name in FRONT_FORM:
    KEYS[_name] = KEYS["front.csv"]


class Mark:
    """One line of stale.csv: the file, the key's patterns, why."""

    def __init__(self, file, key, why):
        self.file, self.why = file, why
        self.match = dict(part.split("=", 1) for part in key.split(";") if part)

    def covers(self, file, row):
        return file == self.file and all(fnmatch.fnmatchcase(row.get(k, ""), v) for k, v in self.match.items())


def read_marks(d):
    """The marks of folder d (none when it has no stale.csv); a malformed line raises ValueError
    naming the file, its line and what is wrong."""
    path = os.path.join(d, NAME)
    if not os.path.isfile(path):
        return []
    marks = []
    with open(path, newline="") as f:
        for n, r in enumerate(csv.DictReader(f), 2):
            if set(r) != {"file", "key", "why"} or not r["file"] or not r["key"] or not r["why"]:
                raise ValueError(f"{path}:{n}: a line is file,key,why, each filled: {r}")
            if any("=" not in part for part in r["key"].split(";") if part):
                raise ValueError(f"{path}:{n}: key {r['key']!r} is not column=value;...")
            marks.append(Mark(r["file"], r["key"], r["why"]))
    return marks


def mark_of(marks, file, row):
    """The first mark that covers the row, or None."""
    return next((m for m in marks if m.covers(file, row)), None)


def key_of(file, row):
    """The row's key as text: flag=demo path=drive size=33 config=multigrid."""
    return " ".join(f"{k}={row.get(k, '')}" for k in KEYS.get(file, ()))
