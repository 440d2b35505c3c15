"""NVIDIA Newton's cloth solvers on the study's flag and pole motion, as rows of the study's CSV.

    tools/study/study.py nvidia-newton IN_DIR OUT_CSV [--solvers vbd,xpbd,style3d] [--max-size N] [--extreme-csv CSV]

IN_DIR holds the JSON files of ``cloth_study --export-nvidia-newton DIR`` (one per configuration: the
particles, masses, springs, triangles, pinned particles and every pin's target at the end of every
step), and a vbd check: our vbd's positions on a small flag after its steps, which Newton's VBD is
checked against (nvidia_newton_vbd_check.csv beside OUT_CSV, flagstudy/nvidia_newton/vbd_check.py). Each file is run with each Newton solver (NVIDIA Newton 1.8.0 on Warp 1.19.0, CPU device,
pins from tools/study/requirements-nvidia-newton.txt; install them in a venv, e.g. .venv-nvidia-newton)
and gives one row of OUT_CSV, with the columns of the study's error_vs_runtime.csv less ``row``.

A solver is named as in the study, ``name[:key=value,...]``; ``--solvers`` takes a comma- (or
semicolon-) separated list, e.g. ``vbd,xpbd:iterations=10,substeps=4,style3d``. The row's
``solver`` column names every setting used, defaults included.

The package flagstudy/nvidia_newton/ says how: how the input is read and checked (load.py, into
case.py's Case), how a configuration is stepped (run.py), each solver's settings (solvers.py), how our
springs' stiffness is matched (models.py), the metrics (metrics.py) and what the extreme cases add
(extreme.py).

Warp compiles its kernels on first use (LLVM, CPU) and caches them in ~/.cache/warp/<version>. On
the study's 2-core machine (with another build running beside it), vbd, xpbd and style3d on a 9x9
and a 17x17 input of 240 steps took 74 s in all with an empty cache (about 55 s of it compiling
Newton's modules; xpbd's kernels alone take 20 s) and 20 to 27 s with the cache filled; the study's
17x17 and 33x33 flags (4 files of 360 steps, 12 rows) take about 85 s with the cache filled.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

try:
    import numpy  # noqa: F401  (the package's modules need it)
except ImportError:
    sys.exit("nvidia_newton_study: numpy is missing: "
             "pip install -r tools/study/requirements-nvidia-newton.txt (in a venv)")

from flagstudy.nvidia_newton.case import Case  # noqa: E402
from flagstudy.nvidia_newton.extreme import EXTREME_COLUMNS  # noqa: E402
from flagstudy.nvidia_newton.load import InputError, load_case  # noqa: E402
from flagstudy.nvidia_newton.output import write_csv  # noqa: E402
from flagstudy.nvidia_newton.run import run_one  # noqa: E402
from flagstudy.nvidia_newton.solvers import SolverChoice, parse_solver, split_solver_list  # noqa: E402
from flagstudy.nvidia_newton.vbd_check import COLUMNS as VBD_CHECK_COLUMNS, vbd_check_rows  # noqa: E402


class UsageError(Exception):
    pass


def parse_args(argv):
    ap = argparse.ArgumentParser(prog="study.py nvidia-newton", description=__doc__.split("\n\n")[0])
    ap.add_argument("in_dir", type=Path, help="directory of cloth_study --export-nvidia-newton JSON files")
    ap.add_argument("out_csv", type=Path)
    ap.add_argument("--solvers", default="vbd,xpbd,style3d",
                    help="comma-separated solver specs, name[:key=value,...] (default: %(default)s)")
    ap.add_argument("--max-size", type=int, default=None, help="skip configurations with size > N")
    ap.add_argument("--extreme-csv", type=Path, default=None,
                    help="where the extreme cases' rows go (default: nvidia_newton_extreme.csv beside OUT_CSV)")
    return ap.parse_args(argv)


def read_inputs(args) -> tuple[list[SolverChoice], list[Case]]:
    """The solvers asked for and the configurations of IN_DIR; UsageError when either is wrong."""
    try:
        choices = [parse_solver(s) for s in split_solver_list(args.solvers)]
    except ValueError as e:
        raise UsageError(str(e)) from None
    if not choices:
        raise UsageError("--solvers names no solver")
    if not args.in_dir.is_dir():
        raise UsageError(f"{args.in_dir} is not a directory")
    paths = sorted(args.in_dir.glob("*.json"))
    if not paths:
        raise UsageError(f"no *.json in {args.in_dir}")
    try:
        cases = [load_case(p) for p in paths]
    except InputError as e:
        raise UsageError(str(e)) from None
    if args.max_size is not None:
        cases = [c for c in cases if c.size <= args.max_size]
        if not cases:
            raise UsageError(f"no configuration in {args.in_dir} has size <= {args.max_size}")
    return choices, cases


def start_warp():
    """Warp on its CPU device, quiet; UsageError when Warp or Newton is missing."""
    try:
        import warp as wp

        import newton  # noqa: F401
    except ImportError as e:
        raise UsageError(f"{e}: pip install -r tools/study/requirements-nvidia-newton.txt (in a venv)") from None
    wp.config.log_level = wp.LOG_WARNING  # no banner, no per-module compile lines
    wp.init()
    wp.set_device("cpu")
    return wp


def run_all(wp, cases: list[Case], choices: list[SolverChoice]) -> tuple[list[dict], list[dict]]:
    """Every configuration with every solver: (rows, extreme-case rows), one progress line each."""
    rows, extreme_rows = [], []
    cases = [c for c in cases if c.kind != "vbd_check"]  # write_vbd_check's
    total = len(cases) * len(choices)
    for case in cases:
        for choice in choices:
            t0 = time.perf_counter()
            with wp.ScopedDevice("cpu"):
                row = run_one(case, choice)
            (extreme_rows if case.kind == "extreme" else rows).append(row)
            ms = row.get("ms_per_step", row.get("ms_per_tick"))
            note = " - " + row["note"] if row["note"] else ""
            print(
                f"[{len(rows) + len(extreme_rows)}/{total}] {case.path.name} {row['solver']}: ms/step {ms} "
                f"max_stretch {row['max_stretch']} p99 {row['p99_stretch']} stable {row['stable']} "
                f"fail_step {row['fail_step']} ({time.perf_counter() - t0:.1f} s){note}",
                file=sys.stderr,
                flush=True,
            )
    return rows, extreme_rows


def write_vbd_check(wp, cases: list[Case], path: Path) -> None:
    """Our vbd against Newton's VBD on every configuration that carries our positions (vbd_check.py)."""
    rows = []
    for case in cases:
        with wp.ScopedDevice("cpu"):
            rows += vbd_check_rows(case)
    write_csv(path, rows, VBD_CHECK_COLUMNS)
    for r in rows:
        print(f"vbd check {r['scene']} {r['size']} at {r['iterations']} iterations: rms {r['rms_m']} m, "
              f"max {r['max_m']} m (moved {r['moved_rms_m']} m)", file=sys.stderr)
    print(f"nvidia_newton_study: {len(rows)} vbd check rows written to {path}", file=sys.stderr)


def main(argv) -> int:
    """Runs on argv, the command line's arguments without the program's name."""
    args = parse_args(argv)
    try:
        choices, cases = read_inputs(args)
        wp = start_warp()
    except UsageError as e:
        print(f"nvidia_newton_study: {e}", file=sys.stderr)
        return 2
    rows, extreme_rows = run_all(wp, cases, choices)
    write_csv(args.out_csv, rows)
    print(f"nvidia_newton_study: {len(rows)} rows written to {args.out_csv}", file=sys.stderr)
    if any(c.name == "vbd" for c in choices):
        write_vbd_check(wp, cases, args.out_csv.with_name("nvidia_newton_vbd_check.csv"))
    if any(c.kind == "extreme" for c in cases):
        extreme_csv = args.extreme_csv or args.out_csv.with_name("nvidia_newton_extreme.csv")
        write_csv(extreme_csv, extreme_rows, EXTREME_COLUMNS)
        print(f"nvidia_newton_study: {len(extreme_rows)} extreme-case rows written to {extreme_csv}", file=sys.stderr)
    return 0
