#!/usr/bin/python3
"""Plots a recording's frame time per phase: a stacked area per frame and the total.

    tools/plot_profile.py out/demo/profile.csv [out/demo/profile.png]

Reads the profile.csv the demo writes (frame_index, one column per phase in ms, frame).
Bullet's own zones ("bullet:*") are nested inside the "bullet" phase and are not stacked.
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    src = sys.argv[1]
    dst = sys.argv[2] if len(sys.argv) > 2 else src.rsplit(".", 1)[0] + ".png"
    with open(src, newline="") as f:
        rows = list(csv.reader(f))
    if len(rows) < 2:
        sys.exit(f"{src}: no frames")
    header, data = rows[0], [[float(x) for x in r] for r in rows[1:]]
    phases = [i for i, name in enumerate(header) if name not in ("frame_index", "frame") and not name.startswith("bullet:")]
    frames = [r[0] for r in data]
    fig, ax = plt.subplots(figsize=(11, 5), dpi=100)
    ax.stackplot(frames, *[[r[i] for r in data] for i in phases], labels=[header[i] for i in phases], alpha=0.85)
    total = header.index("frame")
    ax.plot(frames, [r[total] for r in data], color="black", linewidth=0.8, label="frame (wall)")
    ax.axhline(1000 / 60, color="red", linestyle="--", linewidth=0.8, label="16.7 ms (60 frames/s)")
    ax.set_xlabel("frame")
    ax.set_ylabel("milliseconds")
    ax.set_title(f"Frame time per phase: {src}")
    ax.legend(loc="upper left", fontsize=8, ncol=2)
    ax.set_xlim(frames[0], frames[-1])
    fig.tight_layout()
    fig.savefig(dst)
    print(dst)


if __name__ == "__main__":
    main()
