#!/usr/bin/python3
"""The extreme cases against each flag's fine-step reference, as Markdown: per flag size, every
configuration ranked by how many of the six cases it meets the reference's bounds in, then by its
median cost. The bounds (the stiff flag's goal):
    stable;
    p99 stretch  <= 1.25 x the reference's + 1 point;
    peak stretch <= 1.5 x the reference's + 2 points;
    kinetic energy in the carrier's frame over the last second (ke_late) between 0.5 and 2 times
    the reference's, in the cases where the flag flutters (50 m/s, gale).
Beside them, when the CSV has it, the same ratio of the energy at the scale of 8 x 8 patches of
the flag (ke_patch_late, tools/study/extreme_runs.h): the flutter without its grid-scale motion.
It is shown, and judged with --patch-energy; --patch-energy 4 or 16 judges (and shows) the energy
of 4 x 4 or 16 x 16 patches instead (ke_patch4_late, ke_patch16_late).
A configuration is judged against its own flag's reference: `reference` for the demo's flag,
`stiff_reference` for the stiff flag (configurations named stiff_*).

    tools/study/reference_table.py docs/study/stiff_extreme.csv
    tools/study/reference_table.py A.csv B.csv --configs stiff_newton_bdf2_240x8

Several CSVs are read as one: a row of a later file replaces one of an earlier file with the same
case, size and configuration (the reference's rows from a run that has a column the other lacks).
--configs ranks only the named configurations (comma-separated); --patch-energy judges the band
on ke_patch_late instead of ke_late (a row without it misses the band).
"""
import argparse
import csv
import math
import statistics
import sys

PATCH_COLUMNS = {8: "ke_patch_late", 4: "ke_patch4_late", 16: "ke_patch16_late"}
# The columns a CSV must have (traj_error and the patch energies are optional: NaN when absent).
REQUIRED = ["case", "size", "config", "stable", "p99_stretch", "peak_stretch", "ms_per_tick", "physics_hz", "ke_late"]
CASES = ["speed_50mps", "stop_10g", "spin_5radps", "teleport_1m", "light_particles", "gale_40mps"]
FLUTTER = ["speed_50mps", "gale_40mps"]


def num(v):
    try:
        return float(v)
    except (TypeError, ValueError):
        return math.nan


def reference_of(config):
    return "stiff_reference" if config.startswith("stiff_") else "reference"


def verdict(r, ref, band="ke_late"):
    """What r misses of the bounds against ref, the energy band judged on column `band`: a list of
    words (empty: all met)."""
    miss = []
    if r["stable"] != "1":
        return ["unstable"]
    if not num(r["p99_stretch"]) <= 1.25 * num(ref["p99_stretch"]) + 0.01:
        miss.append("p99")
    if not num(r["peak_stretch"]) <= 1.5 * num(ref["peak_stretch"]) + 0.02:
        miss.append("peak")
    if r["case"] in FLUTTER:
        ratio = num(r.get(band)) / num(ref.get(band))
        if not 0.5 <= ratio <= 2:
            miss.append("energy")
    return miss


def ranking(rows, size, band="ke_late", patch="ke_patch_late"):
    """Every configuration at `size` judged against its reference, the energy band on column
    `band`; the patch energy ratios shown from column `patch`."""
    here = [r for r in rows if r["size"] == str(size)]
    refs = {(r["config"], r["case"]): r for r in here if r["config"] in ("reference", "stiff_reference")}
    out = []
    for c in dict.fromkeys(r["config"] for r in here):
        if c in ("reference", "stiff_reference"):
            continue
        by_case = {r["case"]: r for r in here if r["config"] == c}
        judged = {x: verdict(by_case[x], refs[(reference_of(c), x)], band) for x in CASES
                  if x in by_case and (reference_of(c), x) in refs}
        stretch = sum(1 for m in judged.values() if not ({"unstable", "p99", "peak"} & set(m)))
        ratios = lambda column: [num(by_case[x].get(column)) / num(refs[(reference_of(c), x)].get(column))
                                 for x in FLUTTER if x in by_case and (reference_of(c), x) in refs]
        ms = statistics.median(num(r["ms_per_tick"]) for r in by_case.values())
        traj = [num(r.get("traj_error")) for r in by_case.values()]
        out.append({"config": c, "judged": judged, "stretch": stretch, "energy": ratios("ke_late"),
                    "patch": ratios(patch), "ms": ms,
                    "hz": by_case[CASES[0]]["physics_hz"] if CASES[0] in by_case else "",
                    "traj": statistics.median(traj) if all(math.isfinite(t) for t in traj) else math.nan,
                    "all": sum(1 for m in judged.values() if not m)})
    return sorted(out, key=lambda e: (-e["all"], -e["stretch"], e["ms"]))


def merge(tables):
    """The rows of every table (a list of rows) in turn, a later table's row replacing an earlier
    one's with the same case, size and configuration."""
    merged = {}
    for rows in tables:
        for r in rows:
            merged[(r["case"], r["size"], r["config"])] = r
    return list(merged.values())


def read(paths):
    """The rows of every CSV in paths, merged (merge)."""
    tables = []
    for path in paths:
        with open(path, newline="") as f:
            reader = csv.DictReader(f)
            missing = [c for c in REQUIRED if c not in (reader.fieldnames or [])]
            if missing:
                sys.exit(f"{path}: no column {', '.join(missing)}: not an extreme-case CSV of cloth_study with the "
                         "reference's figures")
            tables.append(list(reader))
    return merge(tables)


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("csv", nargs="*", default=["out/study/extreme.csv"])
    p.add_argument("--configs", default="", help="comma-separated configurations to rank (default: all)")
    p.add_argument("--patch-energy", nargs="?", type=int, const=8, choices=sorted(PATCH_COLUMNS),
                   help="judge the energy band on the energy of PATCH_ENERGY x PATCH_ENERGY patches (default 8: "
                        "ke_patch_late) instead of ke_late")
    a = p.parse_args()
    rows = read(a.csv)
    if a.configs:
        keep = set(a.configs.split(",")) | {"reference", "stiff_reference"}
        rows = [r for r in rows if r["config"] in keep]
    column = PATCH_COLUMNS[a.patch_energy or 8]
    patches = any(column in r for r in rows)
    for size in sorted({int(r["size"]) for r in rows}):
        band = f" (the energy band judged on {column})" if a.patch_energy else ""
        print(f"**{size}x{size}**: per case, the bounds a configuration misses{band} (blank: none); cases within "
              "the stretch bounds; ke_late / the reference's at 50 m/s and in the gale"
              + (f"; the same of {column}" if patches else "") +
              "; median traj_error (NaN when a run failed); median ms per tick at its physics rate\n")
        print("| configuration | Hz | " + " | ".join(CASES) + " | stretch ok | energy 50 m/s, gale | "
              + ("patch energy | " if patches else "") + "traj | ms/tick |")
        print("|---" * (len(CASES) + 6 + patches) + "|")
        for e in ranking(rows, size, column if a.patch_energy else "ke_late", column):
            cells = [", ".join(e["judged"].get(x, ["-"])) for x in CASES]
            energy = ", ".join(f"{v:.2g}" for v in e["energy"])
            patch = (", ".join(f"{v:.2g}" for v in e["patch"]) + " | ") if patches else ""
            print(f"| {e['config']} | {e['hz']} | " + " | ".join(cells) +
                  f" | {e['stretch']}/6 | {energy} | {patch}{e['traj']:.3g} | {e['ms']:.3g} |")
        print()


if __name__ == "__main__":
    main()
