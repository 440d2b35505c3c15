#!/usr/bin/env python3
"""Newton's cloth solvers on the study's flag and pole motion, as rows of the study's CSV.

    tools/study/newton_study.py IN_DIR OUT_CSV [--solvers vbd,xpbd,style3d] [--max-size N] [--extreme-csv CSV]

IN_DIR holds the JSON files of ``cloth_study --export-newton DIR`` (one per configuration: the
particles, masses, springs, triangles, pinned particles and every pin's target at the end of every
step). Each file is run with each Newton solver (NVIDIA Newton 1.8.0 on Warp 1.19.0, CPU device,
pins from tools/study/requirements-newton.txt; install them in a venv, e.g. .venv-newton) and
gives one row of OUT_CSV, with the columns of the study's error_vs_runtime.csv less ``row``.

A solver is named as in the study, ``name[:key=value,...]``; ``--solvers`` takes a comma- (or
semicolon-) separated list, e.g. ``vbd,xpbd:iterations=10,substeps=4,style3d``. The row's
``solver`` column names every setting used, defaults included.

Stepping
--------
One study step of length h is ``substeps`` Newton steps of h/substeps (default 1, so a step of
Newton is a step of ours). Pinned particles have mass 0 and the ACTIVE flag cleared, so that no
solver integrates them (VBD: particle_vbd_kernels.forward_step skips inactive or zero inverse mass
particles; XPBD: solver.integrate_particles and xpbd.kernels.apply_particle_deltas skip inactive
ones; Style3D: kernels.deactivate_zero_mass_particles_kernel / init_step_kernel). Before each
Newton step the harness writes their position (the pin's target at the end of that step, linearly
interpolated between study steps when substeps > 1) and velocity ((target - previous) / dt) into
the input state; the springs and triangles see the pins there during the whole solve, as in our
backward Euler, and the pins land exactly on their targets (checked; a miss above 1e-6 m is noted).
No collisions, air or ground: no Contacts are passed (``contacts=None``), particle radii are 0 (so
XPBD's particle-particle contacts, which run when ``model.particle_max_radius > 0``, are off), VBD's
self contact stays at its default (off), and Style3D's collision object is removed
(``solver.collision = None``, its documented switch). Spring and triangle damping are 0.

Settings (defaults of Newton unless said):
- vbd: ``SolverVBD(model, iterations=10)`` (Newton's default iteration count). Newton's
  ``ModelBuilder.color()`` colours particles only by triangles, bending edges and tetrahedra, not
  springs, so a springs-only model would come out as one colour (no Gauss-Seidel ordering between
  neighbours). The harness colours the spring graph itself with ``newton.utils.color_graph`` (the
  same colouring routine) and passes it with ``ModelBuilder.set_coloring``.
- xpbd: ``SolverXPBD(model, iterations=2)``, Newton's default count (solver_xpbd.py,
  ``iterations: int = 2``), but not one step per study step: XPBD adds up the corrections of all
  springs of a particle in an iteration (Jacobi, no averaging, no relaxation for springs), and with
  particles of about 1 g and k = 1e4 N/m every spring is a nearly hard constraint (compliance
  alpha = 1/(k dt^2) = 5.8 at dt = 1/240 against w_i + w_j = 1.7e3..6.8e3 1/kg at 17x17), so the
  sum overshoots and the cloth explodes within a few steps (9x9 with iterations 1, 2 and 10: all
  blew up by step 5; more iterations do not help, substeps do). ``substeps=auto`` (xpbd's default)
  takes the fewest substeps with alpha >= 2 (w_i + w_j) on every spring, i.e.
  dt = h/substeps <= 1 / sqrt(2 k (w_i + w_j)) (pins have w = 0). Measured at 17x17: the study's
  hanging flag needs 35 (25 and 30 blow up late), its vehicle path 35, the 1 m sideways test 30;
  auto gives 43, 43 and 49 there. The other bound is float32: Newton's state is float32 and XPBD
  takes velocity as (x - x0)/dt, so once g dt^2 is below the float32 spacing of the positions
  (2.4e-7 m at |x| = 2 m) gravity's pull from rest is rounded away, in part, and wholly when it is
  under half a spacing (at 17x17, 60 substeps leave the hanging flag almost still). At 33x33 the
  two bounds cross, so XPBD has no working setting there: on the hanging flag 45 and 55 substeps
  blew up (steps 1 and 168), 65 and 85 (auto) did not move at all. The harness notes every row with g dt^2 under the spacing, and a run whose
  free particles never move 1e-6 m is a failed row (metrics nan, stable 0, reason in the note).
  The label has the substep count used; ``xpbd:substeps=1`` is Newton's plain default.
- style3d: ``SolverStyle3D(model, config=SolverStyle3D.Config())``: iterations=10 non-linear and
  linear_iterations=10 PCG iterations (its defaults); one step per study step. Its velocity update
  keeps 0.998 of (x - x_prev)/dt (style3d/kernels.py ``update_velocity``), a damping of its own.
  Its PD matrix is constant (the rest-state stretch stiffness), so with a stiff membrane
  (k dt^2/m ~ 100) 10 non-linear iterations move the cloth much less than gravity would: it falls
  slowly, as if heavily damped (more ``iterations`` fix that; more ``linear_iterations`` do not).

Stiffness matching
------------------
The JSON's springs are used as they are (i, j, k, rest, kind; bend springs have k/10).

XPBD and VBD offer springs, so both get our springs directly: ``ModelBuilder.add_spring(i, j,
ke=k, kd=0, control=0)`` with the rest length overwritten by ours
(``builder.spring_rest_length[s] = rest``; add_spring would take the distance in the start pose).
Same model, same units (N/m): XPBD uses ke as compliance alpha = 1/(ke dt^2)
(xpbd/kernels.py ``solve_springs``); VBD uses force ke (l0 - l)/l (x_i - x_j) and its Hessian
(vbd/particle_vbd_kernels.py ``evaluate_spring_force_and_hessian_both_vertices``). All spring kinds,
bend springs included, so XPBD and VBD solve exactly our energy (with their own iteration).

Style3D has no springs (SolverStyle3D.step evaluates only ``eval_stretch_kernel`` on triangles and
``eval_bend_kernel`` on edges; springs in the model are ignored), so its membrane is matched to our
springs. Its stretch energy per triangle (style3d/kernels.py ``eval_stretch_kernel``, after Baraff and
Witkin) is, with F = [Fu Fv] the deformation gradient in panel (rest) space and A the rest area,

    E = A * ( ku/2 (|Fu| - 1)^2 + kv/2 (|Fv| - 1)^2 + ks/2 (Fu . Fv)^2 ),

so ku, kv are stretch stiffness per unit width (E*t, N/m) along the panel axes u, v, and ks is the
shear stiffness (G*t, N/m). The parameters enter through
``style3d.add_cloth_mesh(..., tri_aniso_ke=wp.vec3(ku, kv, ks))`` -> custom attribute
``style3d:tri_aniso_ke`` -> ``eval_stretch_kernel`` (force) and
``PDMatrixBuilder.add_stretch_constraints`` (builder.py, the constant PD matrix
area * ((ku + ks) dFu dFu + (kv + ks) dFv dFv)). The panel is our rest grid: u along a row (away
from the pole), v along a column, u = c*dx, v = r*dy with dx, dy our structural rest lengths, so the
panel axes are the grid axes.

For a regular grid with structural springs k_s along u (spacing dx, rows dy apart) and along v, and
both diagonals of every cell as shear springs k_d, a uniform small strain e stores per cell
(area dx*dy) the energy sum k l^2 (n.e.n)^2 / 2 over its springs. Per unit area:

    structural along u: k_s dx^2 e_uu^2 / (2 dx dy)  -> E*t along u = ku = k_s * dx / dy
    structural along v:                              -> kv = k_s * dy / dx
    two diagonals, simple shear gamma = 2 e_uv:      -> G*t = ks = 2 k_d dx dy / (dx^2 + dy^2)

which is what the harness uses (``membrane=springs``, the default). On a square grid this is
ku = kv = k_s and ks = k_d: "E*t ~ k for the structural springs, shear ~ k for the shear springs".
It leaves out what the diagonals and bend springs add to the normal stiffness: the diagonals add
2 k_d dx^3 / ((dx^2 + dy^2) dy) to C_uuuu (and a Poisson-like C_uuvv = ks that Baraff-Witkin cannot
hold) and the bend springs (length 2 dx) 4 k_b dx / dy. ``style3d:membrane=full`` adds those two
terms to ku (and the like to kv), i.e. ku = C_uuuu of all our springs. For the study's 17x17 flag
(1.5 m x 1 m, dx = 0.09375, dy = 0.0625, k_s = k_d = 1e4, k_b = 1e3): springs: ku = 1.5e4,
kv = 6.7e3, ks = 9.2e3 N/m; full: ku = 4.2e4, kv = 1.3e4 N/m. Our springs are a stiffer membrane
in pure stretch than ``membrane=springs``, so Style3D's stretch is not comparable one-to-one.

Bending: a skip (bend) spring has no bending stiffness at first order about the flat state (a
curvature kappa shortens it by kappa^2 dx^3 / 3, an energy in kappa^4), so Style3D's bending
(Bergou et al. quadratic model, ``edge_aniso_ke``) is set to 0.

Metrics (from the particle positions after every study step, with OUR springs list)
-------------------------------------------------------------------------------------
- max_stretch: max over steps and over structural and shear springs of max(L/rest - 1, 0).
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
Numbers are printed as cloth_study prints them (%g; ms with 5 digits, stretch with 4) and the
solver column is quoted, so the rows sit next to error_vs_runtime.csv's (which has a ``row`` column
first). Stretch is measured over the structural springs, as cloth_study's part 1 does
(``cloth::measure(..., structuralOnly = true)``). One difference remains: cloth_study calls a run
unstable as soon as any step's stretch exceeds 1.0 (``StabilityLimits``); this harness looks at
the last 0.25 s instead.

Extreme cases
-------------
A JSON with ``"kind": "extreme"`` is one of cloth_study's extreme cases at one size (the demo's flag,
k = 1e3 / 1e2 / 5 N/m, on a carrier driven through the case; pins and the carrier's velocity per
240 Hz tick; its start velocities). It adds what the flag feels there: our air model (cloth/air.h,
pressure drag, skin friction and lift per triangle, evaluated here in numpy, and checked against the
library's force at one exported state of every case: check_air_twin) and the linear drag, both
evaluated at the state before each Newton step and passed as ``state.particle_f`` (the external force that VBD's forward step, XPBD's
integrate_particles and Style3D's init step read), i.e. explicit air. There is no pole collision.
Its row goes to the extreme CSV (``--extreme-csv``, default newton_extreme.csv beside OUT_CSV) with
cloth_study's extreme.csv metrics: peak_stretch leaves out the 0.25 s after the pole's jump,
late_max_stretch and the stability rule look at the last second, max_speed is relative to the
carrier, and ms_per_tick includes the numpy air (ours includes our air too). ``substeps=auto``
above XPBD_MAX_AUTO_SUBSTEPS (128) is not run; the row says why.

Warp compiles its kernels on first use (LLVM, CPU) and caches them in ~/.cache/warp/<version>. On
the study's 2-core machine (with another build running beside it), vbd, xpbd and style3d on a 9x9
and a 17x17 input of 240 steps took 74 s in all with an empty cache (about 55 s of it compiling
Newton's modules; xpbd's kernels alone take 20 s) and 20 to 27 s with the cache filled; the study's
17x17 and 33x33 flags (4 files of 360 steps, 12 rows) take about 85 s with the cache filled.
"""

