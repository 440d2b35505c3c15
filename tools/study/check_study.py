#!/usr/bin/python3
"""Checks a study's outputs: every column and every solver family present, figures written.

    tools/study/check_study.py out/study      (exit 1 with the reason when something is missing;
                                               front.csv's columns: front_checks.py)
    tools/study/check_study.py --nvidia-newton out/study  (also: NVIDIA Newton's three solvers at every
                                                           scene and size, and at every extreme case
                                                           and size it was given)
    tools/study/check_study.py --docs [DIR]   (only: every finding of docs/study.md (its front table
                                               first), docs/multigrid.md and docs/stiff_flag.md
                                               against the committed CSVs in DIR, default
                                               docs/study; one line per finding)
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from checks.common import Docs, Finding  # noqa: E402
from checks.demo_default_findings import DEMO_DEFAULT_FINDINGS  # noqa: E402
from checks.front_demo_findings import FRONT_DEMO_FINDINGS  # noqa: E402
from checks.front_findings import FRONT_FINDINGS  # noqa: E402
from checks.multigrid_findings import MULTIGRID_FINDINGS  # noqa: E402
from checks.run_outputs import check_run  # noqa: E402
from checks.stiff_flag_findings import STIFF_FLAG_FINDINGS  # noqa: E402
from checks.study_findings import STUDY_FINDINGS  # noqa: E402

# Every named finding, each doc's in the order it cites them: docs/study.md (its opening front table
# and the demo flag's front findings first), docs/multigrid.md, docs/stiff_flag.md.
DOC_CHECKS = (FRONT_FINDINGS + FRONT_DEMO_FINDINGS + STUDY_FINDINGS + DEMO_DEFAULT_FINDINGS + MULTIGRID_FINDINGS
              + STIFF_FLAG_FINDINGS)


def check_docs(d):
    """Every named finding against the CSVs in d: one line each, exit 1 naming those that fail."""
    docs = Docs(d)
    failed = []
    for name, check in DOC_CHECKS:
        try:
            print(f"ok   {name}: {check(docs)}")
        except Finding as e:
            print(f"FAIL {name}: {e}")
            failed.append(name)
    if failed:
        sys.exit(f"{d}: {len(failed)} of {len(DOC_CHECKS)} documented findings no longer hold: {', '.join(failed)} "
                 "(fix the docs that cite them, or the CSVs)")
    print(f"{d}: all {len(DOC_CHECKS)} documented findings hold")


def main(argv):
    """Runs on argv, the command line's arguments without the program's name."""
    if argv and argv[0] == "--docs":
        return check_docs(argv[1] if len(argv) > 1 else "docs/study")
    nvidia_newton = "--nvidia-newton" in argv
    args = [a for a in argv if a != "--nvidia-newton"]
    check_run(args[0] if args else "out/study", nvidia_newton)


if __name__ == "__main__":
    main(sys.argv[1:])
