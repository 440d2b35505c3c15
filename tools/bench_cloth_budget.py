#!/usr/bin/python3
"""The cloth's share of a demo frame: per frame, air + cloth_forces + cloth_solve + collision +
contact (profile.csv of a flagsim run), mean, median and 99th percentile, against a real-time
budget, and the mean's and the median's ratios to the demo's run at the same size in the same call
(LABEL up to "_stiff", "_true" or "_contact").

    tools/bench_cloth_budget.py LABEL:BUDGET_MS:PROFILE_CSV ...
"""
import csv
import re
import statistics
import sys

PHASES = ["air", "cloth_forces", "cloth_solve", "collision", "contact"]


def frame_sums(path):
    """Each frame's cloth milliseconds in a flagsim profile.csv, in frame order."""
    with open(path, newline="") as f:
        return [sum(float(r.get(p) or 0) for p in PHASES) for r in csv.DictReader(f)]


def main():
    print("| run | frames | cloth mean (ms/frame) | cloth median | cloth p99 | budget | within | x demo (mean) | x demo (median) |")
    print("|---|---|---|---|---|---|---|---|---|")
    means, medians = {}, {}
    for arg in sys.argv[1:]:
        label, budget, path = arg.split(":", 2)
        sums = sorted(frame_sums(path))
        if not sums:
            sys.exit(f"{path}: no frames")
        mean = sum(sums) / len(sums)
        p99 = sums[min(len(sums) - 1, int(0.99 * len(sums)))]
        median = statistics.median(sums)
        means[label], medians[label] = mean, median
        base = re.sub(r"_(stiff|true|contact).*", "", label)
        ratio = f"{mean / means[base]:.1f}" if base in means else ""
        ratio_median = f"{median / medians[base]:.1f}" if base in medians else ""
        print(f"| {label} | {len(sums)} | {mean:.2f} | {median:.2f} | {p99:.2f} | {float(budget):g} | "
              f"{'yes' if mean <= float(budget) else 'no'} | {ratio} | {ratio_median} |")


if __name__ == "__main__":
    main()
