"""Checks a study's outputs: every column and every solver family present, figures written; and the
findings the docs state, against the committed CSVs.

    tools/study/study.py check out/study      (exit 1 with the reason when something is missing;
                                               front.csv's columns: study.py front-checks)
    tools/study/study.py check --nvidia-newton out/study  (also: NVIDIA Newton's three solvers at every
                                                           scene and size, and at every extreme case
                                                           and size it was given)
    tools/study/study.py check-docs [DIR]     (only: every finding of docs/study.md (its front table
                                               first), docs/multigrid.md and docs/stiff_flag.md
                                               against the committed CSVs in DIR, default
                                               docs/study; one line per finding)
"""
import sys

from flagstudy.checks.common import Docs, Finding
from flagstudy.checks.demo_default_findings import DEMO_DEFAULT_FINDINGS
from flagstudy.checks.front_65_findings import FRONT_65_FINDINGS
from flagstudy.checks.front_demo_findings import FRONT_DEMO_FINDINGS
from flagstudy.checks.front_findings import FRONT_FINDINGS
from flagstudy.checks.multigrid_findings import MULTIGRID_FINDINGS
from flagstudy.checks.nvidia_newton_front_findings import NVIDIA_NEWTON_FRONT_FINDINGS
from flagstudy.checks.run_outputs import check_run
from flagstudy.checks.stiff_flag_findings import STIFF_FLAG_FINDINGS
from flagstudy.checks.study_findings import STUDY_FINDINGS
from flagstudy.checks.vbd_findings import VBD_FINDINGS
from flagstudy.checks.contact_findings import CONTACT_FINDINGS

# Every named finding, each doc's in the order it cites them: docs/study.md (its opening front table
# and the demo flag's front findings first), docs/multigrid.md, docs/stiff_flag.md.
DOC_CHECKS = (FRONT_FINDINGS + FRONT_DEMO_FINDINGS + FRONT_65_FINDINGS + VBD_FINDINGS + NVIDIA_NEWTON_FRONT_FINDINGS + CONTACT_FINDINGS + STUDY_FINDINGS + DEMO_DEFAULT_FINDINGS
              + MULTIGRID_FINDINGS + STIFF_FLAG_FINDINGS)


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
    """study.py check: [--nvidia-newton] [DIR] (default out/study), the run's outputs."""
    nvidia_newton = "--nvidia-newton" in argv
    args = [a for a in argv if a != "--nvidia-newton"]
    if len(args) > 1 or any(a.startswith("-") for a in args):
        sys.exit(__doc__)
    check_run(args[0] if args else "out/study", nvidia_newton)


def main_docs(argv):
    """study.py check-docs: [DIR] (default docs/study), every documented finding."""
    if len(argv) > 1 or any(a.startswith("-") for a in argv):
        sys.exit(__doc__)
    check_docs(argv[0] if argv else "docs/study")
