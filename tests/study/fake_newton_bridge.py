#!/usr/bin/env python3
"""A stand-in for NVIDIA Newton's process (tools/study/flagstudy/nvidia_newton/bridge.py), for the
nvidia_newton kind's tests: the same protocol, and a step anyone can compute by hand, symplectic
Euler without springs (v' = v + h (g + f / m), x' = x + h v'; the pins on their targets with
velocity (target - x) / h). Its arguments (-m flagstudy...) are ignored. FAKE_NEWTON_FAIL=open or
=step makes it refuse there with a message; =exit makes it exit at the first step without a word.
"""
import json
import os
import struct
import sys
from array import array


def refuse(out, text):
    raw = text.encode()
    out.write(struct.pack("<ii", 1, len(raw)) + raw)
    out.flush()


def main():
    inp, out = sys.stdin.buffer, sys.stdout.buffer
    fail = os.environ.get("FAKE_NEWTON_FAIL", "")
    model = json.loads(inp.readline())
    if fail == "open":
        refuse(out, "ValueError: no such solver in this stand-in")
        return 1
    out.write(struct.pack("<i", 0))
    out.flush()
    masses, g, pinned = model["masses"], model["gravity"], model["pinned"]
    n, p = len(masses), len(pinned)
    while True:
        head = inp.read(4)
        if len(head) < 4 or struct.unpack("<i", head)[0] == 0:
            return 0
        if fail == "exit":
            return 3
        (h,) = struct.unpack("<d", inp.read(8))
        body = array("d")
        body.frombytes(inp.read(8 * 3 * (3 * n + p)))
        if fail == "step":
            refuse(out, "RuntimeError: the stand-in refuses to step")
            continue
        x, v, pins, f = body[: 3 * n], body[3 * n: 6 * n], body[6 * n: 6 * n + 3 * p], body[6 * n + 3 * p:]
        x0 = array("d", x)
        for i in range(n):
            for a in range(3):
                v[3 * i + a] += h * (g[a] + f[3 * i + a] / masses[i])
                x[3 * i + a] += h * v[3 * i + a]
        for k, i in enumerate(pinned):
            for a in range(3):
                v[3 * i + a] = (pins[3 * k + a] - x0[3 * i + a]) / h
                x[3 * i + a] = pins[3 * k + a]
        out.write(struct.pack("<id", 0, 1.5) + x.tobytes() + v.tobytes())
        out.flush()


if __name__ == "__main__":
    sys.exit(main())
