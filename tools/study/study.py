#!/usr/bin/env python3
"""The study's tools, one command each: tools/study/study.py COMMAND [ARGS...]

The package flagstudy/ beside this file holds them (Python's path starts at a script's own folder,
so it imports as it is). A command's modules are imported when it runs: the checks need no
matplotlib, nvidia-newton runs in its own venv (numpy, Warp, NVIDIA Newton).
"""
import importlib
import sys

# command: (flagstudy's module, its function, the arguments, what it does)
COMMANDS = {
    "check": ("check_study", "main", "[--nvidia-newton] [DIR]", "a run's outputs (DIR: out/study)"),
    "check-docs": ("check_study", "main_docs", "[DIR]", "the docs' findings on the CSVs in DIR (docs/study)"),
    "plot-study": ("plot_study", "main", "DIR", "error_vs_runtime.png and stability.png"),
    "plot-front": ("plot_front", "main", "DIR", "front.png"),
    "front-checks": ("front_checks", "main", "[--shipped] DIR", "front.csv's columns recomputed"),
    "front-table": ("front_table", "main", "DIR [--matrix F S|--update MD...]", "the front's Markdown tables"),
    "merge-shards": ("merge_shards", "main", "OUT SHARD_DIR...", "cloth_study --shard parts joined"),
    "compare-runs": ("compare_runs", "main", "DIR_A DIR_B", "two runs agree but for the timings"),
    "evidence": ("evidence", "main", "RUN_DIR [DOCS_DIR]", "a run's rows equal the committed ones"),
    "nvidia-newton": ("nvidia_newton_study", "main", "IN_DIR OUT_CSV [...]", "NVIDIA Newton's solvers (a venv)"),
}
OWN_HELP = {"nvidia-newton"}  # commands that answer --help themselves; the others print their module's text


def usage():
    """The commands, one line each."""
    lines = ["usage: tools/study/study.py COMMAND [ARGS...]   (COMMAND --help: its own text)", "", "commands:"]
    lines += [f"  {name:<14}{args:<35}{what}" for name, (_, _, args, what) in COMMANDS.items()]
    return "\n".join(lines)


def main(argv):
    """Runs the command argv[0] names with the rest of argv; exit 2 for a missing or unknown one."""
    if argv[:1] in (["-h"], ["--help"], ["help"]):
        print(usage())
        return 0
    if not argv:
        print(usage(), file=sys.stderr)
        return 2
    name, args = argv[0], argv[1:]
    if name not in COMMANDS:
        print(f"study.py: unknown command '{name}' (commands: {', '.join(COMMANDS)}; study.py --help)",
              file=sys.stderr)
        return 2
    module_name, function, _, _ = COMMANDS[name]
    module = importlib.import_module(f"flagstudy.{module_name}")
    if args in (["-h"], ["--help"]) and name not in OWN_HELP:
        print(module.__doc__.strip())
        return 0
    return getattr(module, function)(args)


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
