"""The solvers by name, their settings and labels, ``name[:key=value,...]`` as in the study.

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
  blew up (steps 1 and 168), 65 and 85 (auto) did not move at all. The harness notes every row
  with g dt^2 under the spacing, and a run whose free particles never move 1e-6 m is a failed row
  (metrics nan, stable 0, reason in the note).
  The label has the substep count used; ``xpbd:substeps=1`` is Newton's plain default.
- style3d: ``SolverStyle3D(model, config=SolverStyle3D.Config())``: iterations=10 non-linear and
  linear_iterations=10 PCG iterations (its defaults); one step per study step. Its velocity update
  keeps 0.998 of (x - x_prev)/dt (style3d/kernels.py ``update_velocity``), a damping of its own.
  Its PD matrix is constant (the rest-state stretch stiffness), so with a stiff membrane
  (k dt^2/m ~ 100) 10 non-linear iterations move the cloth much less than gravity would: it falls
  slowly, as if heavily damped (more ``iterations`` fix that; more ``linear_iterations`` do not).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

import numpy as np

from flagstudy.nvidia_newton.case import Case
from flagstudy.nvidia_newton.models import build_springs, build_style3d, make_style3d, make_vbd, make_xpbd

XPBD_MARGIN = 2.0  # auto substeps: alpha >= XPBD_MARGIN * (w_i + w_j)
XPBD_MAX_AUTO_SUBSTEPS = 128  # auto beyond this: the row says so instead of running for an hour


def auto_substeps(case: Case) -> int:
    """Fewest substeps with XPBD compliance alpha = 1/(k dt^2) >= XPBD_MARGIN (w_i + w_j) on every spring."""
    w = np.where(case.masses > 0, 1.0 / np.maximum(case.masses, 1e-300), 0.0)
    w[case.pinned] = 0.0
    rate = np.sqrt(XPBD_MARGIN * case.spring_k * (w[case.spring_ij[:, 0]] + w[case.spring_ij[:, 1]]))
    return max(1, int(math.ceil(case.h * float(rate.max()) - 1e-9)))


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
        "nvidia_newton_vbd", {"iterations": 10, "substeps": 1}, lambda c, s: build_springs(c, s, color=True),
        make_vbd,
    ),
    "xpbd": NewtonSolver(
        "nvidia_newton_xpbd", {"iterations": 2, "substeps": "auto"}, lambda c, s: build_springs(c, s, color=False),
        make_xpbd,
    ),
    "style3d": NewtonSolver(
        "nvidia_newton_style3d",
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
