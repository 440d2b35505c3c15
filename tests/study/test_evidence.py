"""`study.py evidence` and the stale marks against fixture folders: a run's row that differs from
the committed one fails naming its key and column; a marked row is listed as stale and passes; a
marked row that no longer differs fails; and `check-docs`' Docs refuses a finding that reads a
marked row beyond its key.

    PYTHONPATH=tools/study python3 tests/study/test_evidence.py   (ctest: Study.EvidenceCheck)
"""
import csv
import os
import subprocess
import sys
import tempfile
import unittest

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
STUDY = os.path.join(ROOT, "tools", "study", "study.py")
from flagstudy.checks.common import Docs, Finding, front

HEADER = ["row", "flag", "path", "size", "config", "ms_per_tick", "timing", "p99_stretch", "stable"]
ROWS = [
    ["0", "demo", "drive", "33", "shipped", "0.1", "serial", "0.2", "1"],
    ["1", "demo", "drive", "33", "multigrid", "0.5", "serial", "0.05", "1"],
]


def write(d, name, header, rows):
    os.makedirs(d, exist_ok=True)
    with open(os.path.join(d, name), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(header)
        w.writerows(rows)


def evidence(run, docs):
    p = subprocess.run([sys.executable, STUDY, "evidence", run, docs], capture_output=True, text=True)
    return p.returncode, p.stdout + p.stderr


class Evidence(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.docs, self.run = os.path.join(self.tmp.name, "docs"), os.path.join(self.tmp.name, "run")
        write(self.docs, "front.csv", HEADER, ROWS)

    def tearDown(self):
        self.tmp.cleanup()

    def test_identical_rows_pass_whatever_the_clock(self):
        rows = [r[:] for r in ROWS]
        rows[0][5], rows[0][6], rows[0][0] = "9.9", "parallel", "7"  # ms, timing, row: not evidence
        write(self.run, "front.csv", HEADER, rows)
        code, out = evidence(self.run, self.docs)
        self.assertEqual(code, 0, out)
        self.assertIn("2 rows of", out)

    def test_a_changed_row_fails_naming_its_key_and_column(self):
        rows = [r[:] for r in ROWS]
        rows[1][7] = "0.051"
        write(self.run, "front.csv", HEADER, rows)
        code, out = evidence(self.run, self.docs)
        self.assertEqual(code, 1, out)
        self.assertIn("front.csv flag=demo path=drive size=33 config=multigrid", out)
        self.assertIn("p99_stretch: 0.051 vs 0.05", out)

    def test_a_marked_row_passes_as_stale_and_a_stale_mark_fails(self):
        rows = [r[:] for r in ROWS]
        rows[1][7] = "0.051"
        write(self.run, "front.csv", HEADER, rows)
        write(self.docs, "stale.csv", ["file", "key", "why"], [["front.csv", "config=multi*", "a test's reason"]])
        code, out = evidence(self.run, self.docs)
        self.assertEqual(code, 0, out)
        self.assertIn("stale as marked (a test's reason)", out)
        write(self.run, "front.csv", HEADER, ROWS)  # the code computes the committed row again
        code, out = evidence(self.run, self.docs)
        self.assertEqual(code, 1, out)
        self.assertIn("remove its mark", out)

    def test_a_finding_that_reads_a_marked_row_fails(self):
        write(self.docs, "stale.csv", ["file", "key", "why"], [["front.csv", "config=multigrid", "re-run"]])
        docs = Docs(self.docs)
        self.assertEqual(front(docs, "demo", "drive", "shipped")["p99_stretch"], "0.2")
        row = front(docs, "demo", "drive", "multigrid")  # found by its key
        with self.assertRaises(Finding) as e:
            row["p99_stretch"]
        self.assertIn("marks stale", str(e.exception))


if __name__ == "__main__":
    unittest.main(verbosity=2)
