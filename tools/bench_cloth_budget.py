#!/usr/bin/python3
"""The cloth's share of a demo frame: per frame, air + cloth_forces + cloth_solve + collision
(profile.csv of a flagsim run), mean and 99th percentile, against a real-time budget, and the
mean's ratio to the demo's run at the same size in the same call (LABEL up to "_stiff" or "_true").

    tools/bench_cloth_budget.py LABEL:BUDGET_MS:PROFILE_CSV ...
"""
import csv
import re
import sys

PHASES = ["air", "cloth_forces", "cloth_solve", "collision"]


def main():
    print("| run | frames | cloth mean (ms/frame) | cloth p99 | budget | within | x demo |")
    print("|---|---|---|---|---|---|---|")
    means = {}
    for arg in sys.argv[1:]:
        label, budget, path = arg.split(":", 2)
        with open(path, newline="") as f:
            rows = list(csv.DictReader(f))
        sums = sorted(sum(float(r.get(p) or 0) for p in PHASES) for r in rows)
        if not sums:
            sys.exit(f"{path}: no frames")
        mean = sum(sums) / len(sums)
        p99 = sums[min(len(sums) - 1, int(0.99 * len(sums)))]
        means[label] = mean
        demo = means.get(re.sub(r"_(stiff|true).*", "", label))
        ratio = f"{mean / demo:.1f}" if demo else ""
        print(f"| {label} | {len(sums)} | {mean:.2f} | {p99:.2f} | {float(budget):g} | "
              f"{'yes' if mean <= float(budget) else 'no'} | {ratio} |")


if __name__ == "__main__":
    main()
