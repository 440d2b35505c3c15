#!/usr/bin/python3
"""Turns Google Benchmark JSON into a markdown table (median of repetitions when present), then
the multigrid cost goals as ratios of medians from that same run (the swung pole, double).

    tools/bench_table.py out/bench/cloth_bench.json > out/bench/cloth_bench.md
"""
import json
import statistics
import sys
from collections import defaultdict


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    with open(sys.argv[1]) as f:
        data = json.load(f)
    runs = defaultdict(list)
    for b in data["benchmarks"]:
        if b.get("run_type") == "aggregate":
            continue
        runs[b["run_name"] if "run_name" in b else b["name"]].append(b)
    ctx = data.get("context", {})
    print(f"Machine: {ctx.get('num_cpus', '?')} CPUs at {ctx.get('mhz_per_cpu', '?')} MHz; "
          f"{ctx.get('date', '')}; build {ctx.get('library_build_type', '?')}. "
          "Medians over repetitions (CPU time of the calling thread and wall time).")
    print()
    contact = {name: bs for name, bs in runs.items() if name.startswith("contactApply/")}
    print("| benchmark | wall us/step | CPU us/step | particle-steps/s (M) | iterations (substeps)/step | max stretch after 1 s |")
    print("|---|---:|---:|---:|---:|---:|")
    for name, bs in runs.items():
        if name in contact:
            continue
        med = lambda key: statistics.median(b[key] for b in bs)
        rate = statistics.median(b.get("particle_steps/s", 0) for b in bs) / 1e6
        stretch = statistics.median(b.get("max_stretch", float("nan")) for b in bs)
        iters = [b.get("iterations/step", b.get("substeps/step")) for b in bs if "iterations/step" in b or "substeps/step" in b]
        iters = f"{statistics.median(iters):.2f}" if iters else ""
        print(f"| {name} | {med('real_time'):.1f} | {med('cpu_time'):.1f} | {rate:.2f} | {iters} | {stretch:.4f} |")
    contact_table(contact)
    goals(runs)


def contact_table(runs):
    """The contactApply rows: one application of contact per call, with its work."""
    if not runs:
        return
    print()
    print("Contact, one application per call (medians of repetitions):")
    print()
    print("| benchmark | wall us/call | broad phase us/call | self pairs | sub-intervals |")
    print("|---|---:|---:|---:|---:|")
    for name, bs in runs.items():
        med = lambda key: statistics.median(b.get(key, float("nan")) for b in bs)
        print(f"| {name} | {med('real_time'):.1f} | {med('broad_phase_us/call'):.1f} | "
              f"{med('self_pairs/call'):.0f} | {med('subintervals/call'):.0f} |")


# The cost goals of the multigrid solve, each against the paper's step of the same run and size.
PAPER, ADAPTIVE, ONE_CYCLE = "swung_kangcho_fast_double", "swung_multigrid_adaptive_double", "swung_multigrid_1_cycle_double"


def goals(runs):
    def median_us(row, size):
        bs = [b for name, group in runs.items() if name.startswith(f"stepFlag/{row}/{size}/") for b in group]
        return statistics.median(b["real_time"] for b in bs) if bs else None

    lines = []

    def goal(label, value, limit):
        lines.append(f"| {label} | {value:.2f}x | <= {limit:g}x | {'yes' if value <= limit else 'no'} |")

    for row, label, limit in ((ONE_CYCLE, "one cycle", 4), (ADAPTIVE, "adaptive default", 10)):
        for size in (33, 129):
            mg, paper = median_us(row, size), median_us(PAPER, size)
            if mg and paper:
                goal(f"{label} / paper's step, {size}x{size}", mg / paper, limit)
    for row, label in ((ADAPTIVE, "adaptive default"), (PAPER, "paper's step")):
        small, large = median_us(row, 33), median_us(row, 257)
        if small and large:
            # particle-steps/s at 33x33 over those at 257x257 (per-particle cost, large over small)
            goal(f"{label}: particle-steps/s, 33x33 over 257x257", (large / 257**2) / (small / 33**2), 1.5)
    small = [median_us(r, 33) for r in (ADAPTIVE, PAPER)]
    large = [median_us(r, 257) for r in (ADAPTIVE, PAPER)]
    if all(small) and all(large):
        goal("adaptive / paper's step at 257x257, over the same at 33x33",
             (large[0] / large[1]) / (small[0] / small[1]), 1.5)
    if lines:
        print()
        print("Multigrid cost goals (medians of this run, wall time):")
        print()
        print("| goal | measured | bound | met |")
        print("|---|---:|---:|---|")
        print("\n".join(lines))


if __name__ == "__main__":
    main()
