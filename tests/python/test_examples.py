"""The Python examples' own logic (ctest also runs them end to end)."""

import contextlib
import importlib.util
import io
import os
import tempfile
import unittest
from unittest import mock

from sinter import _lib

EXAMPLES = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "examples",
                        "python")


def load_example(name):
    spec = importlib.util.spec_from_file_location(name, os.path.join(EXAMPLES, name + ".py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@unittest.skipUnless(os.path.isdir(EXAMPLES), "not running from the source tree")
class ExamplesTest(unittest.TestCase):
    def test_neck_example_without_the_neck_model_exits_cleanly(self):
        example = load_example("neck_two_particles")
        out = io.StringIO()
        with mock.patch.object(_lib, "missing_functions", ["sinter_neck_two_particles"]), \
                contextlib.redirect_stdout(out), tempfile.TemporaryDirectory() as tmp:
            self.assertEqual(example.main(["--out", tmp, "--no-plot"]), 0)
            self.assertEqual(os.listdir(tmp), [])
        self.assertIn("no sinter_neck_two_particles", out.getvalue())

    def test_hot_floor_short_run_writes_csv(self):
        example = load_example("hot_floor")
        out = io.StringIO()
        with contextlib.redirect_stdout(out), tempfile.TemporaryDirectory() as tmp:
            # 1 s: warm enough (> 400 K) for softening to enlarge the contact
            self.assertEqual(example.main(["--out", tmp, "--end-time", "1", "--no-plot"]), 0)
            with open(os.path.join(tmp, "hot_floor.csv")) as csv:
                lines = csv.read().splitlines()
        self.assertEqual(lines[0], "time [s],temperature with softening [K],"
                                   "temperature without softening [K]")
        self.assertEqual(len(lines), 1 + 11)
        self.assertIn("static force 1.2328e-04 N", out.getvalue())

    def test_mpi_example_without_mpi_exits_cleanly(self):
        import sinter.mpi

        example = load_example("mpi_bed")
        out = io.StringIO()
        with mock.patch.object(sinter.mpi, "available", lambda: False), \
                contextlib.redirect_stdout(out), tempfile.TemporaryDirectory() as tmp:
            self.assertEqual(example.main(["--out", tmp]), 0)
            self.assertEqual(os.listdir(tmp), [])
        self.assertIn("needs mpi4py and libsinter_mpi", out.getvalue())


if __name__ == "__main__":
    unittest.main()
