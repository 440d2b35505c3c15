"""Checks that two study runs (e.g. a serial run and merged shards) agree on every deterministic
column of error_vs_runtime.csv, front.csv and extreme_cases.csv; the wall-clock columns
(ms_per_step, ms_per_tick, ms_per_frame: any ms_per_*; timing) may differ.

    tools/study/study.py compare-runs DIR_A DIR_B  (exit 1 naming the first difference)
"""
import csv
import os
import sys

FILES = ["error_vs_runtime.csv", "front.csv", "extreme_cases.csv"]


def wall_clock(col):
    """A column taken from the clock: it differs between any two runs."""
    return col == "timing" or col.startswith("ms_per_")


def rows(path):
    """A CSV's columns and rows."""
    with open(path, newline="") as f:
        reader = csv.DictReader(f)
        return reader.fieldnames, list(reader)


def compare(name, a, b):
    """One CSV in both runs: the same columns, rows and deterministic values; exits at the first
    difference, else prints a line. Skipped if neither run has it."""
    pa, pb = os.path.join(a, name), os.path.join(b, name)
    if not os.path.isfile(pa) and not os.path.isfile(pb):
        return
    for p in (pa, pb):
        if not os.path.isfile(p):
            sys.exit(f"{name}: only one run has it ({p} is missing)")
    ha, ra = rows(pa)
    hb, rb = rows(pb)
    if ha != hb:
        sys.exit(f"{name}: columns differ: {ha} vs {hb}")
    if len(ra) != len(rb):
        sys.exit(f"{name}: {len(ra)} rows vs {len(rb)}")
    for x, y in zip(ra, rb):
        for col in ha:
            if not wall_clock(col) and x[col] != y[col]:
                where = x["row"] if "row" in x else x["case"]
                sys.exit(f"{name} row {where}: {col} = {x[col]} in {a} but {y[col]} in {b}")
    print(f"{name}: {len(ra)} rows, every deterministic column identical")


def main(argv):
    """Runs on argv, the command line's arguments without the program's name."""
    if len(argv) != 2:
        sys.exit(__doc__)
    for name in FILES:
        compare(name, argv[0], argv[1])
