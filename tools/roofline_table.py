#!/usr/bin/python3
"""The roofline table of docs/performance.md from a cloth_bench JSON run (bench/roofline.cpp's
rows): the machine's roofs on one thread and two, then each kernel at 33x33 with its time per call,
its flops and bytes per call, its achieved GFLOP/s and its share of the one-thread multiply + add
roof (the library is built with -ffp-contract=off; a double kernel's roof is half the float one).

    build/bench/cloth_bench --benchmark_filter='^(roof|kernel)/' --benchmark_repetitions=5 \\
        --benchmark_out=out/bench/roofline.json
    tools/roofline_table.py out/bench/roofline.json
"""
import json
import statistics
import sys
from collections import defaultdict


def medians(path):
    """Each benchmark's median over its repetitions: real time (us), CPU time (us) and counters."""
    with open(path) as f:
        data = json.load(f)
    runs = defaultdict(list)
    for b in data["benchmarks"]:
        if b.get("run_type") != "aggregate":
            runs[b.get("run_name", b["name"])].append(b)
    out = {}
    for name, bs in runs.items():
        scale = {"ns": 1e-3, "us": 1.0, "ms": 1e3}[bs[0].get("time_unit", "ns")]
        med = lambda key: statistics.median(b.get(key, 0.0) for b in bs)
        out[name] = {"real_us": med("real_time") * scale, "cpu_us": med("cpu_time") * scale,
                     "flops": med("flops_per_s"), "bytes": med("bytes_per_s"), "calls": med("calls_per_step") or 1,
                     "check_flops": med("check_flops_per_call"), "check_bytes": med("check_bytes_per_call"),
                     "moved": med("moved_by_constraints")}
    return out


def roofs(runs):
    """The peaks (GFLOP/s) and the triad's bandwidth (GB/s), per thread count."""
    def get(prefix, key, threads):
        row = runs.get(f"{prefix}/real_time/threads:{threads}") or runs.get(f"{prefix}/threads:{threads}")
        return row[key] / 1e9 if row else float("nan")
    return {t: {"fma": get("roof/peak_fma", "flops", t), "mul_add": get("roof/peak_mul_add", "flops", t),
                "triad": get("roof/stream_triad", "bytes", t)} for t in (1, 2)}


# The kernels in float (8 lanes); the others run in double (4 lanes: half the float roof).
FLOAT_KERNELS = {"small_steps_substep_64/33", "paper_step_float/33", "small_steps_constraints_64/33"}
# Rows timed as the difference of two runs: the substep with the true motion's constraints less the
# same substep without them is the constraints' time per call (their check in float SIMD).
DIFFERENCES = {"small_steps_constraints_64/33": "small_steps_substep_64/33"}


def per_call_row(name, k, runs):
    """A kernel row's us per call and its (GFLOP/s, kFLOP per call, KB per call), or None when not
    counted (a difference row without its base row, or with no time left over it)."""
    per_call = k["cpu_us"] / k["calls"]
    if name in DIFFERENCES:
        base = runs.get("kernel/" + DIFFERENCES[name])
        if not base:
            return per_call, None
        per_call -= base["cpu_us"] / base["calls"]
        if per_call <= 0:
            return per_call, None
        return per_call, (k["check_flops"] / 1e3 / per_call, k["check_flops"] / 1e3, k["check_bytes"] / 1e3)
    gflops = k["flops"] / 1e9
    if gflops <= 0:
        return per_call, None
    return per_call, (gflops, gflops * per_call, k["bytes"] / 1e9 * per_call)


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    runs = medians(sys.argv[1])
    r = roofs(runs)
    print("| roof | one thread | two threads |")
    print("|---|---:|---:|")
    print(f"| float FMA peak (GFLOP/s) | {r[1]['fma']:.1f} | {r[2]['fma']:.1f} |")
    print(f"| float multiply + add peak (GFLOP/s) | {r[1]['mul_add']:.1f} | {r[2]['mul_add']:.1f} |")
    print(f"| STREAM triad (GB/s) | {r[1]['triad']:.1f} | {r[2]['triad']:.1f} |")
    print()
    print("| kernel at 33x33 | precision | us per call | kFLOP per call | KB per call | GFLOP/s | share of its roof |")
    print("|---|---|---:|---:|---:|---:|---:|")
    for name, k in runs.items():
        if not name.startswith("kernel/"):
            continue
        single = name[7:] in FLOAT_KERNELS
        roof = r[1]["mul_add"] * (1 if single else 0.5)  # the library is built without FMA contraction
        precision = "float" if single else "double"
        per_call, counted = per_call_row(name[7:], k, runs)
        if counted:
            gflops, kflop, kb = counted
            print(f"| {name[7:]} | {precision} | {per_call:.1f} | {kflop:.0f} | {kb:.0f} | {gflops:.2f} | "
                  f"{100 * gflops / roof:.1f}% |")
        else:
            print(f"| {name[7:]} | {precision} | {per_call:.1f} | not counted | not counted | | |")
    for name in DIFFERENCES:
        k = runs.get("kernel/" + name)
        if k:
            print(f"\n{name}: its time per call less {DIFFERENCES[name]}'s; in its step the constraints "
                  f"move a particle by at most {k['moved']:.3g} m (0: the row times their check alone).")


if __name__ == "__main__":
    main()
