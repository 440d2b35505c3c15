"""Plots the front: each configuration's error against the true motion against its cost.

    tools/study/study.py plot-front out/study  (reads front.csv, writes front.png)

One panel per flag and path (flags as columns), log-log: x = cloth ms per 60 Hz frame, y = the
trajectory error against the flag's reference in % of the flag's width. A point per configuration
and size with a trajectory error, labelled with its name: filled when within every bound (misses
empty), hollow when it misses one; an unstable row is an x at the panel's top edge at its cost.
The step line is each size's Pareto front: the configurations within every bound (references
aside) that no other such configuration beats on both cost and error. The dotted line is the
reference's cost; the ring marks the flag as its scene ships (config `shipped`); a triangle marks
NVIDIA Newton's solvers (timing warp_cpu: their cost on Warp's CPU device).
"""
import csv
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402

from flagstudy.front_table import FLAGS, PATHS, num  # noqa: E402  (the flags, paths and numbers of the table)

SIZE_STYLE = {"33": ("tab:blue", "o"), "65": ("tab:orange", "s")}
OTHER_STYLE = ("tab:green", "D")  # a size the study does not run by default (--front-sizes)
PEER_TIMING, PEER_MARKER = "warp_cpu", "^"  # NVIDIA Newton's solvers: their cost on Warp's CPU device


def style(size):
    """A size's colour and marker."""
    return SIZE_STYLE.get(size, OTHER_STYLE)


def ordered(values, order):
    """The values in the given order, any others after them in the order they first appear."""
    seen = list(dict.fromkeys(values))
    return [v for v in order if v in seen] + [v for v in seen if v not in order]


def pareto(points):
    """The points (cost, error) no other beats on both, by rising cost."""
    front, best = [], math.inf
    for ms, err in sorted(points):
        if err < best:
            front.append((ms, err))
            best = err
    return front


def draw_points(ax, rows):
    """Each stable row with a trajectory error as a point, the shipped one ringed; returns the
    points' labels (placed once the layout is known) and the points within every bound
    (references aside) per size, for the front."""
    labels, inside = [], {}
    for r in rows:
        ms, err = num(r["ms_per_frame"]), num(r["traj_error"])
        if r["stable"] != "1" or ms is None or err is None or err <= 0:
            continue
        y = 100 * err
        color, marker = style(r["size"])
        if r.get("timing") == PEER_TIMING:
            marker = PEER_MARKER
        ok = r["misses"] == ""
        ax.scatter(ms, y, s=30, marker=marker, zorder=3, linewidths=1.2, edgecolors=color,
                   facecolors=color if ok else "none")
        if r["config"] == "shipped":
            ax.scatter(ms, y, s=190, marker="o", zorder=4, facecolors="none", edgecolors="black", linewidths=1.5)
        labels.append((ms, y, r["config"]))
        if ok and not r["config"].startswith("reference"):
            inside.setdefault(r["size"], []).append((ms, y))
    return labels, inside


def overlaps(box, boxes):
    """Whether the box (x0, y0, x1, y1) overlaps any of the boxes."""
    return any(box[0] < b[2] and b[0] < box[2] and box[1] < b[3] and b[1] < box[3] for b in boxes)


