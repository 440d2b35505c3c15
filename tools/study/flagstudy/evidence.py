"""Checks that the committed evidence is what today's code computes: every row of a run (CI's quick
study) whose key the committed CSVs also hold must equal the committed row in every
deterministic column (all but the row number, `timing` and the `ms_per_*` clock columns).

    tools/study/study.py evidence RUN_DIR [DOCS_DIR]   (DOCS_DIR: docs/study)

A differing row fails, naming its CSV, its key and each column that differs, unless
DOCS_DIR/stale.csv marks it (then it is listed as stale); a marked row that today's code computes
as committed fails too (its mark is stale). Exit 1 on any failure, else a line per CSV."""
import csv
import os
import sys

from flagstudy import stale

FILES = ("front.csv", "error_vs_runtime.csv")


def deterministic(column):
    return column not in ("row", "timing") and not column.startswith("ms_per_")


def read(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def keyed(name, rows, where):
    """The rows by key; two rows with one key is a broken CSV."""
    out = {}
    for r in rows:
        k = tuple(r.get(c, "") for c in stale.KEYS[name])
        if k in out:
            sys.exit(f"{where}: two rows with {stale.key_of(name, r)}")
        out[k] = r
    return out


def differences(run_row, doc_row):
    """'column: run vs committed' for each deterministic column both have that differs (a column
    the committed CSV does not have yet is no evidence either way: `compare` names them)."""
    return [f"{c}: {run_row[c]} vs {doc_row[c]}" for c in run_row
            if deterministic(c) and c in doc_row and run_row[c] != doc_row[c]]


def compare(name, run_dir, docs_dir, marks):
    """One CSV: (rows compared, failures, stale rows that differ as marked)."""
    run_path, doc_path = os.path.join(run_dir, name), os.path.join(docs_dir, name)
    if not os.path.isfile(run_path) or not os.path.isfile(doc_path):
        return 0, [], []
    run = keyed(name, read(run_path), run_path)
    docs = keyed(name, read(doc_path), doc_path)
    failures, marked = [], []
    shared = [k for k in run if k in docs]
    missing = [c for c in (next(iter(run.values()), {}) or {}) if c not in (next(iter(docs.values()), {}) or {})]
    if missing and shared:
        print(f"{name}: columns the committed CSV does not have yet (not compared): {', '.join(missing)}")
    for k in shared:
        diff = differences(run[k], docs[k])
        mark = stale.mark_of(marks, name, docs[k])
        where = f"{name} {stale.key_of(name, docs[k])}"
        if diff and mark:
            marked.append(f"{where}: stale as marked ({mark.why})")
        elif diff:
            failures.append(f"{where}: today's code computes another row: " + "; ".join(diff))
        elif mark:
            failures.append(f"{where}: marked stale ({mark.why}) but today's code computes the committed row: "
                            f"remove its mark from {stale.NAME}")
    return len(shared), failures, marked


def main(argv):
    if not argv or len(argv) > 2 or argv[0].startswith("-"):
        print(__doc__.strip(), file=sys.stderr)
        return 2
    run_dir = argv[0]
    docs_dir = argv[1] if len(argv) > 1 else "docs/study"
    try:
        marks = stale.read_marks(docs_dir)
    except ValueError as e:
        sys.exit(str(e))
    all_failures = []
    for name in FILES:
        n, failures, marked = compare(name, run_dir, docs_dir, marks)
        for line in marked:
            print(line)
        all_failures += failures
        print(f"{name}: {n} rows of {run_dir} shared with {docs_dir}, {n - len(failures) - len(marked)} identical, "
              f"{len(marked)} marked stale, {len(failures)} failing")
    if all_failures:
        print("\n".join(all_failures), file=sys.stderr)
        print(f"{len(all_failures)} rows: the committed evidence is not what today's code computes (re-run the rows "
              f"and commit them, or mark them in {os.path.join(docs_dir, stale.NAME)})", file=sys.stderr)
        return 1
    return 0
