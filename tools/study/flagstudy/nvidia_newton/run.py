"""One configuration run with one solver: its row.

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
"""

from __future__ import annotations

import contextlib
import io
import math
import sys
import time
import traceback

import numpy as np

from flagstudy.nvidia_newton.case import Case
from flagstudy.nvidia_newton.extreme import external_forces, make_extreme_row
from flagstudy.nvidia_newton.metrics import Metrics, Monitor
from flagstudy.nvidia_newton.output import make_row
from flagstudy.nvidia_newton.solvers import SolverChoice

PIN_TOLERANCE = 1e-6  # m
FROZEN_TOLERANCE = 1e-6  # m: a run whose free particles never move farther did not simulate


def set_pins(state, case: Case, target: np.ndarray, previous: np.ndarray, dt: float) -> None:
    q = state.particle_q.numpy()  # on the CPU device: a view of the Warp array
    qd = state.particle_qd.numpy()
    q[case.pinned] = target
    qd[case.pinned] = (target - previous) / dt
    state.particle_q.assign(q)
    state.particle_qd.assign(qd)


def float32_note(case: Case, dt: float) -> str:
    """A note when one step's fall under gravity from rest, g dt^2, is below float32's spacing at the positions."""
    fall = float(np.linalg.norm(case.gravity)) * dt * dt
    reach = max(float(np.abs(case.rest).max()), float(np.abs(case.pin_targets).max()))
    spacing = float(np.spacing(np.float32(reach)))
    if fall >= spacing:
        return ""
    return (f"g*dt^2 = {fall:.2g} m is below the float32 spacing of the positions ({spacing:.2g} m): "
            "Newton's float32 state rounds part or all of gravity's pull away")


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
