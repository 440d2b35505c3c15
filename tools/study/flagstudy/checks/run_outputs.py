"""The checks of a run's outputs (tools/study/study.py check DIR): every column, solver family and
scene of error_vs_runtime.csv, the figures, the values docs/study.md quotes wherever the run has the
rows, multigrid and an exact reference at every scene and size, NVIDIA Newton's solvers when asked,
and front.csv with the demo's flag as it ships stable on every path the run has (front_checks.py
checks front.csv's columns)."""
import csv
import os
import sys

from flagstudy import front_checks
from flagstudy.checks.common import num

COLUMNS = ["row", "scene", "size", "stiffness", "h", "duration", "family", "solver", "ms_per_step", "timing", "solve_error", "traj_error_be",
           "traj_error_fine", "max_stretch", "p99_stretch", "energy_growth", "stable", "fail_step"]
FAMILIES = {"kangcho", "kangcho_no_eq17", "exact", "desbrun", "cg", "chebyshev", "explicit", "bullet", "multigrid",
            "multigrid_stationary"}
SCENES = {"hanging_flag", "vehicle_path"}
MAIN = ("10000", "0.00416667")  # the stiffness and step of every scene and size of the grid
MULTIGRID_ROWS = {"multigrid", "multigrid:cycles=1", "multigrid:cycles=2"}
NVIDIA_NEWTON_FAMILIES = {"nvidia_newton_vbd", "nvidia_newton_xpbd", "nvidia_newton_style3d"}
EXTREME_COLUMNS = ["ms_per_tick", "max_stretch", "peak_stretch", "p99_stretch", "late_max_stretch"]


def check_findings(rows):
    """The values docs/study.md quotes, wherever the run has the rows: the exact solve is exact,
    adaptive multigrid is within 2% of it at k = 1e4, h = 1/240 in both scenes, and the paper's step
    does not survive the vehicle path at 65x65."""
    problems = []
    for r in rows:
        where = f"{r['scene']} {r['size']} k={r['stiffness']} h={r['h']} {r['solver']}"
        err = num(r["solve_error"])
        if r["family"] == "exact" and err == err and err > 1e-9:
            problems.append(f"{where}: exact's solve error {err} > 1e-9")
        main = r["stiffness"] == "10000" and r["h"] == "0.00416667"
        if main and r["solver"] == "multigrid" and not err <= 0.02:
            problems.append(f"{where}: adaptive multigrid's solve error {err} > 0.02")
        if main and r["scene"] == "vehicle_path" and r["size"] == "65" and r["solver"] == "kangcho:iterations=1" \
                and r["stable"] != "0":
            problems.append(f"{where}: the paper's step is stable at 65x65 on the vehicle path (docs/study.md says not)")
    return problems


def check_everywhere(rows, nvidia_newton_rows):
    """Multigrid (adaptive, one and two cycles) and an exact reference at every scene and size of
    the run; with nvidia_newton_rows, each of NVIDIA Newton's three solvers too, each row with numbers or with
    the reason it has none."""
    problems = []
    places = sorted({(r["scene"], int(r["size"])) for r in rows if (r["stiffness"], r["h"]) == MAIN})
    for scene, size in places:
        here = [r for r in rows if r["scene"] == scene and int(r["size"]) == size and (r["stiffness"], r["h"]) == MAIN]
        missing = sorted(MULTIGRID_ROWS - {r["solver"] for r in here})
        if not any(r["family"] == "exact" for r in here):
            missing.append("an exact reference")
        if nvidia_newton_rows is not None:
            theirs = [r for r in nvidia_newton_rows if r["scene"] == scene and int(r["size"]) == size]
            missing += sorted(NVIDIA_NEWTON_FAMILIES - {r["family"] for r in theirs})
            for r in theirs:
                if num(r["max_stretch"]) != num(r["max_stretch"]) and not r.get("note"):
                    problems.append(f"nvidia_newton.csv {scene} {size} {r['solver']}: no result and no reason")
        if missing:
            problems.append(f"{scene} {size}x{size}: no rows for {missing}")
    return problems