def place_labels(ax, labels):
    """Each point's name beside it, at the first of a few offsets where it stays inside the panel and
    overlaps no point and no name placed before (estimated in pixels at 100 dpi); the first offset
    if none is free."""
    scale, height = 100 / 72, 9
    spots = [(4, 2, "left"), (4, -8, "left"), (4, 9, "left"), (-4, 2, "right"), (-4, -8, "right"),
             (4, -15, "left"), (4, 16, "left"), (-4, 9, "right")]
    pixels = [ax.transData.transform((ms, y)) for ms, y, _ in labels]
    taken = [(px - 5, py - 5, px + 5, py + 5) for px, py in pixels]
    for (ms, y, name), (px, py) in zip(labels, pixels):
        shipped = name == "shipped"
        if shipped:
            taken.append((px - 10, py - 10, px + 10, py + 10))
        width = 4.6 * len(name) + (2 if shipped else 0)
        choice = spots[0]
        for dx, dy, ha in ([(8, -11, "left")] if shipped else []) + spots:
            x0 = px + dx * scale - (width if ha == "right" else 0)
            box = (x0, py + dy * scale, x0 + width, py + dy * scale + height)
            if ax.bbox.x0 <= box[0] and box[2] <= ax.bbox.x1 and not overlaps(box, taken):
                choice = (dx, dy, ha)
                taken.append(box)
                break
        ax.annotate(name, (ms, y), xytext=choice[:2], textcoords="offset points", ha=choice[2], fontsize=6.5,
                    color="black" if shipped else "0.25", fontweight="bold" if shipped else "normal")


def draw_unstable(ax, rows):
    """Each unstable row as an x at the panel's top edge at its cost, labelled downwards."""
    top = ax.get_xaxis_transform()  # x in data, y in axes coordinates
    for r in rows:
        ms = num(r["ms_per_frame"])
        if r["stable"] == "1" or ms is None:
            continue
        color, _ = style(r["size"])
        ax.plot([ms], [0.97], marker="x", color=color, markersize=8, mew=2, transform=top, zorder=4, clip_on=False)
        if r["config"] == "shipped":
            ax.plot([ms], [0.97], marker="o", color="black", markersize=13, mfc="none", mew=1.5, transform=top,
                    clip_on=False)
        ax.text(ms, 0.94, r["config"], transform=top, rotation=90, va="top", ha="center", fontsize=6, color=color)


def draw_fronts_and_references(ax, rows, inside):
    """Each size's Pareto front as a step line (the least error for a cost up to x, on to the
    panel's right edge) and its reference's cost as a dotted line; after the limits are set."""
    right = ax.get_xlim()[1]
    for size, points in inside.items():
        front = pareto(points)
        xs, ys = [p[0] for p in front] + [right], [p[1] for p in front] + [front[-1][1]]
        ax.step(xs, ys, where="post", color=style(size)[0], lw=1.4, alpha=0.8, zorder=2)
    for r in rows:
        ms = num(r["ms_per_frame"])
        if r["config"] == "reference" and ms is not None:
            ax.axvline(ms, color=style(r["size"])[0], ls=":", lw=1.5, zorder=1)


def note_missing(ax, rows):
    """How many stable configurations have no trajectory error, per size (e.g. above
    --trajectories-up-to), and the shipped row's verdict when it has no point."""
    lines = []
    for size in sorted({r["size"] for r in rows}, key=int):
        at = [r for r in rows if r["size"] == size and r["stable"] == "1" and r["config"] != "reference"]
        missing = [r for r in at if num(r["traj_error"]) is None]
        if missing:
            lines.append(f"{size}x{size}: {len(missing)} of {len(at)} stable configurations without a trajectory error")
        for r in missing:
            if r["config"] == "shipped":
                lines.append(f"  shipped at {size}x{size}: {r['misses'] or 'within bounds'}, "
                             f"{num(r['ms_per_frame']) or 0:.3g} ms/frame")
    if lines:
        ax.text(0.01, 0.01, "\n".join(lines), transform=ax.transAxes, fontsize=7, va="bottom", ha="left",
                bbox=dict(boxstyle="round", fc="white", ec="0.7", alpha=0.85))


