"""NVIDIA Newton's solvers as a solver of the study (cloth_study's solver kind ``nvidia_newton``,
tools/study/cpp/nvidia_newton_kind.cpp): a process that steps the flag on request, so that the
front runs Newton's VBD, XPBD and Style3D on the same flags, paths, air, constraints and restarts
as every solver of the library, and judges them by the same reference.

Protocol (over stdin and stdout, little-endian; every message is answered):
- first, one line of JSON: ``{"solver": "vbd:iterations=10", "size": 33, "gravity": [..],
  "rest_positions": [[x, y, z], ..], "masses": [..], "springs": [[i, j, k, rest, kind], ..],
  "triangles": [[a, b, c], ..], "pinned": [..]}``; answered by one int32: 0 when the solver is
  built, else 1 followed by an error message (int32 length, UTF-8 bytes);
- then steps: an int32 1, a float64 h, then float64 arrays: the positions and the velocities
  (n x 3 each), every pin's target at the end of the step (p x 3, in ``pinned``'s order) and the
  external force (n x 3). Answered by an int32 0, the float64 milliseconds of Newton's step (the
  solver's step on the CPU device, timed as the harness times it: run.simulate) and the positions
  and velocities at the end of the step; or 1 and a message. An int32 0 ends the process.

A step sets Newton's state to the given one (so that the study's restarts, constraints and contact
reach it), the pins to their targets with velocity (target - now) / h, the external force as
``particle_f`` (our air and drag, as the harness applies them: run.py), and takes one Newton step of
h. Warp's progress prints are dropped (stdout carries the protocol alone); errors go to stderr.
"""

from __future__ import annotations

import json
import os
import struct
import sys
import time
from pathlib import Path

import numpy as np

from flagstudy.nvidia_newton.case import Case
from flagstudy.nvidia_newton.solvers import parse_solver


def case_of(message: dict) -> Case:
    """The flag of an opening message as the harness's Case (one step: the bridge is told each)."""
    springs = message["springs"]
    pinned = np.asarray(message["pinned"], dtype=np.int64)
    return Case(
        path=Path("<bridge>"),
        scene="bridge",
        size=int(message["size"]),
        stiffness=float(max((s[2] for s in springs), default=0.0)),
        h=float(message.get("h", 1.0 / 240)),
        steps=1,
        gravity=np.asarray(message["gravity"], dtype=float).reshape(3),
        rest=np.asarray(message["rest_positions"], dtype=float).reshape(-1, 3),
        masses=np.asarray(message["masses"], dtype=float),
        spring_ij=np.asarray([[s[0], s[1]] for s in springs], dtype=np.int64).reshape(-1, 2),
        spring_k=np.asarray([s[2] for s in springs], dtype=float),
        spring_rest=np.asarray([s[3] for s in springs], dtype=float),
        spring_kind=np.asarray([s[4] for s in springs], dtype=str),
        triangles=np.asarray(message["triangles"], dtype=np.int64).reshape(-1, 3),
        pinned=pinned,
        pin_targets=np.zeros((0, len(pinned), 3)),
    )


class Bridge:
    def __init__(self, message: dict):
        self.case = case_of(message)
        choice = parse_solver(message["solver"])
        self.settings = dict(choice.settings)
        if self.settings.get("substeps", 1) != 1:
            raise ValueError("the bridge takes one Newton step per call: give the substeps to the study's "
                             "configuration (its air and pins then move at each)")
        self.model = choice.spec.build(self.case, self.settings)
        self.solver = choice.spec.make(self.model, self.settings)
        self.state_in, self.state_out = self.model.state(), self.model.state()
        self.control = self.model.control()

    def step(self, h: float, x: np.ndarray, v: np.ndarray, pins: np.ndarray, force: np.ndarray):
        import warp as wp

        pinned = self.case.pinned
        v = v.copy()
        v[pinned] = (pins - x[pinned]) / h
        x = x.copy()
        x[pinned] = pins
        self.state_in.particle_q.assign(x.astype(np.float32))
        self.state_in.particle_qd.assign(v.astype(np.float32))
        self.state_in.clear_forces()
        self.state_in.particle_f.assign(force.astype(np.float32))
        wp.synchronize()
        t0 = time.perf_counter()
        self.solver.step(self.state_in, self.state_out, self.control, None, h)
        wp.synchronize()
        ms = (time.perf_counter() - t0) * 1e3
        self.state_in, self.state_out = self.state_out, self.state_in
        return ms, self.state_in.particle_q.numpy().astype(float), self.state_in.particle_qd.numpy().astype(float)


def read_exact(stream, count: int) -> bytes:
    data = stream.read(count)
    if len(data) != count:
        raise EOFError("the study closed the bridge")
    return data


def reply_error(out, text: str) -> None:
    raw = text.encode()
    out.write(struct.pack("<ii", 1, len(raw)) + raw)
    out.flush()


def serve(inp, out) -> int:
    try:
        bridge = Bridge(json.loads(inp.readline()))
    except Exception as e:  # the study shows the reason and stops the row
        reply_error(out, f"{type(e).__name__}: {e}")
        return 1
    out.write(struct.pack("<i", 0))
    out.flush()
    n, p = bridge.case.n, len(bridge.case.pinned)
    while True:
        (op,) = struct.unpack("<i", read_exact(inp, 4))
        if op == 0:
            return 0
        (h,) = struct.unpack("<d", read_exact(inp, 8))
        body = np.frombuffer(read_exact(inp, 8 * 3 * (3 * n + p)), dtype="<f8")
        x, v = body[: 3 * n].reshape(n, 3), body[3 * n: 6 * n].reshape(n, 3)
        pins, force = body[6 * n: 6 * n + 3 * p].reshape(p, 3), body[6 * n + 3 * p:].reshape(n, 3)
        try:
            ms, x1, v1 = bridge.step(h, x, v, pins, force)
        except Exception as e:
            reply_error(out, f"{type(e).__name__}: {e}")
            continue
        out.write(struct.pack("<id", 0, ms) + np.concatenate([x1.ravel(), v1.ravel()]).astype("<f8").tobytes())
        out.flush()


def main() -> int:
    protocol = os.fdopen(os.dup(1), "wb")
    quiet = os.open(os.devnull, os.O_WRONLY)
    os.dup2(quiet, 1)  # Warp's and Newton's progress prints (module loads): dropped; errors go to stderr
    sys.stdout = open(os.devnull, "w")
    try:
        return serve(sys.stdin.buffer, protocol)
    except EOFError:
        return 0


if __name__ == "__main__":
    sys.exit(main())
