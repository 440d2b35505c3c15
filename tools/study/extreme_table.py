#!/usr/bin/python3
"""The extreme cases as Markdown tables, one per flag size: a row per configuration (Newton's
included), a column per case; a cell gives stable or not and the p99 stretch, and the peak
stretch outside the teleport's jump; the last column is the median ms per 240 Hz tick over the
cases the configuration ran. A Newton row whose note says "old spin" ran the spin about the
pole's own axis, which moved no pin: its cell says so instead of a result.

    tools/study/extreme_table.py out/study   (reads extreme.csv and, if present, nvidia_newton_extreme.csv)
"""
import csv
import math
import os
import statistics
import sys

CASES = ["speed_50mps", "stop_10g", "spin_5radps", "teleport_1m", "light_particles", "gale_40mps"]
HEADERS = ["50 m/s", "10 g stop", "spin", "teleport", "light", "gale"]


def num(v):
    try:
        x = float(v)
    except (TypeError, ValueError):
        return math.nan
    return x


def pct(x):
    if not math.isfinite(x):
        return "non-finite"
    return ">1000%" if x > 10 else f"{100 * x:.0f}%"


def cell(r):
    if r is None:
        return ""
    if r.get("note", "").startswith("old spin"):  # Newton's rows of the spin about the pole's own axis
        return "old spin"
    p99 = num(r["p99_stretch"])
    if math.isnan(p99):  # a Newton row that could not run: its note says why
        return "could not run"
    verdict = "yes" if r["stable"] == "1" else "no"
    return f"{verdict}, {pct(p99)} / {pct(num(r['peak_stretch']))}"


def main():
    d = sys.argv[1] if len(sys.argv) > 1 else "out/study"
    with open(os.path.join(d, "extreme.csv"), newline="") as f:
        rows = list(csv.DictReader(f))
    nvidia_newton = os.path.join(d, "nvidia_newton_extreme.csv")
    if os.path.isfile(nvidia_newton):
        with open(nvidia_newton, newline="") as f:
            rows += list(csv.DictReader(f))
    for size in sorted({int(r["size"]) for r in rows}):
        here = [r for r in rows if int(r["size"]) == size]
        configs = list(dict.fromkeys(r["config"] for r in here))
        print(f"**{size}x{size}** (a cell: stable, p99 stretch / peak stretch outside the teleport's jump; "
              "the last column: median ms per 240 Hz tick over the cases; nvidia_newton_*: Warp CPU kernels)\n")
        print("| configuration | " + " | ".join(HEADERS) + " | ms/tick |")
        print("|---" * (len(HEADERS) + 2) + "|")
        for c in configs:
            by_case = {r["case"]: r for r in here if r["config"] == c}
            ms = [num(r["ms_per_tick"]) for r in by_case.values()
                  if math.isfinite(num(r["ms_per_tick"])) and not r.get("note", "").startswith("old spin")]
            cost = f"{statistics.median(ms):.3g}" if ms else "-"
            print(f"| {c} | " + " | ".join(cell(by_case.get(x)) for x in CASES) + f" | {cost} |")
        print()


if __name__ == "__main__":
    main()