def draw_panel(ax, rows, title):
    """One flag on one path: points, unstable rows, fronts, the reference's cost and the notes;
    returns the points' labels."""
    labels, inside = draw_points(ax, rows)
    ax.set_xscale("log")
    ax.set_yscale("log")
    costs = [num(r["ms_per_frame"]) for r in rows if num(r["ms_per_frame"]) is not None]
    errors = [100 * num(r["traj_error"]) for r in rows if (num(r["traj_error"]) or 0) > 0 and r["stable"] == "1"]
    if costs:
        ax.set_xlim(min(costs) / 1.6, max(costs) * 2.2)
    # room above the points for the unstable rows' labels, below for the notes
    ax.set_ylim(min(errors) / 3 if errors else 0.1, max(errors) * 8 if errors else 100)
    draw_fronts_and_references(ax, rows, inside)
    draw_unstable(ax, rows)
    note_missing(ax, rows)
    ax.set_title(title, fontsize=11)
    ax.grid(True, which="major", alpha=0.3)
    ax.grid(True, which="minor", alpha=0.1)
    ax.tick_params(labelsize=8)
    return labels


def legend(fig, sizes):
    """One legend for every panel: the sizes' markers and what filled, hollow, x, ring and lines mean."""
    handles = [Line2D([], [], ls="", marker=style(s)[1], color=style(s)[0], label=f"{s}x{s}") for s in sizes]
    handles += [
        Line2D([], [], ls="", marker="o", color="0.3", label="within every bound"),
        Line2D([], [], ls="", marker="o", color="0.3", mfc="none", label="misses a bound (p99, peak or energy)"),
        Line2D([], [], ls="", marker="x", color="0.3", mew=2, label="unstable (at its cost, top edge)"),
        Line2D([], [], ls="", marker="o", color="black", mfc="none", markersize=12, label="shipped"),
        Line2D([], [], ls="", marker=PEER_MARKER, color="0.3", label="NVIDIA Newton (Warp CPU)"),
        Line2D([], [], color="0.3", lw=1.4, label="Pareto front within every bound"),
        Line2D([], [], color="0.3", ls=":", lw=1.5, label="reference's cost"),
    ]
    fig.legend(handles=handles, loc="upper center", ncol=len(handles), fontsize=9, frameon=False,
               bbox_to_anchor=(0.5, 0.995))


def plot(rows, out):
    """The grid of panels (paths as rows, flags as columns) into `out`; returns the panel count."""
    flags = ordered([r["flag"] for r in rows], FLAGS)
    paths = ordered([r["path"] for r in rows], PATHS)
    sizes = sorted({r["size"] for r in rows}, key=int)
    fig, axes = plt.subplots(len(paths), len(flags), figsize=(9 * len(flags), 5.2 * len(paths) + 0.6),
                             squeeze=False, dpi=100)
    labels = []
    for i, path in enumerate(paths):
        for j, flag in enumerate(flags):
            here = [r for r in rows if r["flag"] == flag and r["path"] == path]
            if not here:
                axes[i][j].set_axis_off()
                continue
            labels.append((axes[i][j], draw_panel(axes[i][j], here, f"{flag} / {path}")))
            axes[i][j].set_xlabel("cloth ms per 60 Hz frame", fontsize=9)
            if j == 0:
                axes[i][j].set_ylabel("trajectory error, % of the flag's width", fontsize=9)
    legend(fig, sizes)
    fig.tight_layout(rect=(0, 0, 1, 1 - 0.45 / fig.get_figheight()))
    for ax, names in labels:
        place_labels(ax, names)
    fig.savefig(out, dpi=80)  # under 1 MiB for the repository; the layout is in inches
    plt.close(fig)
    return len(labels)


def main(argv):
    """Runs on argv, the command line's arguments without the program's name."""
    if len(argv) != 1:
        sys.exit(__doc__)
    d = argv[0]
    with open(os.path.join(d, "front.csv"), newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        sys.exit(f"{d}/front.csv: no rows")
    out = os.path.join(d, "front.png")
    panels = plot(rows, out)
    points = sum(1 for r in rows if r["stable"] == "1" and (num(r["traj_error"]) or 0) > 0)
    print(f"{out}: {panels} panels, {points} configurations with a trajectory error, "
          f"{sum(r['stable'] != '1' for r in rows)} unstable rows")