from __future__ import annotations

import argparse
import contextlib
import io
import json
import math
import os
import sys
import tempfile
import time
import traceback
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

try:
    import numpy as np
except ImportError:
    sys.exit("newton_study: numpy is missing: pip install -r tools/study/requirements-newton.txt (in a venv)")

COLUMNS = [
    "scene", "size", "stiffness", "h", "family", "solver", "ms_per_step", "timing", "solve_error",
    "traj_error_be", "traj_error_fine", "max_stretch", "p99_stretch", "energy_growth", "stable",
    "fail_step", "note",
]
REQUIRED_FIELDS = [
    "scene", "size", "stiffness", "h", "steps", "gravity", "rest_positions", "masses", "springs",
    "triangles", "pinned", "pin_positions",
]
STRETCH_KINDS = ("structural",)  # as cloth_study part 1 (cloth::measure(..., structuralOnly = true))
MAX_DISTANCE = 100.0  # m from the first pin
MAX_SPEED = 1000.0  # m/s
LATE_WINDOW = 0.25  # s
LATE_MAX_STRETCH = 0.5
PIN_TOLERANCE = 1e-6  # m
FROZEN_TOLERANCE = 1e-6  # m: a run whose free particles never move farther did not simulate
XPBD_MARGIN = 2.0  # auto substeps: alpha >= XPBD_MARGIN * (w_i + w_j)
XPBD_MAX_AUTO_SUBSTEPS = 128  # auto beyond this: the row says so instead of running for an hour
EXTREME_COLUMNS = [
    "case", "size", "config", "solver", "stable", "fail_step", "ms_per_tick", "timing", "max_stretch",
    "peak_stretch", "p99_stretch", "late_max_stretch", "max_speed", "note",
]
EXTREME_LATE_WINDOW = 1.0  # s: cloth_study's extreme cases judge the last second
JUMP_WINDOW = 0.25  # s after a jump of the pole that peak_stretch leaves out (as cloth_study)


