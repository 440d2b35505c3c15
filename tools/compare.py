#!/usr/bin/env python3
"""Side by side: one scene and its script run with two to four flag solvers, each recorded by
flagsim, then tiled into one video with each tile labelled by its solver and its cloth milliseconds
per frame (ffmpeg).

    tools/run compare --solvers "kangcho;small_steps:max_move=0.01" [--scene S] [--frames N]
                      [--out DIR] [--width W] [--height H] [--png]

Every run drives the same vehicle with the same input, so the tiles differ only in the flag.
Writes DIR/<k>/ (each run's frames-free recording: video.mp4, summary.json, profile.csv) and
DIR/compare.mp4 (2: side by side; 3 or 4: two by two), and with --png its frames as DIR/frames/*.png. Under each solver's name: its cloth per frame
(air, forces, solve, collisions and contact from its profile.csv, as tools/bench_cloth_budget.py sums
them), the mean over the last second, renewed every half second, and the whole run's mean
(DIR/<k>/labels.cmd holds the renewals). A bad solver spec stops before any run, with flagsim's
message naming it.
"""
import argparse
import json
import os
import shutil
import subprocess
import sys

from bench_cloth_budget import frame_sums

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
FONT = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf"


def fail(message):
    print(f"compare: error: {message}", file=sys.stderr)
    sys.exit(2)


def parse(argv):
    p = argparse.ArgumentParser(prog="tools/run compare", description=__doc__.split("\n\n")[0])
    p.add_argument("--solvers", required=True, help="two to four solver specs, ';'-separated")
    p.add_argument("--scene", default="flag_vehicle", help="scene name or file (default flag_vehicle)")
    p.add_argument("--frames", type=int, default=0, help="frames to run (default: the scene's duration)")
    p.add_argument("--out", default=os.path.join(ROOT, "out", "compare"), help="output folder (default out/compare)")
    p.add_argument("--width", type=int, default=640, help="each tile's width (default 640)")
    p.add_argument("--height", type=int, default=360, help="each tile's height (default 360)")
    p.add_argument("--png", action="store_true", help="also the tiled frames as DIR/frames/frame_NNNNN.png")
    p.add_argument("--flagsim", default=os.path.join(ROOT, "build", "app", "flagsim"), help=argparse.SUPPRESS)
    a = p.parse_args(argv)
    a.specs = [s.strip() for s in a.solvers.split(";") if s.strip()]
    if not 2 <= len(a.specs) <= 4:
        fail(f"--solvers: '{a.solvers}' names {len(a.specs)} solvers; give two to four, ';'-separated")
    if a.frames < 0:
        fail(f"--frames: {a.frames} is not a frame count")
    for name, v in (("--width", a.width), ("--height", a.height)):
        if not 16 <= v <= 3840 or v % 2:
            fail(f"{name}: {v} is not an even size in [16, 3840]")
    return a


def run_args(a, spec, out):
    args = [a.flagsim, "--scene", a.scene, "--solver", spec, "--out", out, "--force", "--no-frames", "--video",
            "--width", str(a.width), "--height", str(a.height)]
    if not sys.stdout.isatty():
        args.append("--no-progress")
    return args + (["--frames", str(a.frames)] if a.frames else [])


def check_specs(a):
    """Each spec as flagsim reads it, before any run: one frame, nothing kept."""
    for spec in a.specs:
        r = subprocess.run([a.flagsim, "--scene", a.scene, "--solver", spec, "--frames", "1", "--no-progress"],
                           capture_output=True, text=True)
        if r.returncode != 0:
            fail(f"--solvers: '{spec}': {r.stderr.strip().splitlines()[-1] if r.stderr.strip() else 'flagsim failed'}")


def cloth_ms(run_dir):
    """Each frame's cloth milliseconds in a run (profile.csv) and its frames per second (summary.json)."""
    sums = frame_sums(os.path.join(run_dir, "profile.csv"))
    with open(os.path.join(run_dir, "summary.json")) as f:
        summary = json.load(f)
    if not sums or summary.get("sim_time_s", 0) <= 0:
        fail(f"{run_dir}: no frames in profile.csv or summary.json")
    return sums, summary["frames"] / summary["sim_time_s"]


