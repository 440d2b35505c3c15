"""The front in Markdown tables: per flag, path and size, the cheapest configuration within every
bound and what the flag's scene ships; and, for one flag and size, every configuration on every
path (its cost, its error and the bounds it misses).

    tools/study/study.py front-table out/study                    (reads front.csv, prints the table)
    tools/study/study.py front-table out/study --matrix stiff 33  (every configuration of one flag
                                                                  and size)
    tools/study/study.py front-table docs/study --update docs/study.md docs/stiff_flag.md
        (rewrites the tables between the markers <!-- front-table --> and <!-- front-matrix FLAG
         SIZE --> and their closing ones in each file, from DIR/front.csv)

A row per (flag, path, size), flags demo then stiff, paths in the study's order, sizes rising. The
cheapest within every bound: stable, no bound missed, not a reference (config reference*), the
least cloth ms per 60 Hz frame ("none" if no configuration is within every bound). Its trajectory
error is in % of the flag's width ("n/a" where the run has none, e.g. above --trajectories-up-to).
The bounds judge stretch and flutter, not the path the cloth takes, so a second choice also asks for
a trajectory error of at most 2% of the width (TRAJ).
The shipped columns are config `shipped`: the flag as its scene ships it, and the bounds it misses.
A row that DIR/stale.csv marks (flagstudy/stale.py) is no evidence: it is never the cheapest, and a
matrix shows it as "stale".
study.py check-docs compares docs/study.md's copy of the table with table(docs/study/front.csv).
"""
import csv
import math
import os
import re
import sys

from flagstudy import stale

FLAGS = ["demo", "stiff"]
PATHS = ["drive", "speed_50mps", "stop_10g", "spin_5radps", "teleport_1m", "light_particles", "gale_40mps"]
TRAJ = 0.02  # "close to the true motion": trajectory error at most 2% of the flag's width
HEADER = ["flag / path", "size", "cheapest within every bound", "ms / frame", "traj. error",
          "cheapest also within 2% traj.", "ms / frame", "traj. error",
          "shipped ms / frame", "shipped traj. error", "shipped misses"]


def num(v):
    """A finite float, or None."""
    try:
        x = float(v)
    except (TypeError, ValueError):
        return None
    return x if math.isfinite(x) else None


def ms(v):
    """Milliseconds with 3 significant digits (whole ones from 100 up)."""
    x = num(v)
    if x is None:
        return "n/a"
    return f"{x:.0f}" if x >= 100 else f"{x:.3g}"


def pct(v):
    """A share of the flag's width in %, 2-3 significant digits; n/a when missing."""
    x = num(v)
    if x is None:
        return "n/a"
    x *= 100
    return f"{x:.0f}%" if x >= 10 else f"{x:.1f}%" if x >= 1 else f"{x:.2f}%"


def within(r):
    """Stable, judged against a reference, and no bound missed."""
    return r["stable"] == "1" and r["misses"] == "" and num(r["ref_p99_stretch"]) is not None


def verdict(r):
    """The bounds a row misses ("unstable" misses them all), "within bounds", or "no reference" when
    the run had none to judge it by (--no-references)."""
    if r["stable"] != "1":
        return "unstable"
    if num(r["ref_p99_stretch"]) is None:
        return "no reference"
    return r["misses"].replace(";", ", ") if r["misses"] else "within bounds"


def groups(rows):
    """The (flag, path, size) groups in the table's order (unknown flags and paths last)."""
    def rank(value, order):
        return order.index(value) if value in order else len(order)
    keys = {(r["flag"], r["path"], r["size"]) for r in rows}
    return sorted(keys, key=lambda k: (rank(k[0], FLAGS), k[0], rank(k[1], PATHS), k[1], int(k[2])))


def table_row(here, flag, path, size):
    """One group's cells: its cheapest configuration within every bound and its shipped row."""
    fits = [r for r in here if not is_stale(r) and within(r) and not r["config"].startswith("reference")
            and num(r["ms_per_frame"]) is not None]
    close = [r for r in fits if num(r["traj_error"]) is not None and num(r["traj_error"]) <= TRAJ]
    cells = [f"{flag} / {path}", size]
    for group in (fits, close):
        best = min(group, key=lambda r: num(r["ms_per_frame"])) if group else None
        cells += [f"`{best['config']}`", ms(best["ms_per_frame"]), pct(best["traj_error"])] if best else ["none", "-", "-"]
    shipped = [r for r in here if r["config"] == "shipped"]
    if shipped:
        s = shipped[0]
        cells += [ms(s["ms_per_frame"]), pct(s["traj_error"]) if s["stable"] == "1" else "-", verdict(s)]
    else:
        cells += ["-", "-", "not run"]
    return cells