class InputError(Exception):
    pass


# ------------------------------------------------------------------------------------------------
# Input


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

    @property
    def n(self) -> int:
        return len(self.masses)


def load_case(path: Path) -> Case:
    try:
        data = json.loads(path.read_text())
    except (OSError, ValueError) as e:
        raise InputError(f"{path}: cannot read JSON: {e}") from e
    if not isinstance(data, dict):
        raise InputError(f"{path}: not a JSON object")
    for name in REQUIRED_FIELDS:
        if name not in data:
            raise InputError(f"{path}: missing field '{name}'")

    def read(name: str, convert: Callable):
        try:
            return convert(data[name])
        except (TypeError, ValueError, IndexError) as e:
            raise InputError(f"{path}: field '{name}' is malformed: {e}") from e
        except KeyError as e:  # a field that is an object without one of its keys
            raise InputError(f"{path}: field '{name}' is malformed: it has no key {e}") from e

    def points(v):
        return np.asarray(v, dtype=float).reshape(-1, 3)

    def indices(width: int):
        return lambda v: np.asarray(v, dtype=np.int64).reshape(-1, width)

    springs = read("springs", lambda v: [(int(i), int(j), float(k), float(r), str(kind)) for i, j, k, r, kind in v])
    case = Case(
        path=path,
        scene=read("scene", str),
        size=read("size", int),
        stiffness=read("stiffness", float),
        h=read("h", float),
        steps=read("steps", int),
        gravity=read("gravity", lambda v: np.asarray(v, dtype=float).reshape(3)),
        rest=read("rest_positions", points),
        masses=read("masses", lambda v: np.asarray(v, dtype=float).reshape(-1)),
        spring_ij=np.asarray([s[:2] for s in springs], dtype=np.int64).reshape(-1, 2),
        spring_k=np.asarray([s[2] for s in springs], dtype=float),
        spring_rest=np.asarray([s[3] for s in springs], dtype=float),
        spring_kind=np.asarray([s[4] for s in springs]),
        triangles=read("triangles", indices(3)),
        pinned=read("pinned", lambda v: np.asarray(v, dtype=np.int64).reshape(-1)),
        pin_targets=read("pin_positions", lambda v: np.asarray(v, dtype=float)),
        kind=str(data.get("kind", "config")),
    )
    if case.kind == "extreme":
        for name in ("velocities", "air", "drag", "jump_at", "carrier_velocity", "air_check"):
            if name not in data:
                raise InputError(f"{path}: missing field '{name}' (needed by an extreme case)")
        case.velocities = read("velocities", points)
        case.air = read("air", dict)
        case.drag = read("drag", float)
        case.jump_at = read("jump_at", float)
        case.carrier_velocity = read("carrier_velocity", points)
        check = read("air_check", lambda v: {k: points(v[k]) for k in ("positions", "velocities", "force")})
    elif case.kind != "config":
        raise InputError(f"{path}: field 'kind': '{case.kind}' is neither 'config' nor 'extreme'")
    check_case(case)
    if case.kind == "extreme":
        check_air_twin(case, check)
    return case


