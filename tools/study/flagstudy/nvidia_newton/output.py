"""The rows of the study's CSV (error_vs_runtime.csv's columns less ``row``, and ``note``), written as
cloth_study writes its own: numbers as %g (ms with 5 digits, stretch with 4), the solver column quoted,
so the rows sit next to error_vs_runtime.csv's (which has a ``row`` column first)."""

from __future__ import annotations

import math
import os
import tempfile
from pathlib import Path
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from flagstudy.nvidia_newton.case import Case
    from flagstudy.nvidia_newton.metrics import Metrics
    from flagstudy.nvidia_newton.solvers import SolverChoice

COLUMNS = [
    "scene", "size", "stiffness", "h", "family", "solver", "ms_per_step", "timing", "solve_error",
    "traj_error_be", "traj_error_fine", "max_stretch", "p99_stretch", "energy_growth", "stable",
    "fail_step", "note",
]


def fmt(v: float, digits: int) -> str:
    """As cloth_study prints its numbers (%g with 4 or 5 digits); nan as nan."""
    return "nan" if math.isnan(v) else f"{v:.{digits}g}"


def make_row(case: Case, choice: SolverChoice, label: str, metrics: Metrics | None, ms: float, note: str) -> dict:
    ok = metrics is not None
    return {
        "scene": case.scene,
        "size": case.size,
        "stiffness": f"{case.stiffness:g}",
        "h": f"{case.h:g}",
        "family": choice.spec.family,
        "solver": label,
        "ms_per_step": fmt(ms, 5),
        "timing": "warp_cpu",
        "solve_error": "nan",
        "traj_error_be": "nan",
        "traj_error_fine": "nan",
        "max_stretch": fmt(metrics.max_stretch if ok else math.nan, 4),
        "p99_stretch": fmt(metrics.p99_stretch if ok else math.nan, 4),
        "energy_growth": "nan",
        "stable": 1 if ok and metrics.fail_step < 0 else 0,
        "fail_step": metrics.fail_step if ok else -1,
        "note": note,
    }


def csv_field(column: str, value) -> str:
    text = str(value)
    if column == "solver" or any(ch in text for ch in ',"\n\r'):  # cloth_study always quotes solver
        return '"' + text.replace('"', '""') + '"'
    return text


def write_csv(path: Path, rows: list[dict], columns: list[str] = COLUMNS) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=path.name + ".", suffix=".tmp", dir=path.parent)
    with os.fdopen(fd, "w", newline="") as f:
        f.write(",".join(columns) + "\n")
        for row in rows:
            f.write(",".join(csv_field(c, row[c]) for c in columns) + "\n")
    os.replace(tmp, path)
