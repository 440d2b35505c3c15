#!/usr/bin/python3
"""The front in one Markdown table: per flag, path and size, the cheapest configuration within
every bound and what the flag's scene ships.

    tools/study/front_table.py out/study       (reads front.csv, prints the table)

A row per (flag, path, size), flags demo then stiff, paths in the study's order, sizes rising. The
cheapest within every bound: stable, no bound missed, not a reference (config reference*), the
least cloth ms per 60 Hz frame ("none" if no configuration is within every bound). Its trajectory
error is in % of the flag's width ("n/a" where the run has none, e.g. above --trajectories-up-to).
The shipped columns are config `shipped`: the flag as its scene ships it, and the bounds it misses.
check_study.py --docs compares docs/study.md's copy of the table with table(docs/study/front.csv).
"""
import csv
import math
import os
import sys

FLAGS = ["demo", "stiff"]
PATHS = ["drive", "speed_50mps", "stop_10g", "spin_5radps", "teleport_1m", "light_particles", "gale_40mps"]
HEADER = ["flag / path", "size", "cheapest within every bound", "ms / frame", "traj. error",
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
    fits = [r for r in here if within(r) and not r["config"].startswith("reference")
            and num(r["ms_per_frame"]) is not None]
    best = min(fits, key=lambda r: num(r["ms_per_frame"])) if fits else None
    cells = [f"{flag} / {path}", size]
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


def read(d):
    """front.csv's rows in d."""
    with open(os.path.join(d, "front.csv"), newline="") as f:
        return list(csv.DictReader(f))


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    print("\n".join(table(read(sys.argv[1]))))


if __name__ == "__main__":
    main()
