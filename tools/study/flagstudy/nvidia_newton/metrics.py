"""The metrics of a run, from the particle positions after every study step, with OUR springs list.

- max_stretch: max over steps and over the structural springs of max(L/rest - 1, 0).
- p99_stretch: max over steps of the 99th percentile (nearest rank, as cloth/diagnostics.cpp) over
  those springs of max(L/rest - 1, 0).
- ms_per_step: median wall time of one study step (pins written, all substeps, wp.synchronize()).
- stable: 1 if every position is finite, within 100 m of the first pin (its target at that step),
  every speed (|x_s - x_{s-1}| / h, from positions, so the same for every solver) < 1000 m/s, and
  the max stretch over the last 0.25 s < 0.5. fail_step: the first step breaking this, -1 if none.
  The run stops at the first step that is non-finite, too far or too fast (as cloth_study does);
  max_stretch and p99_stretch then cover the steps before it.
- timing = warp_cpu; solve_error, traj_error_be, traj_error_fine, energy_growth = nan.
A solver that cannot run a configuration (an exception, or a run in which no free particle ever
moves 1e-6 m from its start) still gives its row: stable = 0, metrics nan, the reason in ``note``.
Stretch is measured over the structural springs, as cloth_study's part 1 does
(``cloth::measure(..., structuralOnly = true)``). One difference remains: cloth_study calls a run
unstable as soon as any step's stretch exceeds 1.0 (``StabilityLimits``); this harness looks at
the last 0.25 s instead.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from flagstudy.nvidia_newton.case import Case

STRETCH_KINDS = ("structural",)  # as cloth_study part 1 (cloth::measure(..., structuralOnly = true))
MAX_DISTANCE = 100.0  # m from the first pin
MAX_SPEED = 1000.0  # m/s
LATE_WINDOW = 0.25  # s
LATE_MAX_STRETCH = 0.5
EXTREME_LATE_WINDOW = 1.0  # s: cloth_study's extreme cases judge the last second
JUMP_WINDOW = 0.25  # s after a jump of the pole that peak_stretch leaves out (as cloth_study)


def stretch_per_spring(x: np.ndarray, ij: np.ndarray, rest: np.ndarray) -> np.ndarray:
    lengths = np.linalg.norm(x[ij[:, 0]] - x[ij[:, 1]], axis=1)
    return np.maximum(lengths / rest - 1.0, 0.0)


def p99_nearest_rank(values: np.ndarray) -> float:
    rank = max(int(math.ceil(0.99 * len(values))) - 1, 0)
    return float(np.partition(values, rank)[rank])


@dataclass
class Metrics:
    max_stretch: float = 0.0
    p99_stretch: float = 0.0
    peak_stretch: float = 0.0  # max_stretch without the JUMP_WINDOW after a jump of the pole
    late_max_stretch: float = 0.0  # over the late window
    max_speed: float = 0.0  # m/s relative to the carrier (extreme cases), from positions
    fail_step: int = -1
    reason: str = ""
    moved: float = 0.0  # farthest any free particle got from its start (m)
    late_stretch: list = field(default_factory=list)  # (step, max stretch) over the last 0.25 s


class Monitor:
    """Checks each step's positions and keeps the run's stretch metrics."""

    def __init__(self, case: Case):
        mask = np.isin(case.spring_kind, STRETCH_KINDS)
        self.ij, self.rest = case.spring_ij[mask], case.spring_rest[mask]
        self.case = case
        self.late_window = EXTREME_LATE_WINDOW if case.kind == "extreme" else LATE_WINDOW
        self.late_from = case.steps - max(1, int(round(self.late_window / case.h)))
        self.prev = case.rest.copy()
        self.free = np.setdiff1d(np.arange(case.n), case.pinned)
        self.m = Metrics()

    def step(self, s: int, x: np.ndarray) -> bool:
        """Record step s (positions x at its end); False when the run has to stop here."""
        c, m = self.case, self.m
        problem = ""
        if not np.all(np.isfinite(x)):
            problem = "non-finite position"
        elif np.max(np.linalg.norm(x - c.pin_targets[s, 0], axis=1)) > MAX_DISTANCE:
            problem = f"position beyond {MAX_DISTANCE:g} m of the first pin"
        elif np.max(np.linalg.norm(x - self.prev, axis=1)) / c.h >= MAX_SPEED:
            problem = f"speed beyond {MAX_SPEED:g} m/s"
        if problem:
            m.fail_step, m.reason = s, f"step {s}: {problem}"
            return False
        stretch = stretch_per_spring(x, self.ij, self.rest)
        top = float(stretch.max()) if len(stretch) else 0.0
        m.max_stretch = max(m.max_stretch, top)
        t = (s + 1) * c.h
        if not (c.jump_at >= 0 and c.jump_at <= t + 1e-9 and t < c.jump_at + JUMP_WINDOW - 1e-9):
            m.peak_stretch = max(m.peak_stretch, top)
        if c.carrier_velocity is not None:
            relative = (x - self.prev) / c.h - c.carrier_velocity[s]
            m.max_speed = max(m.max_speed, float(np.max(np.linalg.norm(relative, axis=1))))
        m.p99_stretch = max(m.p99_stretch, p99_nearest_rank(stretch) if len(stretch) else 0.0)
        if s >= self.late_from:
            m.late_stretch.append((s, top))
        m.moved = max(m.moved, float(np.max(np.abs(x[self.free] - c.rest[self.free]), initial=0.0)))
        self.prev = x
        return True

    def finish(self) -> Metrics:
        m = self.m
        m.late_max_stretch = max((v for _, v in m.late_stretch), default=0.0)
        if m.fail_step < 0:
            late = [(s, v) for s, v in m.late_stretch if v >= LATE_MAX_STRETCH]
            if late:
                m.fail_step = late[0][0]
                m.reason = (f"step {late[0][0]}: stretch {late[0][1]:.3g} >= {LATE_MAX_STRETCH} "
                            f"in the last {self.late_window:g} s")
        return m
