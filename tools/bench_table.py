#!/usr/bin/python3
"""Turns Google Benchmark JSON into a markdown table (median of repetitions when present).

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
    print("| benchmark | wall us/step | CPU us/step | particle-steps/s (M) | iterations/step | max stretch after 1 s |")
    print("|---|---:|---:|---:|---:|---:|")
    for name, bs in runs.items():
        med = lambda key: statistics.median(b[key] for b in bs)
        rate = statistics.median(b.get("particle_steps/s", 0) for b in bs) / 1e6
        stretch = statistics.median(b.get("max_stretch", float("nan")) for b in bs)
        iters = [b["iterations/step"] for b in bs if "iterations/step" in b]
        iters = f"{statistics.median(iters):.2f}" if iters else ""
        print(f"| {name} | {med('real_time'):.1f} | {med('cpu_time'):.1f} | {rate:.2f} | {iters} | {stretch:.4f} |")


if __name__ == "__main__":
    main()
