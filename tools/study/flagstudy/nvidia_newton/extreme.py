"""The extreme cases.

A JSON with ``"kind": "extreme"`` is one of cloth_study's extreme cases at one size (the demo's flag,
k = 1e3 / 1e2 / 5 N/m, on a carrier driven through the case; pins and the carrier's velocity per
240 Hz tick; its start velocities). It adds what the flag feels there: our air model (cloth/air.h,
pressure drag, skin friction and lift per triangle, evaluated here in numpy, and checked against the
library's force at one exported state of every case: load.check_air_twin) and the linear drag, both
evaluated at the state before each Newton step and passed as ``state.particle_f`` (the external
force that VBD's forward step, XPBD's integrate_particles and Style3D's init step read), i.e.
explicit air. There is no pole collision. Its row goes to the extreme CSV (``--extreme-csv``,
default nvidia_newton_extreme.csv beside OUT_CSV) with cloth_study's extreme.csv metrics:
peak_stretch leaves out the 0.25 s after the pole's jump, late_max_stretch and the stability rule
look at the last second, max_speed is relative to the carrier, and ms_per_tick includes the numpy
air (ours includes our air too). ``substeps=auto`` above XPBD_MAX_AUTO_SUBSTEPS (128) is not run;
the row says why.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from flagstudy.nvidia_newton.output import fmt

if TYPE_CHECKING:
    from flagstudy.nvidia_newton.case import Case
    from flagstudy.nvidia_newton.metrics import Metrics
    from flagstudy.nvidia_newton.solvers import SolverChoice

EXTREME_COLUMNS = [
    "case", "size", "config", "solver", "stable", "fail_step", "ms_per_tick", "timing", "max_stretch",
    "peak_stretch", "p99_stretch", "late_max_stretch", "max_speed", "note",
]


def external_forces(case: Case, x: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Our air model (cloth/air.h: pressure drag, skin friction and lift per triangle, shared by its
    corners) and linear drag, evaluated at (x, v): the explicit external force of an extreme case."""
    f = -case.drag * case.masses[:, None] * v
    a = case.air
    if a is not None and a["enabled"] and len(case.triangles):
        t = case.triangles
        xa, xb, xc = x[t[:, 0]], x[t[:, 1]], x[t[:, 2]]
        cross = np.cross(xb - xa, xc - xa)
        twice = np.linalg.norm(cross, axis=1)
        w = np.asarray(a["wind"], dtype=float) - (v[t[:, 0]] + v[t[:, 1]] + v[t[:, 2]]) / 3
        speed = np.linalg.norm(w, axis=1)
        ok = (twice >= 1e-14) & (speed >= 1e-9)
        twice, speed = np.where(ok, twice, 1.0), np.where(ok, speed, 1.0)
        n = cross / twice[:, None]
        wn = np.einsum("ij,ij->i", w, n)
        n = np.where((wn < 0)[:, None], -n, n)  # oriented with the flow
        wn = np.abs(wn)
        half_rho_area = 0.5 * float(a["density"]) * 0.5 * twice
        tangential = w - wn[:, None] * n
        force = (half_rho_area * speed)[:, None] * (
            float(a["drag_coefficient"]) * wn[:, None] * n + float(a["friction_coefficient"]) * tangential)
        lift_dir = n - (wn / speed**2)[:, None] * w
        lift_norm = np.linalg.norm(lift_dir, axis=1)
        sin_a, cos_a = wn / speed, np.linalg.norm(tangential, axis=1) / speed
        lift = (half_rho_area * float(a["lift_coefficient"]) * speed**2 * sin_a * cos_a
                / np.where(lift_norm > 1e-9, lift_norm, 1.0))
        force += np.where(lift_norm > 1e-9, lift, 0.0)[:, None] * lift_dir
        force[~ok] = 0.0
        for corner in range(3):
            np.add.at(f, t[:, corner], force / 3)
    f[case.pinned] = 0.0
    return f


def make_extreme_row(case: Case, choice: SolverChoice, label: str, metrics: Metrics | None, ms: float,
                     note: str) -> dict:
    ok = metrics is not None

    def metric(name: str) -> str:
        return fmt(getattr(metrics, name) if ok else math.nan, 4)

    return {
        "case": case.scene,
        "size": case.size,
        "config": choice.spec.family,
        "solver": label,
        "stable": 1 if ok and metrics.fail_step < 0 else 0,
        "fail_step": metrics.fail_step if ok else -1,
        "ms_per_tick": fmt(ms, 4),
        "timing": "warp_cpu",
        "max_stretch": metric("max_stretch"),
        "peak_stretch": metric("peak_stretch"),
        "p99_stretch": metric("p99_stretch"),
        "late_max_stretch": metric("late_max_stretch"),
        "max_speed": metric("max_speed"),
        "note": note,
    }
