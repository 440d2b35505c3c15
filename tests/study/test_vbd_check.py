"""The check of our vbd against NVIDIA Newton's VBD (study.py check --nvidia-newton,
checks/run_outputs.check_vbd_against_nvidia_newton) on fixture CSVs: converged rows within the bound
pass; a converged row farther apart fails naming its distance; a run whose flag does not move, or
that has no converged row, fails; rows at 10 iterations, far apart by design, are not judged.

    PYTHONPATH=tools/study python3 tests/study/test_vbd_check.py   (ctest: Study.VbdCheckAgainstNvidiaNewton)
"""
import csv
import os
import tempfile
import unittest

from flagstudy.checks.run_outputs import check_vbd_against_nvidia_newton

HEADER = ["scene", "size", "iterations", "steps", "rms_m", "max_m", "moved_rms_m"]


def problems(rows):
    with tempfile.TemporaryDirectory() as d:
        with open(os.path.join(d, "nvidia_newton_vbd_check.csv"), "w", newline="") as f:
            w = csv.writer(f)
            w.writerow(HEADER)
            w.writerows(rows)
        return check_vbd_against_nvidia_newton(d)


class VbdCheck(unittest.TestCase):
    def test_converged_rows_within_the_bound_pass(self):
        self.assertEqual(problems([["vehicle_path", "9", "10", "120", "0.0061", "0.018", "0.96"],
                                   ["vehicle_path", "9", "100", "120", "1.07e-05", "2.8e-05", "0.93"]]), [])

    def test_a_converged_row_farther_apart_fails_naming_its_distance(self):
        found = problems([["vehicle_path", "9", "100", "120", "0.0061", "0.018", "0.93"]])
        self.assertEqual(len(found), 1)
        self.assertIn("0.0061 m apart", found[0])

    def test_a_flag_that_does_not_move_fails(self):
        found = problems([["hanging_flag", "9", "100", "120", "1e-06", "3e-06", "0.001"]])
        self.assertTrue(any("moves over" in p for p in found))

    def test_a_missing_file_or_converged_row_fails(self):
        with tempfile.TemporaryDirectory() as d:
            self.assertTrue(check_vbd_against_nvidia_newton(d))
        self.assertTrue(problems([["vehicle_path", "9", "10", "120", "1e-06", "3e-06", "0.96"]]))


if __name__ == "__main__":
    unittest.main()
