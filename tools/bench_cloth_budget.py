#!/usr/bin/python3
"""The cloth's share of a demo frame: per frame, air + cloth_forces + cloth_solve + collision +
contact (profile.csv of a flagsim run), mean, median and 99th percentile, against a real-time
budget, and the mean's and the median's ratios to the demo's run at the same size in the same call
(LABEL up to "_stiff", "_true" or "_contact"), to the same run without contact (LABEL_no_contact,
or for LABEL_contact, LABEL) and, for a LABEL with "_2threads", to the same run on one thread.
Then, for each run with contact (its summary.json beside the profile has `contact`), where
contact's time goes: its broad phase and its sub-intervals, per frame, per application and against
the cloth's other phases, and the whole cloth against those phases alone: the run's own ratio to
the same cloth without contact, steadier on a shared machine than two runs' ratio.

    tools/bench_cloth_budget.py LABEL:BUDGET_MS:PROFILE_CSV ...
"""
import csv
import json
import os
import re
import statistics
import sys

PHASES = ["air", "cloth_forces", "cloth_solve", "collision", "contact"]


def frame_sums(path):
    """Each frame's cloth milliseconds in a flagsim profile.csv, in frame order."""
    with open(path, newline="") as f:
        return [sum(float(r.get(p) or 0) for p in PHASES) for r in csv.DictReader(f)]


def without_contact(label, labels):
    """The row of the same run without contact: LABEL_no_contact, or for LABEL_contact, LABEL."""
    if label + "_no_contact" in labels:
        return label + "_no_contact"
    if label.endswith("_contact") and not label.endswith("_no_contact"):
        base = label[: -len("_contact")]
        return base if base in labels else None
    return None


def one_thread(label, labels):
    """The same run on one thread: LABEL without "_2threads"."""
    base = label.replace("_2threads", "")
    return base if base != label and base in labels else None


def main():
    rows = []
    for arg in sys.argv[1:]:
        label, budget, path = arg.split(":", 2)
        sums = sorted(frame_sums(path))
        if not sums:
            sys.exit(f"{path}: no frames")
        rows.append((label, float(budget), sums))
    means = {label: sum(sums) / len(sums) for label, _, sums in rows}
    medians = {label: statistics.median(sums) for label, _, sums in rows}

    def ratio(table, label, base):
        return f"{table[label] / table[base]:.1f}" if base in table else ""

    print("| run | frames | cloth mean (ms/frame) | cloth median | cloth p99 | budget | within | x demo (mean) | "
          "x demo (median) | x without contact (mean) | x without contact (median) | x one thread (mean) | "
          "x one thread (p99) |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    p99s = {label: sums[min(len(sums) - 1, int(0.99 * len(sums)))] for label, _, sums in rows}
    for label, budget, sums in rows:
        base = re.sub(r"_(stiff|true|contact|no_contact).*", "", label)
        plain, single = without_contact(label, means), one_thread(label, means)
        print(f"| {label} | {len(sums)} | {means[label]:.2f} | {medians[label]:.2f} | {p99s[label]:.2f} | {budget:g} | "
              f"{'yes' if means[label] <= budget else 'no'} | {ratio(means, label, base)} | {ratio(medians, label, base)} | "
              f"{ratio(means, label, plain)} | {ratio(medians, label, plain)} | {ratio(means, label, single)} | "
              f"{ratio(p99s, label, single)} |")
    print_contact_split(sys.argv[1:])


def contact_split(label, path):
    """A table row of contact's broad phase and sub-intervals for the run of `path`, or None."""
    summary = os.path.join(os.path.dirname(path), "summary.json")
    if not os.path.exists(summary):
        return None
    with open(summary) as f:
        c = json.load(f).get("contact")
    if not c or "broad_phase_ms" not in c:
        return None
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    contact = sum(float(r.get("contact") or 0) for r in rows)
    other = sum(float(r.get(p) or 0) for r in rows for p in PHASES if p != "contact")
    broad, frames, apps = c["broad_phase_ms"], len(rows), max(1, c["applications"])
    return (f"| {label} | {contact / frames:.2f} | {broad / frames:.2f} | {(contact - broad) / frames:.2f} | "
            f"{1000 * broad / apps:.0f} | {1000 * (contact - broad) / apps:.0f} | {broad / other:.2f} | "
            f"{(contact - broad) / other:.2f} | {1 + contact / other:.2f} | {c.get('self_pairs', 0) / apps:.1f} |")


def print_contact_split(args):
    split = [row for row in (contact_split(*arg.split(":", 2)[::2]) for arg in args) if row]
    if not split:
        return
    print()
    print("| run with contact | contact (ms/frame) | broad phase | sub-intervals | broad phase (us/application) | "
          "sub-intervals (us/application) | broad phase x the other phases | sub-intervals x the other phases | "
          "cloth x its other phases | self pairs per application |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    print("\n".join(split))


if __name__ == "__main__":
    main()
