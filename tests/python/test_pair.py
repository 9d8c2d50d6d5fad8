"""sinter.neck.run_pair (sinter_pair_run) on a Table 3 profile of examples/pair."""

import csv
import os
import tempfile
import unittest

import sinter
import sinter.neck

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))


class RunPairTest(unittest.TestCase):
    def test_table3_profile(self):
        ctx = sinter.Context()
        with tempfile.TemporaryDirectory() as out:
            csv_path = os.path.join(out, "E14B.csv")
            sinter.neck.run_pair(ctx, os.path.join(ROOT, "examples", "pair", "E14B.pair"),
                                 csv_path, os.path.join(out, "E14B.svg"))
            with open(csv_path, newline="") as f:
                rows = list(csv.reader(f))
            self.assertEqual(rows[0][:4], ["time [s]", "temperature [K]", "neck_ratio [1]",
                                           "shrinkage [1]"])
            last = [float(v) for v in rows[-1]]
            self.assertEqual(last[0], 8880.0)      # 793 K -> 1373 K -> 793 K
            self.assertGreater(last[2], 0.4)       # x/R
            self.assertGreater(last[3], 0.0)       # shrinkage
            self.assertEqual(last[9], 0.0)         # inside the model's domain
            self.assertTrue(os.path.exists(os.path.join(out, "E14B.svg")))

    def test_missing_file(self):
        ctx = sinter.Context()
        with self.assertRaises(sinter.SinterError):
            sinter.neck.run_pair(ctx, "/nonexistent.pair", "/tmp/x.csv")


if __name__ == "__main__":
    unittest.main()
