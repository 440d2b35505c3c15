"""Checks of a study run's front (front.csv, cloth_study's front.h), each written here apart from
the C++ that wrote the columns:

    tools/study/study.py front-checks DIR             every column; the derived columns recomputed
                                                      from the raw ones (ms_per_frame, energy_ratio,
                                                      misses: the bounds written out again); each
                                                      flag's reference in every group
    tools/study/study.py front-checks --shipped DIR   only: the demo's flag as it ships is stable on
                                                      every path the run has (the ctest that runs the
                                                      demo's flag on all seven paths)
"""
import csv
import math
import os
import sys

COLUMNS = ["row", "flag", "path", "size", "config", "solver", "constraints", "physics_hz", "substeps", "stable",
           "failures", "ms_per_tick", "ms_per_frame", "timing", "traj_error", "p99_stretch", "peak_stretch",
           "max_stretch", "late_max_stretch", "ke_patch_late", "ref_p99_stretch", "ref_peak_stretch",
           "ref_ke_patch_late", "energy_ratio", "misses", "iterations_mean", "iterations_max", "ke_mean", "ke_late",
           "ke_patch4_late", "ke_patch16_late", "ke_windows", "max_speed"]
FLUTTER_PATHS = {"drive", "speed_50mps", "gale_40mps"}  # where the air keeps the flag fluttering
PATHS = ["drive", "speed_50mps", "stop_10g", "spin_5radps", "teleport_1m", "light_particles", "gale_40mps"]


def num(v):
    try:
        return float(v)
    except ValueError:
        return float("nan")


def read(d):
    path = os.path.join(d, "front.csv")
    with open(path, newline="") as f:
        reader = csv.DictReader(f)
        rows = list(reader)
        missing = [c for c in COLUMNS if c not in (reader.fieldnames or [])]
    if missing:
        sys.exit(f"{path}: missing columns {missing}")
    return path, rows


def misses(r):
    """The bounds of docs/study.md, written out again: p99 <= 1.25 ref + 0.01, peak <= 1.5 ref + 0.02,
    the 8x8 patch energy 0.5-2x the reference's on a fluttering path; unstable misses them all."""
    if r["stable"] != "1":
        return "unstable"
    out = []
    if not num(r["p99_stretch"]) <= 1.25 * num(r["ref_p99_stretch"]) + 0.01:
        out.append("p99")
    if not num(r["peak_stretch"]) <= 1.5 * num(r["ref_peak_stretch"]) + 0.02:
        out.append("peak")
    ratio = num(r["ke_patch_late"]) / num(r["ref_ke_patch_late"])
    if r["path"] in FLUTTER_PATHS and not 0.5 <= ratio <= 2:
        out.append("energy")
    return ";".join(out)


def close(a, b, digits=4):
    """Equal to the 4 significant digits the study prints (NaN equals NaN, inf equals inf: an
    unstable row's figures)."""
    if a == b:
        return True
    if math.isnan(a) or math.isnan(b):
        return math.isnan(a) and math.isnan(b)
    return abs(a - b) <= 10 ** (1 - digits) * max(abs(a), abs(b)) + 1e-300


def check_derived(rows):
    """ms_per_frame = ms_per_tick x physics_hz / 60; energy_ratio = ke_patch_late / ref_ke_patch_late;
    misses as the bounds say (rows with references only)."""
    problems = []
    for r in rows:
        key = f"{r['flag']}/{r['path']}/{r['size']}/{r['config']}"
        if not close(num(r["ms_per_frame"]), num(r["ms_per_tick"]) * num(r["physics_hz"]) / 60):
            problems.append(f"{key}: ms_per_frame {r['ms_per_frame']} is not ms_per_tick x physics_hz / 60")
        if math.isnan(num(r["ref_p99_stretch"])):
            continue  # a run without references (--no-references)
        if not close(num(r["energy_ratio"]), num(r["ke_patch_late"]) / num(r["ref_ke_patch_late"]), 3):
            problems.append(f"{key}: energy_ratio {r['energy_ratio']} is not ke_patch_late / ref_ke_patch_late")
        if r["misses"] != misses(r):
            problems.append(f"{key}: misses '{r['misses']}', the bounds say '{misses(r)}'")
    return problems


def check_references(rows):
    """Every group (flag, path, size) that has rows has its reference, which misses nothing and has no
    trajectory error against itself."""
    problems = []
    groups = {(r["flag"], r["path"], r["size"]) for r in rows}
    for g in sorted(groups):
        refs = [r for r in rows if (r["flag"], r["path"], r["size"]) == g and r["config"] == "reference"]
        if not refs:
            continue  # a run of chosen configurations (--configs) may leave it out
        ref = refs[0]
        if ref["misses"] or num(ref["traj_error"]) != 0:
            problems.append(f"{'/'.join(g)}: the reference misses '{ref['misses']}', traj_error {ref['traj_error']}")
    return problems


def check_shipped(d):
    path, rows = read(d)
    shipped = [r for r in rows if r["flag"] == "demo" and r["config"] == "shipped"]
    if not shipped:
        sys.exit(f"{path}: no rows of the demo's flag as it ships (flag=demo, config=shipped)")
    bad = [f"{r['path']} at {r['size']}x{r['size']}" for r in shipped if r["stable"] != "1"]
    if bad:
        sys.exit(f"{path}: the demo's flag as it ships is not stable on: {', '.join(bad)}")
    print(f"{path}: the demo's flag as it ships is stable on " + ", ".join(f"{r['path']} ({r['size']})" for r in shipped))


def main(args):
    """Runs on argv, the command line's arguments without the program's name."""
    if len(args) == 2 and args[0] == "--shipped":
        return check_shipped(args[1])
    if len(args) != 1:
        sys.exit(__doc__)
    path, rows = read(args[0])
    problems = check_derived(rows) + check_references(rows)
    if problems:
        sys.exit(f"{path}: " + "; ".join(problems[:20]))
    print(f"{path}: {len(rows)} rows, every column; ms_per_frame, energy_ratio and misses agree with the raw "
          "columns and the bounds; every reference misses nothing")