def check_air_twin(case: Case, check: dict) -> None:
    """external_forces (numpy) against the library's air and drag (cloth/air.h), which cloth_study
    exported at one state of the case: the two must agree to rounding, or the Newton rows would
    feel another air than ours."""
    for key in ("positions", "velocities", "force"):
        if check[key].shape != (case.n, 3):
            raise InputError(f"{case.path}: field 'air_check': '{key}' has shape {check[key].shape}, expected ({case.n}, 3)")
    ours = external_forces(case, check["positions"], check["velocities"])
    scale = float(np.abs(check["force"]).max())
    error = float(np.abs(ours - check["force"]).max())
    if not error <= 1e-9 * scale + 1e-15:
        raise InputError(f"{case.path}: field 'air_check': the harness's air and drag differ from cloth/air.h's by "
                         f"{error:.3g} N (largest force {scale:.3g} N); external_forces must follow the library")


def check_case(c: Case) -> None:
    def bad(field_name: str, why: str):
        raise InputError(f"{c.path}: field '{field_name}': {why}")

    n = c.n
    if len(c.rest) != n:
        bad("rest_positions", f"{len(c.rest)} positions for {n} masses")
    if n != c.size * c.size:
        bad("size", f"size {c.size} but {n} particles (expected size*size, row-major)")
    for name, idx in (("springs", c.spring_ij), ("triangles", c.triangles), ("pinned", c.pinned)):
        if idx.size and (idx.min() < 0 or idx.max() >= n):
            bad(name, "particle index out of range")
    if c.pin_targets.shape != (c.steps, len(c.pinned), 3):
        bad("pin_positions", f"shape {c.pin_targets.shape}, expected ({c.steps}, {len(c.pinned)}, 3)")
    if not len(c.pinned):
        bad("pinned", "no pinned particle")
    if c.velocities is not None and c.velocities.shape != (n, 3):
        bad("velocities", f"shape {c.velocities.shape}, expected ({n}, 3)")
    if c.carrier_velocity is not None and c.carrier_velocity.shape != (c.steps, 3):
        bad("carrier_velocity", f"shape {c.carrier_velocity.shape}, expected ({c.steps}, 3)")
    if c.air is not None:
        for key in ("enabled", "wind", "density", "drag_coefficient", "lift_coefficient", "friction_coefficient"):
            if key not in c.air:
                bad("air", f"missing '{key}'")
    if c.h <= 0 or c.steps <= 0:
        bad("h" if c.h <= 0 else "steps", "must be positive")
    if (c.spring_rest <= 0).any():
        bad("springs", "a rest length is not positive")
    if (c.masses < 0).any():
        bad("masses", "a mass is negative")
    unknown = set(c.spring_kind) - {"structural", "shear", "bend"}
    if unknown:
        bad("springs", f"unknown spring kind(s) {sorted(unknown)}")


