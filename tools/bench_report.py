#!/usr/bin/python3
"""docs/performance.md from one run of tools/run bench: the commit and the machine, then the
run's tables (out/bench/cloth_bench.md, cloth_budget.md, and the demo frame's profile when the
run has it), with what each row measures.

    tools/bench_report.py out/bench > out/bench/performance.md
"""
import datetime
import os
import subprocess
import sys


def machine():
    model = "unknown CPU"
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    model = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    return f"{os.cpu_count()} vCPUs, {model}"


def commit(root):
    try:
        out = subprocess.run(["git", "-C", root, "log", "-1", "--format=%h %cd", "--date=short"],
                             capture_output=True, text=True, check=True).stdout.strip()
        dirty = subprocess.run(["git", "-C", root, "status", "--porcelain", "--untracked-files=no"],
                               capture_output=True, text=True, check=True).stdout.strip()
        return out + (" (with uncommitted changes)" if dirty else "")
    except (OSError, subprocess.CalledProcessError):
        return "unknown"


def section(path, title, text):
    if not os.path.exists(path):
        return []
    with open(path) as f:
        body = f.read().strip()
    return [f"## {title}", "", text, "", body, ""]


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    out = sys.argv[1]
    root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
    quick = os.path.exists(os.path.join(out, "quick"))
    lines = ["# Performance", "",
             f"One run of `tools/run bench{' --quick' if quick else ''}` at commit {commit(root)}, on "
             f"{datetime.date.today().isoformat()}: {machine()}; Release build, GCC, no `-march` (the "
             "kernels carry their own AVX2 clone). The machine is shared and noisy: compare rows of one "
             "run (the ratios below), not runs. Regenerate: `tools/run bench` (or `--quick`), which writes "
             "this report to `out/bench/performance.md`; `docs/performance.md` is the reference that "
             "cites such runs.", ""]
    lines += section(os.path.join(out, "cloth_bench.md"), "The cloth step",
                     "Google Benchmark, medians of the repetitions. `stepFlag/NAME/SIDE/THREADS`: the hanging "
                     "flag (h = 1/240 s, k = 1e4 N/m) on a still pole, or (`swung_`) on a pole moving on a 2 Hz "
                     "circle so that the flag moves in every timed step. `max stretch after 1 s` is the largest "
                     "structural `L/l0 - 1` after 240 steps from rest. The multigrid cost goals are ratios of this "
                     "run's own medians.")
    lines += section(os.path.join(out, "cloth_budget.md"), "The cloth's real-time budget per 60 Hz frame",
                     "Copies of the demo's scenes without rendering (the 129x129 flag on two threads), of the "
                     "true-motion scene (`flag_vehicle_true_motion`: the demo's flag on `small_steps` paced at 1 cm "
                     "per substep, contact after every second substep once the flag has moved 1 cm on its pole; "
                     "`33x33_true_no_contact` the same without "
                     "contact) and of the stiff scene (`flag_vehicle_stiff`: its true motion, `small_steps` at 240 Hz, contact after "
                     "every fourth substep once the flag has moved 2 cm on its pole), each on one and two "
                     "threads, and again beside a busy loop pinned to the last core (`_busy`); in the full run also at 65x65, and "
                     "at 129x129 on two threads, without contact, beside the demo flag's true motion at 129x129 without "
                     "contact); `33x33` is the demo's flag "
                     "without contact (`flag_vehicle_no_contact`) and `33x33_contact` the main demo (`flag_vehicle`, "
                     "with contact), on the demo's drive: air, cloth forces, solve, collision and contact per "
                     "frame from `profile.csv`, against 1 ms (33x33), 2 ms (33x33 with contact), 4 ms (65x65) and 16 ms "
                     "(129x129, the true-motion and the stiff scene). `x demo`: the row's mean and median over the "
                     "demo's at its size, in this run; `x without contact`: over the same scene's without contact; "
                     "`x one thread`: a two-thread row over the same run on one thread.")
    lines += section(os.path.join(out, "demo_frame.txt"), "The demo frame without disk writes",
                     "`flagsim --frames 300` at 1280x720 (software OpenGL through llvmpipe: render and readback "
                     "dominate).")
    lines += section(os.path.join(out, "demo_recording.txt"), "The demo frame while recording",
                     "`flagsim --frames 300 --out DIR`: PNG frames written on worker threads.")
    print("\n".join(lines).rstrip() + "\n")


if __name__ == "__main__":
    main()
