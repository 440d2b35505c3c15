"""Plots the study: error against run time (with the Pareto front) and stability maps.

    tools/study/study.py plot-study out/study  (reads error_vs_runtime.csv, writes the PNGs)
"""
import csv
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def num(x):
    try:
        v = float(x)
        return v if math.isfinite(v) else None
    except ValueError:
        return None


def read_rows(d):
    """error_vs_runtime.csv's rows, and NVIDIA Newton's beside them if the run has them."""
    with open(os.path.join(d, "error_vs_runtime.csv"), newline="") as f:
        rows = list(csv.DictReader(f))
    nvidia_newton = os.path.join(d, "nvidia_newton.csv")  # tools/run study --nvidia-newton (Warp CPU)
    if os.path.isfile(nvidia_newton):
        with open(nvidia_newton, newline="") as f:
            rows += list(csv.DictReader(f))
    return rows


def main_config(r):
    """The configuration every solver ran at every size (k = 1e4, h = 1/240)."""
    return float(r["stiffness"]) == 1e4 and abs(float(r["h"]) * 240 - 1) < 1e-4  # h is printed with 6 digits


def draw_panel(ax, mine, metric, label, title, colors, families):
    """One scene and size: each stable run's metric against its ms per step, with the Pareto front;
    unstable or failed runs listed in the panel."""
    ax.axis("on")
    pts, out = [], []
    for r in mine:
        ms, err = num(r["ms_per_step"]), num(r[metric])
        short = r["solver"].split(",substeps=1")[0][:26]
        if r["stable"] != "1" or ms is None:
            out.append(short)
            continue
        if err is None or err <= 0:
            continue  # stable, but without this metric (Newton's rows have no trajectory error)
        pts.append((ms, err))
        ax.scatter(ms, err, color=colors[r["family"]], s=28, zorder=3,
                   marker="s" if r["family"].startswith("nvidia_newton_") else "o")
        ax.annotate(short.split(":", 1)[-1][:22], (ms, err), fontsize=6, alpha=0.7)
    front, best = [], float("inf")
    for ms, err in sorted(pts):
        if err < best:
            front.append((ms, err))
            best = err
    if front:
        ax.plot(*zip(*front), color="black", linestyle="--", linewidth=1, label="Pareto front", zorder=2)
    if out:
        ax.text(0.01, 0.01, "unstable or failed:\n" + "\n".join(sorted(set(out))), transform=ax.transAxes,
                fontsize=5, va="bottom", ha="left", alpha=0.8)
    for fam in families:
        ax.scatter([], [], color=colors[fam], label=fam, marker="s" if fam.startswith("nvidia_newton_") else "o")
    if pts:
        ax.set_xscale("log")
        ax.set_yscale("log")
    else:
        ax.text(0.5, 0.5, f"no stable run has {metric} here", transform=ax.transAxes, ha="center")
    ax.set_xlabel("ms per step (median; nvidia_newton_*: Warp CPU kernels)")
    ax.set_ylabel(label)
    ax.set_title(title, fontsize=9)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=6, loc="upper right")


def plot_error_vs_runtime(rows, d):
    """Error against run time at k = 1e4, h = 1/240: two rows per scene (trajectory error against
    converged backward Euler, which Newton's rows do not have; and max stretch, which every row has),
    one column per size. Unstable or failed runs are listed in the panel, not plotted."""
    families = sorted({r["family"] for r in rows})
    palette = plt.cm.tab10 if len(families) <= 10 else plt.cm.tab20
    colors = {f: palette(i % palette.N) for i, f in enumerate(families)}
    panels = sorted({(r["scene"], r["size"]) for r in rows if main_config(r)},
                    key=lambda p: (p[0], int(p[1])))
    scenes = sorted({p[0] for p in panels})
    sizes = sorted({int(p[1]) for p in panels})
    metrics = [("traj_error_be", "trajectory error vs converged backward Euler / size"),
               ("max_stretch", "max stretch")]
    fig, axes = plt.subplots(len(scenes) * len(metrics), len(sizes),
                             figsize=(5.5 * len(sizes), 4.8 * len(scenes) * len(metrics)), squeeze=False)
    for ax in axes.flat:
        ax.axis("off")
    for scene, size in panels:
        mine = [r for r in rows if (r["scene"], r["size"]) == (scene, size) and main_config(r)]
        for m, (metric, label) in enumerate(metrics):
            ax = axes[scenes.index(scene) * len(metrics) + m][sizes.index(int(size))]
            draw_panel(ax, mine, metric, label, f"{scene} {size}x{size}, k = 1e4 N/m, h = 1/240 s", colors, families)
    fig.tight_layout()
    fig.savefig(os.path.join(d, "error_vs_runtime.png"), dpi=90)


def plot_stability(rows, d):
    """Stiffness against h per solver on the hanging 17x17 flag, coloured by max stretch, blow-ups marked."""
    scan = [r for r in rows if r["scene"] == "hanging_flag" and r["size"] == "17"]
    solvers = sorted({r["solver"] for r in scan})
    cols = 5
    nrows = math.ceil(len(solvers) / cols)
    fig, axes = plt.subplots(nrows, cols, figsize=(3.2 * cols, 2.8 * nrows), squeeze=False)
    for ax, solver in zip(axes.flat, solvers):
        for r in scan:
            if r["solver"] != solver:
                continue
            k, h = float(r["stiffness"]), float(r["h"])
            if r["stable"] == "1":
                s = num(r["max_stretch"]) or 0
                ax.scatter(h, k, c=[min(s, 1.0)], cmap="viridis", vmin=0, vmax=1, s=60)
            else:
                ax.scatter(h, k, marker="x", color="red", s=60)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_title(solver[:34], fontsize=7)
        ax.tick_params(labelsize=6)
    for ax in list(axes.flat)[len(solvers):]:
        ax.axis("off")
    fig.supxlabel("time step h (s)")
    fig.supylabel("stiffness k (N/m)")
    fig.suptitle("Hanging flag 17x17: colour = max stretch (0..1), red x = blew up", fontsize=10)
    fig.tight_layout()
    fig.savefig(os.path.join(d, "stability.png"), dpi=90)


def main(argv):
    """Runs on argv, the command line's arguments without the program's name."""
    d = argv[0] if argv else "out/study"
    rows = read_rows(d)
    plot_error_vs_runtime(rows, d)
    plot_stability(rows, d)
    print(os.path.join(d, "error_vs_runtime.png"), os.path.join(d, "stability.png"))