# ------------------------------------------------------------------------------------------------
# Metrics


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
                m.reason = f"step {late[0][0]}: stretch {late[0][1]:.3g} >= {LATE_MAX_STRETCH} in the last {self.late_window:g} s"
        return m


# ------------------------------------------------------------------------------------------------
# Newton models and solvers (one table, SOLVERS, below)


def grid_spacing(case: Case) -> tuple[float, float]:
    """Rest spacing along a row (u, away from the pole) and along a column (v)."""
    n = case.size
    ij = np.sort(case.spring_ij, axis=1)
    structural = case.spring_kind == "structural"
    du = case.spring_rest[structural & (ij[:, 1] - ij[:, 0] == 1)]
    dv = case.spring_rest[structural & (ij[:, 1] - ij[:, 0] == n)]
    if not len(du) or not len(dv):
        raise ValueError("no structural springs along the grid's rows and columns")
    return float(np.median(du)), float(np.median(dv))


def mean_k(case: Case, kind: str) -> float:
    k = case.spring_k[case.spring_kind == kind]
    return float(k.mean()) if len(k) else 0.0


def membrane_stiffness(case: Case, mode: str) -> tuple[float, float, float]:
    """(ku, kv, ks) of Style3D's membrane matched to our springs (see the module docstring)."""
    dx, dy = grid_spacing(case)
    k_s, k_d, k_b = mean_k(case, "structural"), mean_k(case, "shear"), mean_k(case, "bend")
    diag2 = dx * dx + dy * dy
    ku, kv = k_s * dx / dy, k_s * dy / dx
    ks = 2.0 * k_d * dx * dy / diag2
    if mode == "full":
        ku += 2.0 * k_d * dx**3 / (diag2 * dy) + 4.0 * k_b * dx / dy
        kv += 2.0 * k_d * dy**3 / (diag2 * dx) + 4.0 * k_b * dy / dx
    elif mode != "springs":
        raise ValueError(f"membrane must be 'springs' or 'full', not '{mode}'")
    return ku, kv, ks


def new_builder(case: Case):
    import newton

    return newton.ModelBuilder(up_axis=newton.Axis.Y, gravity=tuple(case.gravity))


def make_kinematic(builder, case: Case) -> None:
    """Pinned particles: mass 0 and not ACTIVE, so that no solver moves them."""
    import newton

    for p in case.pinned:
        builder.particle_mass[p] = 0.0
        builder.particle_flags[p] = int(builder.particle_flags[p]) & ~int(newton.ParticleFlags.ACTIVE)


def build_springs(case: Case, settings: dict, color: bool):
    """Particles and our springs as they are (XPBD, VBD)."""
    import warp as wp

    import newton.utils

    b = new_builder(case)
    for x, m in zip(case.rest, case.masses):
        b.add_particle(pos=wp.vec3(*x), vel=wp.vec3(0.0, 0.0, 0.0), mass=float(m), radius=0.0)
    for (i, j), k, rest in zip(case.spring_ij, case.spring_k, case.spring_rest):
        b.add_spring(int(i), int(j), ke=float(k), kd=0.0, control=0.0)
        b.spring_rest_length[-1] = float(rest)
    make_kinematic(b, case)
    if color:
        edges = wp.array(np.sort(case.spring_ij, axis=1).astype(np.int32), dtype=int, device="cpu")
        b.set_coloring(newton.utils.color_graph(case.n, edges))
    return b.finalize(device="cpu")


def panel_coordinates(case: Case) -> np.ndarray:
    """Our rest grid in 2D: u = column * dx, v = row * dy (row-major, column 0 at the pole)."""
    dx, dy = grid_spacing(case)
    rows, cols = np.divmod(np.arange(case.n), case.size)
    return np.stack([cols * dx, rows * dy], axis=1)


