"""The harness's input: one JSON file of ``cloth_study --export-nvidia-newton DIR`` per configuration
(the particles, masses, springs, triangles, pinned particles and every pin's target at the end of every
step) or extreme case (also its start velocities, air, drag, the pole's jump and the carrier's
velocity), read into a Case and checked."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Callable

import numpy as np

from flagstudy.nvidia_newton.case import Case
from flagstudy.nvidia_newton.extreme import external_forces

REQUIRED_FIELDS = [
    "scene", "size", "stiffness", "h", "steps", "gravity", "rest_positions", "masses", "springs",
    "triangles", "pinned", "pin_positions",
]


class InputError(Exception):
    pass


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
    elif case.kind not in ("config", "vbd_check"):
        raise InputError(f"{path}: field 'kind': '{case.kind}' is not 'config', 'extreme' or 'vbd_check'")
    elif case.kind == "vbd_check":
        if "vbd_check" not in data:
            raise InputError(f"{path}: missing field 'vbd_check' (needed by a vbd check)")
        case.vbd_check = read("vbd_check", lambda v: [(int(r["iterations"]), int(r["steps"]), points(r["positions"]))
                                                     for r in v])
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
            raise InputError(f"{case.path}: field 'air_check': '{key}' has shape {check[key].shape}, "
                             f"expected ({case.n}, 3)")
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
    for iterations, steps, positions in c.vbd_check or []:
        if iterations < 1 or not 0 < steps <= c.steps:
            bad("vbd_check", f"iterations {iterations} and steps {steps} (at least 1, and 1 to {c.steps})")
        if positions.shape != (n, 3):
            bad("vbd_check", f"positions of shape {positions.shape}, expected ({n}, 3)")
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
