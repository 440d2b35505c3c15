"""One configuration or extreme case of the harness's input, as every module sees it: the flag's
particles, masses, springs, triangles, pinned particles and every pin's target at the end of every
step, and what an extreme case adds (start velocities, air, drag, the pole's jump and the carrier's
velocity). load.py reads it from cloth_study's JSON and checks it."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np


@dataclass
class Case:
    path: Path
    scene: str
    size: int
    stiffness: float
    h: float
    steps: int
    gravity: np.ndarray  # (3,)
    rest: np.ndarray  # (n, 3) start positions
    masses: np.ndarray  # (n,)
    spring_ij: np.ndarray  # (m, 2) int
    spring_k: np.ndarray  # (m,)
    spring_rest: np.ndarray  # (m,)
    spring_kind: np.ndarray  # (m,) str
    triangles: np.ndarray  # (t, 3) int
    pinned: np.ndarray  # (p,) int
    pin_targets: np.ndarray  # (steps, p, 3): target at the end of step s
    # Extreme cases (``"kind": "extreme"``) also give:
    kind: str = "config"
    velocities: np.ndarray | None = None  # (n, 3) start velocities (else at rest)
    air: dict | None = None  # our air model's parameters, applied as an explicit external force
    drag: float = 0.0  # linear drag rate, 1/s: f = -drag m v
    jump_at: float = -1.0  # s: when the pole jumps (teleport), else < 0
    carrier_velocity: np.ndarray | None = None  # (steps, 3): the carrier's velocity at the end of step s
    # A vbd check (``"kind": "vbd_check"``) gives our vbd's positions after its steps:
    # (iterations, steps, (n, 3) positions) each, for vbd_check.py.
    vbd_check: list | None = None

    @property
    def n(self) -> int:
        return len(self.masses)