def build_style3d(case: Case, settings: dict):
    import warp as wp

    import newton
    from newton.solvers import style3d

    b = new_builder(case)
    newton.solvers.SolverStyle3D.register_custom_attributes(b)
    panel = panel_coordinates(case)
    tris = case.triangles.copy()
    p0, p1, p2 = panel[tris[:, 0]], panel[tris[:, 1]], panel[tris[:, 2]]
    signed = (p1 - p0)[:, 0] * (p2 - p0)[:, 1] - (p1 - p0)[:, 1] * (p2 - p0)[:, 0]
    tris[signed < 0] = tris[signed < 0][:, [0, 2, 1]]  # Style3D drops triangles of negative panel area
    ku, kv, ks = membrane_stiffness(case, settings["membrane"])
    style3d.add_cloth_mesh(
        b,
        pos=wp.vec3(0.0, 0.0, 0.0),
        rot=wp.quat_identity(),
        vel=wp.vec3(0.0, 0.0, 0.0),
        vertices=case.rest.tolist(),
        indices=tris.reshape(-1).tolist(),
        density=0.0,
        panel_verts=panel.tolist(),
        tri_aniso_ke=wp.vec3(ku, kv, ks),
        edge_aniso_ke=wp.vec3(0.0, 0.0, 0.0),
        tri_kd=0.0,
        edge_kd=0.0,
        particle_radius=0.0,
    )
    if len(b.tri_indices) != len(tris):
        raise ValueError(f"Style3D kept {len(b.tri_indices)} of {len(tris)} triangles (degenerate panel triangles)")
    b.particle_mass[:] = case.masses.tolist()
    make_kinematic(b, case)
    return b.finalize(device="cpu")


def make_vbd(model, settings: dict):
    import newton

    return newton.solvers.SolverVBD(model, iterations=settings["iterations"])


def make_xpbd(model, settings: dict):
    import newton

    return newton.solvers.SolverXPBD(model, iterations=settings["iterations"])


def make_style3d(model, settings: dict):
    import newton

    solver_cls = newton.solvers.SolverStyle3D
    config = solver_cls.Config(iterations=settings["iterations"], linear_iterations=settings["linear_iterations"])
    solver = solver_cls(model, config=config)
    solver.collision = None  # no collisions (the solver's documented switch)
    return solver


def auto_substeps(case: Case) -> int:
    """Fewest substeps with XPBD compliance alpha = 1/(k dt^2) >= XPBD_MARGIN (w_i + w_j) on every spring."""
    w = np.where(case.masses > 0, 1.0 / np.maximum(case.masses, 1e-300), 0.0)
    w[case.pinned] = 0.0
    rate = np.sqrt(XPBD_MARGIN * case.spring_k * (w[case.spring_ij[:, 0]] + w[case.spring_ij[:, 1]]))
    return max(1, int(math.ceil(case.h * float(rate.max()) - 1e-9)))


def float32_note(case: Case, dt: float) -> str:
    """A note when one step's fall under gravity from rest, g dt^2, is below float32's spacing at the positions."""
    fall = float(np.linalg.norm(case.gravity)) * dt * dt
    reach = max(float(np.abs(case.rest).max()), float(np.abs(case.pin_targets).max()))
    spacing = float(np.spacing(np.float32(reach)))
    if fall >= spacing:
        return ""
    return (f"g*dt^2 = {fall:.2g} m is below the float32 spacing of the positions ({spacing:.2g} m): "
            "Newton's float32 state rounds part or all of gravity's pull away")


def positive_int(value: str):
    v = int(value)
    if v < 1:
        raise ValueError("must be at least 1")
    return v


def substeps_value(value: str):
    return "auto" if value == "auto" else positive_int(value)


def membrane_value(value: str):
    if value not in ("springs", "full"):
        raise ValueError("must be springs or full")
    return value


PARAMETERS = {  # how each solver setting is read from a spec
    "iterations": positive_int,
    "linear_iterations": positive_int,
    "substeps": substeps_value,
    "membrane": membrane_value,
}


@dataclass(frozen=True)
class NewtonSolver:
    family: str
    defaults: dict  # every setting, in label order (substeps belongs to the harness)
    build: Callable  # (case, settings) -> Model
    make: Callable  # (model, settings) -> solver


SOLVERS = {
    "vbd": NewtonSolver(
        "newton_vbd", {"iterations": 10, "substeps": 1}, lambda c, s: build_springs(c, s, color=True), make_vbd
    ),
    "xpbd": NewtonSolver(
        "newton_xpbd", {"iterations": 2, "substeps": "auto"}, lambda c, s: build_springs(c, s, color=False), make_xpbd
    ),
    "style3d": NewtonSolver(
        "newton_style3d",
        {"iterations": 10, "linear_iterations": 10, "membrane": "springs", "substeps": 1},
        build_style3d,
        make_style3d,
    ),
}


