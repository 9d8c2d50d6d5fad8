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


def _load_recover():
    spec = importlib.util.spec_from_file_location(
        "recover", os.path.join(ROOT, "examples", "calibrate", "recover.py"))
    recover = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(recover)
    return recover


@unittest.skipUnless(HAVE_SCIPY, "sinter.calibrate.fit needs NumPy and SciPy")
class PathConstantTest(unittest.TestCase):
    """The path constants of docs/7dof.md sec. 3 as fitted parameters (issue 42)."""

    def synthetic(self, ctx, material, names, sigma, rng=None, count=40):
        recover = _load_recover()
        profiles = []
        for name in names:
            times, temps = recover.schedule(name)
            profile = calibrate.Profile(name, 3.3e-5, times, temps)
            out = numpy.linspace(0.0, times[-1], count)
            model = calibrate.predict(ctx, material, profile, out)
            noise = rng.normal(0.0, sigma, out.size) if rng is not None else 0.0
            profile.time, profile.shrinkage = out, numpy.asarray(model.shrinkage) + noise
            profile.shrinkage_sigma = sigma
            profiles.append(profile)
        return profiles

    def test_boundary_path_recovered_with_d0_fixed(self):
        # Titanium with the grain-boundary path at 0.15 y1 instead of the default 0.25, the
        # diffusion data fixed at Table 4's: shrinkage determines the path (it scales fluxes I
        # and II as 1 / ds). Noise-free data must give it back to 1e-4 in ln ds (the model at
        # rtol 1e-9 moves it far less); with noise of 1e-4 in dL/L0 (fixed seed) the truth must
        # lie in the 95 % interval, which must be narrower than +-2 % (the shrinkage, 1e-2 at the
        # end, pins 1 / ds to about the relative noise over 80 points); s^2 must be near 1, the
        # noise being what the weights say: with 79 degrees of freedom its spread is
        # sqrt(2/79) = 0.16, so 0.36-1.64 is four spreads.
        recover = _load_recover()
        truth = dict(recover.titanium(), neck_boundary_path=0.15)
        key = "neck_boundary_path"
        with sinter.Context() as ctx:
            material = sinter.Material(ctx, "titanium", truth)
            exact = self.synthetic(ctx, material, ("E14B", "E28B"), 1e-4)
            noisy = self.synthetic(ctx, material, ("E14B", "E28B"), 1e-4,
                                   numpy.random.default_rng(42))
            start = {key: 0.25}
            result = calibrate.fit(ctx, material, exact, [key], start)
            self.assertTrue(result.success, result.message)
            self.assertTrue(result.identifiable)
            self.assertEqual(result.jacobian_kind, "sensitivity")
            self.assertAlmostEqual(result.reported[0], math.log(0.15), delta=1e-4)
            result = calibrate.fit(ctx, material, noisy, [key], start)
        self.assertTrue(result.identifiable)
        self.assertEqual(result.contains({key: 0.15}), {key: True})
        low, high = result.interval[key]
        self.assertLess(high / low, 1.04)
        self.assertGreater(result.residual_variance, 0.36)
        self.assertLess(result.residual_variance, 1.64)

    def test_sensitivity_and_differences_agree(self):
        # The Jacobian of a path constant from the forward sensitivities (sinter_neck_
        # sensitivities) and from central differences of +-1e-3 in ln ds: the same fit to 1e-6
        # in ln ds (both converge to the noise-free truth; the differences' truncation error is
        # 1e-6 of the derivative, which moves the optimum by less).
        recover = _load_recover()
        truth = dict(recover.titanium(), neck_cap_path=1.6)
        key = "neck_cap_path"
        with sinter.Context() as ctx:
            material = sinter.Material(ctx, "titanium", truth)
            profiles = self.synthetic(ctx, material, ("E14B",), 1e-5)
            for profile in profiles:  # the cap path acts on the neck more than on shrinkage
                profile.neck_time, profile.neck_ratio = profile.time, calibrate.predict(
                    ctx, material, profile, profile.time).neck_ratio
                profile.neck_sigma = 1e-4
            by_sens = calibrate.fit(ctx, material, profiles, [key], {key: 1.0})
            by_diff = calibrate.fit(ctx, material, profiles, [key], {key: 1.0},
                                    jacobian="differences")
        self.assertEqual(by_diff.jacobian_kind, "differences")
        self.assertAlmostEqual(by_sens.reported[0], math.log(1.6), delta=1e-4)
        self.assertAlmostEqual(by_diff.reported[0], by_sens.reported[0], delta=1e-6)

    def test_path_and_its_prefactor_are_not_identifiable(self):
        # Copper at 1293 K with lattice diffusion off: the boundary path enters only flux I, as
        # D_gb0 / ds (docs/7dof.md sec. 3), so every data set is fitted equally well along
        # ln D_gb0 - ln ds = const. The driver must say so: not identifiable, the direction
        # (1, 1) / sqrt 2 in (ln ds, ln D_gb0), infinite intervals for both; what it can fit,
        # the ratio D_gb0 / ds, must still come back (1e-4 in its ln, as above); with
        # refuse_unidentifiable it raises NotIdentifiable.
        keys = ["neck_boundary_path", "grain_boundary_diffusion_prefactor"]
        with sinter.Context() as ctx:
            material = sinter.Material(ctx, "copper", {"lattice_diffusion_prefactor": 0.0})
            truth = {k: float(material[k]) for k in keys}
            profile = calibrate.Profile("cu", 25e-6, [0.0, 5000.0], [1293.0, 1293.0])
            out = numpy.linspace(100.0, 5000.0, 30)
            model = calibrate.predict(ctx, material, profile, out)
            profile.time, profile.shrinkage, profile.shrinkage_sigma = out, model.shrinkage, 1e-4
            profile.neck_time, profile.neck_ratio, profile.neck_sigma = (
                out, model.neck_ratio, 1e-3)
            start = {keys[0]: truth[keys[0]] * 1.5, keys[1]: truth[keys[1]] / 2.0}
            result = calibrate.fit(ctx, material, [profile], keys, start)
            self.assertFalse(result.identifiable)
            self.assertGreater(result.condition, 1e5)
            self.assertEqual(len(result.unidentified), 1)
            direction = result.unidentified[0]
            self.assertAlmostEqual(abs(direction[keys[0]]), math.sqrt(0.5), delta=1e-4)
            self.assertAlmostEqual(direction[keys[0]], direction[keys[1]], delta=1e-4)
            for key in keys:
                self.assertTrue(math.isinf(result.standard_error[keys.index(key)]))
                self.assertEqual(result.interval[key], (0.0, math.inf))
            self.assertIn("not identifiable", result.message)
            ratio = result.reported[1] - result.reported[0]
            self.assertAlmostEqual(ratio, math.log(truth[keys[1]] / truth[keys[0]]), delta=1e-4)
            with self.assertRaises(calibrate.NotIdentifiable) as caught:
                calibrate.fit(ctx, material, [profile], keys, start, refuse_unidentifiable=True)
            self.assertEqual(len(caught.exception.combinations), 1)
            # the path alone, with D_gb0 fixed at the truth, is identifiable and comes back
            alone = calibrate.fit(ctx, material, [profile], keys[:1], {keys[0]: 0.5})
        self.assertTrue(alone.identifiable)
        self.assertAlmostEqual(alone.reported[0], math.log(truth[keys[0]]), delta=1e-4)
        self.assertLess(alone.condition, 1.0 + 1e-12)


if __name__ == "__main__":
    unittest.main()