def label_commands(sums, fps, target):
    """sendcmd lines renewing `target`'s text every half second: the last second's mean cloth
    milliseconds per frame, then the run's mean (no ',' or ':' in the text, which sendcmd parses)."""
    mean = sum(sums) / len(sums)
    step, window = max(1, round(fps / 2)), max(1, round(fps))
    lines = []
    for k in range(0, len(sums), step):
        last = sums[max(0, k + 1 - window): k + 1]
        text = f"cloth {sum(last) / len(last):.1f} ms/frame (run mean {mean:.1f})"
        lines.append(f"{k / fps:.4f} {target} reinit text='{text}';")
    return "\n".join(lines) + "\n"


def quoted(text):
    """Text for a filter option inside '...' (ffmpeg's escaping)."""
    return text.replace("\\", "\\\\").replace(":", "\\:").replace("'", "\\'").replace(",", "\\,")


def tile_filter(specs, width, height, commands):
    """ffmpeg's filter graph: each input labelled with its solver and, below it, its cloth
    milliseconds (renewed by the sendcmd file commands[k]), then side by side (2) or two by two
    (3, 4)."""
    parts = []
    size = max(12, height // 20)
    for k, spec in enumerate(specs):
        text = f"fontfile={FONT}:fontsize={size}:fontcolor=white:box=1:boxcolor=black@0.5:x=10"
        parts.append(f"[{k}:v]drawtext={text}:y=10:text='{quoted(spec)}',sendcmd=f='{quoted(commands[k])}',"
                     f"drawtext@ms{k}={text}:y={10 + size * 3 // 2}:text='cloth'[t{k}]")
    if len(specs) == 2:
        parts.append("[t0][t1]hstack=inputs=2:shortest=1[out]")
    else:  # two by two; with three, the fourth corner black
        tiles = "".join(f"[t{k}]" for k in range(len(specs)))
        layout = "|".join(["0_0", "w0_0", "0_h0", "w0_h0"][: len(specs)])
        parts.append(f"{tiles}xstack=inputs={len(specs)}:layout={layout}:fill=black:shortest=1[out]")
    return ";".join(parts)


def main(argv):
    a = parse(argv)
    if not os.access(a.flagsim, os.X_OK):
        fail(f"no flagsim at {a.flagsim}: build it first (tools/run demo --help builds it)")
    os.makedirs(a.out, exist_ok=True)
    check_specs(a)
    videos, commands = [], []
    for k, spec in enumerate(a.specs, start=1):
        out = os.path.join(a.out, str(k))
        print(f"compare: [{k}/{len(a.specs)}] {spec} -> {out}", flush=True)
        if subprocess.run(run_args(a, spec, out)).returncode != 0:
            fail(f"the run of '{spec}' failed: {out}")
        videos.append(os.path.join(out, "video.mp4"))
        commands.append(os.path.join(out, "labels.cmd"))
        with open(commands[-1], "w") as f:
            f.write(label_commands(*cloth_ms(out), f"drawtext@ms{k - 1}"))
    target = os.path.join(a.out, "compare.mp4")
    partial = target + ".tmp.mp4"
    cmd = ["ffmpeg", "-y", "-loglevel", "error"]
    for v in videos:
        cmd += ["-i", v]
    cmd += ["-filter_complex", tile_filter(a.specs, a.width, a.height, commands), "-map", "[out]", "-c:v", "libx264",
            "-pix_fmt", "yuv420p", "-shortest", partial]
    if subprocess.run(cmd).returncode != 0:
        if os.path.exists(partial):
            os.remove(partial)
        fail("ffmpeg could not tile the videos")
    os.replace(partial, target)
    print(f"compare: {target}")
    if a.png:
        print(f"compare: {write_frames(target, os.path.join(a.out, 'frames'))}")


def write_frames(video, folder):
    """The video's frames as PNGs in `folder` (frame_00000.png on), written beside it and renamed into
    place when all are written, so that the folder never holds a partial set; returns the folder."""
    partial = folder + ".tmp"
    shutil.rmtree(partial, ignore_errors=True)
    os.makedirs(partial)
    cmd = ["ffmpeg", "-y", "-loglevel", "error", "-i", video, "-start_number", "0", os.path.join(partial, "frame_%05d.png")]
    if subprocess.run(cmd).returncode != 0:
        shutil.rmtree(partial, ignore_errors=True)
        fail(f"ffmpeg could not write the frames of {video}")
    shutil.rmtree(folder, ignore_errors=True)
    os.replace(partial, folder)
    return folder


if __name__ == "__main__":
    main(sys.argv[1:])
