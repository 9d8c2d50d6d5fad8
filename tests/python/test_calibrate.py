"""sinter.calibrate: dilatometry import with the thermal-expansion correction, and the
least-squares driver (docs/calibration.md). The fitting tests need SciPy and are skipped without
it; the import tests need only the standard library."""

import importlib.util
import math
import os
import sys
import tempfile
import unittest
from unittest import mock

import sinter
from sinter import calibrate

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))

try:
    import numpy
    import scipy.optimize  # noqa: F401
    HAVE_SCIPY = True
except ImportError:
    HAVE_SCIPY = False


def write(directory, name, text):
    path = os.path.join(directory, name)
    with open(path, "w") as handle:
        handle.write(text)
    return path


class ThermalStrainTest(unittest.TestCase):
    def test_constant_alpha(self):
        # integral of a constant: alpha (T - T_ref), to round-off
        strains = calibrate.thermal_strain([293.0, 800.0, 1573.0], 293.0, cte=9e-6)
        for strain, temp in zip(strains, [293.0, 800.0, 1573.0]):
            self.assertAlmostEqual(strain, 9e-6 * (temp - 293.0), delta=1e-17)

    def test_linear_alpha_table_is_integrated_exactly(self):
        # alpha = a + b T sampled on three nodes: the integral is a (T - T0) + b (T^2 - T0^2) / 2
        # exactly (the table is piecewise linear and so is alpha); round-off only (1e-12 rel.)
        a, b = 7e-6, 3e-9
        nodes = (300.0, 700.0, 1600.0)
        table = calibrate.ExpansionTable(nodes, tuple(a + b * t for t in nodes))
        for temp in (300.0, 450.0, 700.0, 1156.0, 1600.0):
            exact = a * (temp - 400.0) + 0.5 * b * (temp * temp - 400.0 * 400.0)
            self.assertAlmostEqual(table.strain(temp, 400.0), exact, delta=1e-12 * abs(exact)
                                   + 1e-20)

    def test_table_is_constant_beyond_its_ends(self):
        table = calibrate.ExpansionTable((500.0, 1000.0), (8e-6, 10e-6))
        self.assertAlmostEqual(table.strain(400.0, 300.0), 8e-6 * 100.0, delta=1e-18)
        # 1000 -> 1200 K at the last node's value
        self.assertAlmostEqual(table.strain(1200.0, 1000.0), 10e-6 * 200.0, delta=1e-18)
        with self.assertRaises(ValueError):
            calibrate.ExpansionTable((500.0, 500.0), (8e-6, 9e-6))
        with self.assertRaises(ValueError):
            calibrate.thermal_strain([300.0], 300.0)  # neither cte nor table


class ReadDilatometryTest(unittest.TestCase):
    def test_round_trip_and_correction(self):
        with tempfile.TemporaryDirectory() as out:
            path = os.path.join(out, "run.csv")
            temps = [793.0, 1000.0, 1373.0, 1373.0, 900.0]
            shrink = [0.0, 1e-4, 5e-3, 1.2e-2, 1.3e-2]
            measured = [9e-6 * (t - 793.0) - s for t, s in zip(temps, shrink)]
            calibrate.write_dilatometry(path, [0.0, 600.0, 1800.0, 3600.0, 5000.0], temps,
                                        measured)
            data = calibrate.read_dilatometry(path, cte=9e-6)
            self.assertEqual(data.name, "run")
            self.assertEqual(data.reference_temperature, 793.0)  # the first line's
            self.assertEqual(data.measured_strain, measured)  # exact round trip (repr)
            for got, want in zip(data.shrinkage, shrink):
                self.assertAlmostEqual(got, want, delta=1e-17)
            # a table file of one constant node gives the same correction
            table = write(out, "alpha.csv", "T,alpha\n500,9e-6\n")
            again = calibrate.read_dilatometry(path, cte_table=table)
            for got, want in zip(again.thermal_strain, data.thermal_strain):
                self.assertAlmostEqual(got, want, delta=1e-18)

    def test_comments_header_and_blank_lines(self):
        with tempfile.TemporaryDirectory() as out:
            path = write(out, "d.csv", "# furnace 3\n\ntime,T,dL/L0\n0,300,0\n# gap\n10,310,"
                         "1e-5\n")
            data = calibrate.read_dilatometry(path)
            self.assertEqual(data.time, [0.0, 10.0])
            self.assertEqual(data.shrinkage, [-0.0, -1e-5])  # no correction asked for

    def test_bad_files_name_the_line(self):
        cases = {
            "0,300,0\n10,310\n": (2, "2 fields, expected 3"),
            "t,T,e\n0,300,0\n10,abc,0\n": (3, "field 2 is not a number"),
            "0,300,0\n10,310,nan\n": (2, "not finite"),
            "0,300,0\n10,310,0\n10,320,0\n": (3, "does not increase"),
            "0,300,0\n10,-5,0\n": (2, "not positive"),
            "time,T,e\n": (0, "no data lines"),
        }
        with tempfile.TemporaryDirectory() as out:
            for text, (line, words) in cases.items():
                path = write(out, "bad.csv", text)
                with self.assertRaises(calibrate.DilatometryError) as caught:
                    calibrate.read_dilatometry(path)
                self.assertEqual(caught.exception.line, line, text)
                self.assertIn(words, str(caught.exception))
                if line:
                    self.assertIn("bad.csv:%d:" % line, str(caught.exception))
            table = write(out, "alpha.csv", "T,alpha\n500,9e-6\n400,9e-6\n")
            with self.assertRaises(calibrate.DilatometryError) as caught:
                calibrate.read_expansion_table(table)
            self.assertEqual(caught.exception.line, 3)
        with self.assertRaises(FileNotFoundError):
            calibrate.read_dilatometry(os.path.join(ROOT, "no", "such.csv"))