@dataclass
class SolverChoice:
    name: str
    spec: NewtonSolver
    settings: dict  # as asked (substeps may be "auto")

    def resolved(self, case: Case) -> dict:
        settings = dict(self.settings)
        if settings["substeps"] == "auto":
            settings["substeps"] = auto_substeps(case)
            if settings["substeps"] > XPBD_MAX_AUTO_SUBSTEPS:
                raise ValueError(
                    f"cannot run: stable XPBD needs {settings['substeps']} substeps per step here (alpha >= "
                    f"{XPBD_MARGIN:g} (w_i + w_j)), over the harness's cap of {XPBD_MAX_AUTO_SUBSTEPS}")
        return settings

    def label(self, settings: dict) -> str:
        return self.name + ":" + ",".join(f"{k}={v}" for k, v in settings.items())


def parse_solver(text: str) -> SolverChoice:
    name, _, rest = text.partition(":")
    if name not in SOLVERS:
        raise ValueError(f"unknown solver '{name}' (known: {', '.join(SOLVERS)})")
    spec = SOLVERS[name]
    settings = dict(spec.defaults)
    for item in filter(None, rest.split(",")):
        key, eq, value = item.partition("=")
        if not eq:
            raise ValueError(f"solver '{name}': parameter '{item}' is not key=value")
        if key not in settings:
            raise ValueError(f"solver '{name}' has no parameter '{key}' (known: {', '.join(settings)})")
        try:
            settings[key] = PARAMETERS[key](value)
        except ValueError as e:
            raise ValueError(f"solver '{name}' parameter {key} has a bad value '{value}': {e}") from None
    return SolverChoice(name, spec, settings)


def split_solver_list(text: str) -> list[str]:
    """'vbd,xpbd:iterations=10,substeps=2;style3d' -> ['vbd', 'xpbd:iterations=10,substeps=2', 'style3d']."""
    specs: list[str] = []
    for part in text.replace(";", ",").split(","):
        part = part.strip()
        if not part:
            continue
        if "=" in part and ":" not in part and specs:
            specs[-1] += "," + part  # a further key=value of the previous solver
        else:
            specs.append(part)
    return specs


# ------------------------------------------------------------------------------------------------
# Running


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


def set_pins(state, case: Case, target: np.ndarray, previous: np.ndarray, dt: float) -> None:
    q = state.particle_q.numpy()  # on the CPU device: a view of the Warp array
    qd = state.particle_qd.numpy()
    q[case.pinned] = target
    qd[case.pinned] = (target - previous) / dt
    state.particle_q.assign(q)
    state.particle_qd.assign(qd)


def simulate(case: Case, choice: SolverChoice, settings: dict) -> tuple[Metrics, float, str]:
    """Run one configuration with one solver: (metrics, ms_per_step, note)."""
    import warp as wp

    model = choice.spec.build(case, settings)
    solver = choice.spec.make(model, settings)
    state_in, state_out, control = model.state(), model.state(), model.control()
    substeps = settings["substeps"]
    dt = case.h / substeps
    monitor = Monitor(case)
    if case.velocities is not None:
        state_in.particle_qd.assign(case.velocities.astype(np.float32))
    forced = case.kind == "extreme"
    pins_prev = case.rest[case.pinned]
    step_ms, pin_miss = [], 0.0
    for s in range(case.steps):
        target = case.pin_targets[s]
        wp.synchronize()
        t0 = time.perf_counter()
        for sub in range(substeps):
            before = pins_prev + (target - pins_prev) * (sub / substeps)
            after = pins_prev + (target - pins_prev) * ((sub + 1) / substeps)
            set_pins(state_in, case, after, before, dt)
            state_in.clear_forces()
            if forced:  # air and drag, explicit (Newton's solvers read particle_f as external force)
                x_now = state_in.particle_q.numpy().astype(float)
                v_now = state_in.particle_qd.numpy().astype(float)
                state_in.particle_f.assign(external_forces(case, x_now, v_now).astype(np.float32))
            solver.step(state_in, state_out, control, None, dt)
            state_in, state_out = state_out, state_in
        wp.synchronize()
        step_ms.append((time.perf_counter() - t0) * 1e3)
        x = state_in.particle_q.numpy().astype(float)
        pin_miss = max(pin_miss, float(np.max(np.abs(x[case.pinned] - target))))
        pins_prev = target
        if not monitor.step(s, x):
            break
    metrics = monitor.finish()
    notes = [metrics.reason] if metrics.reason else []
    if pin_miss > PIN_TOLERANCE:
        notes.append(f"pins missed their targets by up to {pin_miss:.3g} m")
    notes.append(float32_note(case, dt))
    return metrics, float(np.median(step_ms)), "; ".join(filter(None, notes))


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