def check_nvidia_newton_extremes(d):
    """nvidia_newton_extreme.csv: each of NVIDIA Newton's three solvers at every extreme case and size
    it holds, each row with its cost and stretch or with the reason it has none."""
    try:
        with open(os.path.join(d, "nvidia_newton_extreme.csv"), newline="") as f:
            reader = csv.DictReader(f)
            missing = [c for c in EXTREME_COLUMNS + ["note"] if c not in reader.fieldnames]
            rows = list(reader)
    except OSError as e:
        return [f"--nvidia-newton: {e}"]
    if missing:
        return [f"nvidia_newton_extreme.csv: missing columns {missing}"]
    problems = []
    for case, size in sorted({(r["case"], r["size"]) for r in rows}):
        here = [r for r in rows if (r["case"], r["size"]) == (case, size)]
        absent = sorted(NVIDIA_NEWTON_FAMILIES - {r["config"] for r in here})
        if absent:
            problems.append(f"nvidia_newton_extreme.csv {case} {size}: no rows for {absent}")
        for r in here:
            if num(r["p99_stretch"]) != num(r["p99_stretch"]) and not r["note"]:
                problems.append(f"nvidia_newton_extreme.csv {case} {size} {r['solver']}: no result and no reason")
    if not rows:
        problems.append("nvidia_newton_extreme.csv: no rows")
    return problems


# Our vbd against NVIDIA Newton's VBD (flagstudy/nvidia_newton/vbd_check.py): at VBD_CONVERGED iterations both
# reach backward Euler's step, so their positions after half a second of the drive lie within VBD_BOUND_M (rms;
# Newton's are float32, about 1 m from the origin) while the flag moves over VBD_MOVED_M (rms). At 10 iterations
# they lie 6 mm apart: the check tells the two implementations' orders of vertices apart.
VBD_CONVERGED, VBD_BOUND_M, VBD_MOVED_M = 100, 1e-4, 0.1


def check_vbd_against_nvidia_newton(d):
    """nvidia_newton_vbd_check.csv: our vbd and Newton's VBD at VBD_CONVERGED iterations within VBD_BOUND_M of
    each other, with the flag moving."""
    try:
        with open(os.path.join(d, "nvidia_newton_vbd_check.csv"), newline="") as f:
            rows = [r for r in csv.DictReader(f) if int(r["iterations"]) == VBD_CONVERGED]
    except (OSError, KeyError, ValueError) as e:
        return [f"--nvidia-newton: nvidia_newton_vbd_check.csv: {e}"]
    problems = [f"nvidia_newton_vbd_check.csv {r['scene']} {r['size']}: our vbd and Newton's VBD at {VBD_CONVERGED} "
                f"iterations are {r['rms_m']} m apart (rms; at most {VBD_BOUND_M:g})"
                for r in rows if not float(r["rms_m"]) <= VBD_BOUND_M]
    if not any(float(r["moved_rms_m"]) > VBD_MOVED_M for r in rows):
        problems.append(f"nvidia_newton_vbd_check.csv: no row at {VBD_CONVERGED} iterations whose flag moves over "
                        f"{VBD_MOVED_M:g} m")
    return problems


def check_run(d, nvidia_newton):
    """A run's outputs in d: error_vs_runtime.csv's columns, solver families and scenes, the figures,
    front.csv and front.png, check_findings and check_everywhere (with nvidia_newton, NVIDIA Newton's CSVs
    too); exit 1 with the problems, else print a line and check that the demo's flag as it ships is
    stable on every path of the front (front_checks.check_shipped)."""
    with open(os.path.join(d, "error_vs_runtime.csv"), newline="") as f:
        reader = csv.DictReader(f)
        rows = list(reader)
        missing = [c for c in COLUMNS if c not in reader.fieldnames]
    problems = []
    if missing:
        problems.append(f"missing columns: {missing}")
    if FAMILIES - {r['family'] for r in rows}:
        problems.append(f"missing solver families: {sorted(FAMILIES - {r['family'] for r in rows})}")
    if SCENES - {r['scene'] for r in rows}:
        problems.append(f"missing scenes: {sorted(SCENES - {r['scene'] for r in rows})}")
    for name in ["error_vs_runtime.png", "stability.png", "front.csv", "front.png"]:
        if not os.path.isfile(os.path.join(d, name)):
            problems.append(f"missing {name}")
    problems += check_findings(rows)
    nvidia_newton_rows = None
    if nvidia_newton:
        try:
            with open(os.path.join(d, "nvidia_newton.csv"), newline="") as f:
                nvidia_newton_rows = list(csv.DictReader(f))
        except OSError as e:
            problems.append(f"--nvidia-newton: {e}")
            nvidia_newton_rows = []
    problems += check_everywhere(rows, nvidia_newton_rows)
    if nvidia_newton:
        problems += check_nvidia_newton_extremes(d) + check_vbd_against_nvidia_newton(d)
    if problems:
        sys.exit(f"{d}: " + "; ".join(problems))
    print(f"{d}: {len(rows)} rows, every column, solver family and scene present, multigrid"
          f"{' and NVIDIA Newton' if nvidia_newton else ''} at every scene and size"
          f"{' (and its extreme cases)' if nvidia_newton else ''}; the findings hold")
    front_checks.check_shipped(d)