class UnavailableTest(unittest.TestCase):
    def test_fit_says_scipy_is_missing(self):
        with mock.patch.dict(sys.modules, {"scipy": None, "scipy.optimize": None}):
            with sinter.Context() as ctx:
                material = sinter.Material(ctx, "cu")
                with self.assertRaises(calibrate.CalibrationUnavailable) as caught:
                    calibrate.fit(ctx, material, [], ["surface_diffusion_prefactor"])
        self.assertIn("SciPy", str(caught.exception))


@unittest.skipUnless(HAVE_SCIPY, "sinter.calibrate.fit needs NumPy and SciPy")
class FitTest(unittest.TestCase):
    def test_noise_free_data_give_back_the_truth(self):
        # Data made by the model itself: the least-squares minimum is the truth, and the driver
        # must reach it from a start a factor 3 and 5 % away. Tolerances: the model runs at
        # rtol 1e-9, which moves ln D0 by far less than 1e-4 and Q by less than 1e-5 relative.
        spec = importlib.util.spec_from_file_location(
            "recover", os.path.join(ROOT, "examples", "calibrate", "recover.py"))
        recover = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(recover)
        truth = recover.titanium()
        keys = ["grain_boundary_diffusion_prefactor_hot", "grain_boundary_activation_energy_hot"]
        with sinter.Context() as ctx:
            material = sinter.Material(ctx, "titanium", truth)
            profiles = []
            for name in ("E14B", "E28B"):
                times, temps = recover.schedule(name)
                profile = calibrate.Profile(name, 3.3e-5, times, temps)
                out = numpy.linspace(0.0, times[-1], 40)
                model = calibrate.predict(ctx, material, profile, out)
                profile.time, profile.shrinkage = out, model.shrinkage
                profile.shrinkage_sigma = 1e-4
                profiles.append(profile)
            start = {keys[0]: truth[keys[0]] * 3.0, keys[1]: truth[keys[1]] * 1.05}
            result = calibrate.fit(ctx, material, profiles, keys, start)
        self.assertTrue(result.success, result.message)
        self.assertAlmostEqual(result.reported[0], math.log(truth[keys[0]]), delta=1e-4)
        self.assertAlmostEqual(result.values[keys[1]] / truth[keys[1]], 1.0, delta=1e-5)

    def test_synthetic_dilatometry_recovered_within_intervals(self):
        # examples/calibrate/recover.py: three Table 3 profiles, noise 1e-4 in dL/L0 and 0.01 in
        # the final x/R, four beta-phase parameters. Each true value must lie in its 95 %
        # interval (fixed seed), and s^2 must be near 1 as the noise is what the weights say:
        # with about 350 degrees of freedom its spread is sqrt(2/350) = 0.076, so 0.7-1.3 is
        # four spreads.
        spec = importlib.util.spec_from_file_location(
            "recover", os.path.join(ROOT, "examples", "calibrate", "recover.py"))
        recover = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(recover)
        with tempfile.TemporaryDirectory() as out:
            result, truth = recover.run(out)
            self.assertTrue(os.path.exists(os.path.join(out, "E14B.dil.csv")))
        self.assertEqual(result.contains(truth), {k: True for k in truth})
        self.assertGreater(result.residual_variance, 0.7)
        self.assertLess(result.residual_variance, 1.3)
        # the grain-boundary data are what shrinkage determines: Q to better than 2 %
        q = result.interval["grain_boundary_activation_energy_hot"]
        self.assertLess((q[1] - q[0]) / truth["grain_boundary_activation_energy_hot"], 0.04)


if __name__ == "__main__":
    unittest.main()