def make_extreme_row(case: Case, choice: SolverChoice, label: str, metrics: Metrics | None, ms: float, note: str) -> dict:
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


def run_one(case: Case, choice: SolverChoice) -> dict:
    label = choice.label(choice.settings)
    make_row_for = make_extreme_row if case.kind == "extreme" else make_row
    try:
        settings = choice.resolved(case)
        label = choice.label(settings)
        with contextlib.redirect_stdout(io.StringIO()):  # Warp's timers (e.g. Style3D precompute) print here
            metrics, ms, note = simulate(case, choice, settings)
        if metrics.fail_step < 0 and metrics.moved < FROZEN_TOLERANCE:  # ran, but simulated nothing
            frozen = f"failed: no free particle moved {FROZEN_TOLERANCE:g} m in {case.steps} steps"
            return make_row_for(case, choice, label, None, math.nan, "; ".join(filter(None, [frozen, note])))
        return make_row_for(case, choice, label, metrics, ms, note)
    except Exception as e:  # a solver that cannot run this configuration still gives its row
        traceback.print_exc(file=sys.stderr)
        reason = f"{type(e).__name__}: {e}".replace("\n", " ")
        return make_row_for(case, choice, label, None, math.nan, f"failed: {reason}")


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


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("in_dir", type=Path, help="directory of cloth_study --export-newton JSON files")
    ap.add_argument("out_csv", type=Path)
    ap.add_argument("--solvers", default="vbd,xpbd,style3d",
                    help="comma-separated solver specs, name[:key=value,...] (default: %(default)s)")
    ap.add_argument("--max-size", type=int, default=None, help="skip configurations with size > N")
    ap.add_argument("--extreme-csv", type=Path, default=None,
                    help="where the extreme cases' rows go (default: newton_extreme.csv beside OUT_CSV)")
    args = ap.parse_args(argv)

    def fail(msg: str) -> int:
        print(f"newton_study: {msg}", file=sys.stderr)
        return 2

    try:
        choices = [parse_solver(s) for s in split_solver_list(args.solvers)]
    except ValueError as e:
        return fail(str(e))
    if not choices:
        return fail("--solvers names no solver")
    if not args.in_dir.is_dir():
        return fail(f"{args.in_dir} is not a directory")
    paths = sorted(args.in_dir.glob("*.json"))
    if not paths:
        return fail(f"no *.json in {args.in_dir}")
    try:
        cases = [load_case(p) for p in paths]
    except InputError as e:
        return fail(str(e))
    if args.max_size is not None:
        cases = [c for c in cases if c.size <= args.max_size]
        if not cases:
            return fail(f"no configuration in {args.in_dir} has size <= {args.max_size}")

    try:
        import warp as wp

        import newton  # noqa: F401
    except ImportError as e:
        return fail(f"{e}: pip install -r tools/study/requirements-newton.txt (in a venv)")
    wp.config.log_level = wp.LOG_WARNING  # no banner, no per-module compile lines
    wp.init()
    wp.set_device("cpu")

    rows, extreme_rows = [], []
    total = len(cases) * len(choices)
    for case in cases:
        for choice in choices:
            t0 = time.perf_counter()
            with wp.ScopedDevice("cpu"):
                row = run_one(case, choice)
            (extreme_rows if case.kind == "extreme" else rows).append(row)
            ms = row.get("ms_per_step", row.get("ms_per_tick"))
            print(
                f"[{len(rows) + len(extreme_rows)}/{total}] {case.path.name} {row['solver']}: ms/step {ms} "
                f"max_stretch {row['max_stretch']} p99 {row['p99_stretch']} stable {row['stable']} "
                f"fail_step {row['fail_step']} ({time.perf_counter() - t0:.1f} s){' - ' + row['note'] if row['note'] else ''}",
                file=sys.stderr,
                flush=True,
            )
    write_csv(args.out_csv, rows)
    print(f"newton_study: {len(rows)} rows written to {args.out_csv}", file=sys.stderr)
    if any(c.kind == "extreme" for c in cases):
        extreme_csv = args.extreme_csv or args.out_csv.with_name("newton_extreme.csv")
        write_csv(extreme_csv, extreme_rows, EXTREME_COLUMNS)
        print(f"newton_study: {len(extreme_rows)} extreme-case rows written to {extreme_csv}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
