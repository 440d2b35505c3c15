#!/usr/bin/python3
"""Checks that two study runs (e.g. a serial run and merged shards) agree on every deterministic
column; the timing columns (ms_per_step, ms_per_tick, timing) may differ.

    tools/study/compare_runs.py DIR_A DIR_B      (exit 1 naming the first difference)
"""
import csv
import os
import sys

TIMING = {"ms_per_step", "ms_per_tick", "timing"}


def rows(path):
    with open(path, newline="") as f:
        reader = csv.DictReader(f)
        return reader.fieldnames, list(reader)


def main():
    a, b = sys.argv[1], sys.argv[2]
    for name in ["error_vs_runtime.csv", "extreme.csv", "extreme_cases.csv"]:
        pa, pb = os.path.join(a, name), os.path.join(b, name)
        if not os.path.isfile(pa) and not os.path.isfile(pb):
            continue
        ha, ra = rows(pa)
        hb, rb = rows(pb)
        if ha != hb:
            sys.exit(f"{name}: columns differ: {ha} vs {hb}")
        if len(ra) != len(rb):
            sys.exit(f"{name}: {len(ra)} rows vs {len(rb)}")
        for x, y in zip(ra, rb):
            for col in ha:
                if col not in TIMING and x[col] != y[col]:
                    where = x["row"] if "row" in x else x["case"]
                    sys.exit(f"{name} row {where}: {col} = {x[col]} in {a} but {y[col]} in {b}")
        print(f"{name}: {len(ra)} rows, every deterministic column identical")


if __name__ == "__main__":
    main()
