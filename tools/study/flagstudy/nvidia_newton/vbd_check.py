"""Our vbd against NVIDIA Newton's VBD on the same model: an independent implementation of the same
method, as a check that can fail.

cloth_study exports a vbd check (nvidia_newton_export.cpp, ``exportVbdCheck``): a 9x9 flag of the
study's stiffness on the first half second of the demo's drive, with our ``vbd``'s positions at its
end at 10 and at 100 iterations. Both solvers take our springs' energy as it is (models.py), the
same masses, pins, gravity and step, and no damping, air or contact, so at enough iterations both
reach the same backward Euler step; at few, their orders of vertices differ (their colourings), and
so do their positions. The harness runs Newton's VBD (float32) as far at each iteration count and
writes the distance per particle to ``nvidia_newton_vbd_check.csv``; ``study.py check
--nvidia-newton`` holds the converged row to its bound (checks/run_outputs.py).
"""

from __future__ import annotations

import numpy as np

from flagstudy.nvidia_newton.case import Case
from flagstudy.nvidia_newton.run import set_pins
from flagstudy.nvidia_newton.solvers import parse_solver

COLUMNS = ["scene", "size", "iterations", "steps", "rms_m", "max_m", "moved_rms_m"]


def newton_vbd_positions(case: Case, iterations: int, steps: int) -> np.ndarray:
    """Newton's VBD at `iterations` on the case's model, after its first `steps` steps."""
    choice = parse_solver(f"vbd:iterations={iterations}")
    settings = choice.resolved(case)
    model = choice.spec.build(case, settings)
    solver = choice.spec.make(model, settings)
    state_in, state_out, control = model.state(), model.state(), model.control()
    previous = case.rest[case.pinned]
    for s in range(steps):
        target = case.pin_targets[s]
        set_pins(state_in, case, target, previous, case.h)
        state_in.clear_forces()
        solver.step(state_in, state_out, control, None, case.h)
        state_in, state_out = state_out, state_in
        previous = target
    return state_in.particle_q.numpy().astype(float)


def vbd_check_rows(case: Case) -> list[dict]:
    """One row per iteration count the case's vbd_check gives: the distance between the two."""
    rows = []
    for iterations, steps, ours in case.vbd_check or []:
        theirs = newton_vbd_positions(case, iterations, steps)
        d = np.linalg.norm(theirs - ours, axis=1)
        moved = np.linalg.norm(ours - case.rest, axis=1)
        rows.append({"scene": case.scene, "size": case.size, "iterations": iterations, "steps": steps,
                     "rms_m": f"{np.sqrt(np.mean(d * d)):.4g}", "max_m": f"{d.max():.4g}",
                     "moved_rms_m": f"{np.sqrt(np.mean(moved * moved)):.4g}"})
    return rows