def table(rows):
    """The table's lines (header, rule, a line per group) for front.csv's rows."""
    lines = ["| " + " | ".join(HEADER) + " |", "|" + "---|" * len(HEADER)]
    for flag, path, size in groups(rows):
        here = [r for r in rows if (r["flag"], r["path"], r["size"]) == (flag, path, size)]
        lines.append("| " + " | ".join(table_row(here, flag, path, size)) + " |")
    return lines


def matrix_cell(r):
    """ms per frame and trajectory error, then the bounds missed; bold when within every bound."""
    if r["stable"] != "1":
        return f"unstable ({ms(r['ms_per_frame'])} ms)"
    text = f"{ms(r['ms_per_frame'])} ms, {pct(r['traj_error'])}"
    if r["config"].startswith("reference"):
        return text
    v = verdict(r)
    return f"**{text}**" if v == "within bounds" else f"{text}, {v}"


def matrix(rows, flag, size):
    """The lines of one flag and size's table: a row per configuration (in the CSV's order), a column
    per path (in the study's order)."""
    here = [r for r in rows if r["flag"] == flag and r["size"] == str(size)]
    paths = [p for p in PATHS if any(r["path"] == p for r in here)]
    configs = list(dict.fromkeys(r["config"] for r in here))
    lines = ["| config | " + " | ".join(paths) + " |", "|---|" + "---|" * len(paths)]
    for c in configs:
        cells = []
        for p in paths:
            found = [r for r in here if r["config"] == c and r["path"] == p]
            cells.append(("stale" if is_stale(found[0]) else matrix_cell(found[0])) if found else "-")
        lines.append(f"| `{c}` | " + " | ".join(cells) + " |")
    return lines


class Marked(dict):
    """A row that stale.csv marks (is_stale: the checks' StaleRow has its `mark` too)."""

    def __init__(self, row, mark):
        super().__init__(row)
        self.mark = mark


def is_stale(r):
    return getattr(r, "mark", None) is not None


def read(d):
    """front.csv's rows in d, those d's stale.csv marks as Marked."""
    marks = stale.read_marks(d)
    with open(os.path.join(d, "front.csv"), newline="") as f:
        rows = list(csv.DictReader(f))
    return [Marked(r, m) if (m := stale.mark_of(marks, "front.csv", r)) else r for r in rows]


def update(path, rows):
    """Rewrites the front's tables between their markers in the file at path (through a temporary
    file and a rename); returns how many it wrote."""
    with open(path) as f:
        text = f.read()
    count = 0

    def fill(head, lines, tail):
        nonlocal count
        count += 1
        return head + "\n" + "\n".join(lines) + "\n" + tail

    text = re.sub(r"(<!-- front-table -->).*?(<!-- /front-table -->)",
                  lambda m: fill(m.group(1), table(rows), m.group(2)), text, flags=re.S)
    text = re.sub(r"(<!-- front-matrix (\w+) (\d+) -->).*?(<!-- /front-matrix -->)",
                  lambda m: fill(m.group(1), matrix(rows, m.group(2), m.group(3)), m.group(4)), text, flags=re.S)
    with open(path + ".tmp", "w") as f:
        f.write(text)
    os.replace(path + ".tmp", path)
    return count


def main(argv):
    """Runs on argv, the command line's arguments without the program's name."""
    if len(argv) >= 3 and argv[1] == "--update":
        rows = read(argv[0])
        for path in argv[2:]:
            print(f"{path}: {update(path, rows)} tables")
        return None
    if len(argv) == 4 and argv[1] == "--matrix":
        return print("\n".join(matrix(read(argv[0]), argv[2], argv[3])))
    if len(argv) != 1:
        sys.exit(__doc__)
    print("\n".join(table(read(argv[0]))))
