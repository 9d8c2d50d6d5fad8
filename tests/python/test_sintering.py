"""Solid-state sintering from Python: the quasi-static stepper, its options, the furnace and the
sintering statistics (issue 36's acceptance test).

The numbers are those of the C tests: a 3x3x3 simple-cubic lattice of touching copper spheres
(R = 25 um) at 1293 K has 54 links (tests/unit/test_bonded.c, test_hard_cases.c); at 10 s every
neck is x/R = 0.12755 within 0.5 % (test_many_necks_at_once, the two-particle model of
docs/7dof.md sec. 6.2); the lattice shrinks affinely, equally along x, y and z, by the free
pair's Delta L / L0 (test_qs_lattice: 1e-3); examples/scenes/copper_lattice.scene says 1.03 %
at 1000 s.
"""

import math
import os
import tempfile
import unittest

import sinter

R = 25e-6  # sphere radius [m]
T_SINTER = 1293.0  # [K]
COPPER = {"density": 8960.0, "youngs_modulus": 72e9, "poisson_ratio": 0.3}
SOURCE_ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
COPPER_SCENE = os.path.join(SOURCE_ROOT, "examples", "scenes", "copper_lattice.scene")


def lattice(ctx, temperature=T_SINTER):
    """27 touching copper spheres in a 3x3x3 simple-cubic lattice with a corner at 0."""
    copper = sinter.Material(ctx, "copper", **COPPER)
    particles = sinter.Particles(ctx)
    particles.set_material(0, copper)
    particles.add([(2 * R * (k % 3), 2 * R * (k // 3 % 3), 2 * R * (k // 9)) for k in range(27)],
                  [R] * 27, temperature=temperature)
    return copper, particles


def pair_shrinkage(ctx, material, t_end, times=(0.0,), temperatures=(T_SINTER,)):
    """Delta L / L0 and the neck ratio of a free pair of the lattice's spheres at t_end."""
    with sinter.NeckModel(ctx) as neck:
        result = neck.two_particles(material, R, R, list(times), list(temperatures), [t_end])
    return list(result.shrinkage)[0], list(result.neck_ratio)[0]


class QuasiStaticStepperTest(unittest.TestCase):
    """A quasi-static stepper built from Python objects."""

    def setUp(self):
        self.ctx = sinter.Context()
        self.addCleanup(self.ctx.close)
        self.copper, self.particles = lattice(self.ctx)

    def test_lattice_sinters_like_the_c_tests(self):
        with sinter.Stepper(self.ctx, self.particles, kind="quasistatic", dt=1e-6) as stepper:
            self.assertIs(stepper.kind, sinter.StepperKind.QUASISTATIC)
            stepper.advance(2.0)
            early = stepper.sintering_stats()
            self.assertEqual(stepper.advance(10.0), 10.0)
            late = stepper.sintering_stats()
        self.assertIsInstance(late, sinter.SinteringStats)
        self.assertEqual(late.links, 54)
        self.assertAlmostEqual(late.coordination, 4.0, places=12)
        # every neck follows the two-particle model: x/R = 0.12755 at 10 s within 0.5 %
        for neck in (late.neck_min, late.neck_max, late.neck_mean):
            self.assertLess(abs(neck / R - 0.12755), 0.005 * 0.12755)
        self.assertAlmostEqual(late.neck_ratio_mean, late.neck_mean / R, places=12)
        # necks grow and the packing shrinks with time, isotropically
        self.assertGreater(late.neck_ratio_mean, early.neck_ratio_mean)
        self.assertGreater(early.shrinkage[0], 0.0)
        self.assertGreater(late.shrinkage[0], early.shrinkage[0])
        for axis in (1, 2):
            self.assertLess(abs(late.shrinkage[axis] - late.shrinkage[0]), 1e-9)
        self.assertAlmostEqual(late.linear_shrinkage, late.shrinkage[0], places=9)
        # the green density of touching spheres is pi/6; the box shrinks with the strain
        strain = (1 - late.shrinkage[0]) * (1 - late.shrinkage[1]) * (1 - late.shrinkage[2])
        self.assertAlmostEqual(late.relative_density, math.pi / 6 / strain, places=10)
        self.assertGreater(late.pcg_iterations, 0)
        # the lattice shrinks by the free pair's Delta L / L0 (test_qs_lattice: 1e-3)
        shrinkage, ratio = pair_shrinkage(self.ctx, self.copper, 10.0)
        self.assertLess(abs(late.shrinkage[0] - shrinkage), 1e-3 * shrinkage)
        self.assertLess(abs(late.neck_ratio_mean - ratio), 1e-3 * ratio)
        self.assertIn("links", late.as_dict())

    def test_options_by_key(self):
        with sinter.Stepper(self.ctx, self.particles, kind=sinter.StepperKind.QUASISTATIC,
                            dt=1e-6, options={"qs_strategy": 1, "qs_rtol": 1e-7}) as stepper:
            self.assertEqual(stepper.get_option("qs_strategy"), 1.0)
            self.assertEqual(stepper.get_option("qs_rtol"), 1e-7)
            stepper.set_option("qs_solve_rtol", 1e-10)
            self.assertEqual(stepper.get_option("qs_solve_rtol"), 1e-10)
            with self.assertRaises(sinter.NotFound) as caught:
                stepper.set_option("qs_bogus", 1.0)
            message = str(caught.exception)
            for key in sinter.OPTIONS["quasistatic"]:  # the message lists every valid key
                self.assertIn(key, message)
            with self.assertRaises(sinter.NotFound) as caught:
                stepper.set_option("bogus", 1.0)
            self.assertIn("qs_strategy", str(caught.exception))
            with self.assertRaises(sinter.InvalidArgument):
                stepper.set_option("qs_strategy", 7)
            stepper.advance(1.0)
            self.assertEqual(stepper.sintering_stats().links, 54)

    def test_furnace_schedule(self):
        # heated from 293 K to 1293 K in 5 s, then held: less sintering than the isothermal run
        times, temperatures = [0.0, 5.0], [293.0, T_SINTER]
        with sinter.Stepper(self.ctx, self.particles, kind="quasistatic", dt=1e-6,
                            furnace=(times, temperatures)) as stepper:
            stepper.advance(10.0)
            stats = stepper.sintering_stats()
            with self.particles.view("temperature") as temperature:
                self.assertEqual(list(temperature)[0], T_SINTER)
            stepper.set_furnace([], [])  # removed
        self.assertEqual(stats.links, 54)
        isothermal, _ = pair_shrinkage(self.ctx, self.copper, 10.0)
        ramped, _ = pair_shrinkage(self.ctx, self.copper, 10.0, times, temperatures)
        self.assertLess(ramped, isothermal)
        self.assertLess(abs(stats.shrinkage[0] - ramped), 1e-2 * ramped)
        with sinter.Stepper(self.ctx, self.particles, kind="quasistatic") as stepper:
            with self.assertRaises(sinter.InvalidArgument):
                stepper.set_furnace([0.0, 0.0], [300.0, 400.0])  # not increasing
            with self.assertRaises(ValueError):
                stepper.set_furnace([0.0], [300.0, 400.0])

    def test_checkpoint_continues_bit_for_bit(self):
        with tempfile.TemporaryDirectory() as directory:
            path = os.path.join(directory, "qs.bin")
            with sinter.Stepper(self.ctx, self.particles, kind="quasistatic", dt=1e-6) as st:
                st.advance(5.0)
                st.write_checkpoint(path)
                st.advance(10.0)
                straight = st.sintering_stats()
            _, again = lattice(self.ctx)
            with sinter.Stepper(self.ctx, again, kind="quasistatic", dt=1e-6) as st:
                st.read_checkpoint(path)
                self.assertEqual(st.time, 5.0)
                st.advance(10.0)
                self.assertEqual(st.sintering_stats(), straight)
                with self.assertRaises(FileNotFoundError):
                    st.read_checkpoint(os.path.join(directory, "missing.bin"))

    def test_statistics_need_a_quasistatic_stepper_that_stepped(self):
        with sinter.Stepper(self.ctx, self.particles, kind="quasistatic") as stepper:
            with self.assertRaises(sinter.SinterError) as caught:
                stepper.sintering_stats()
            self.assertIs(caught.exception.status, sinter.Status.ERR_STATE)
        with sinter.Stepper(self.ctx, self.particles, dt=1e-9) as stepper:
            with self.assertRaises(sinter.SinterError) as caught:
                stepper.sintering_stats()
            self.assertIs(caught.exception.status, sinter.Status.ERR_STATE)

    def test_unknown_kind_lists_the_kinds(self):
        with self.assertRaises(ValueError) as caught:
            sinter.Stepper(self.ctx, self.particles, kind="implicit")
        self.assertIn("quasistatic", str(caught.exception))


class CopperLatticeSceneTest(unittest.TestCase):
    """examples/scenes/copper_lattice.scene through sinter.Scene."""

    def test_scene_runs_and_reports_sintering(self):
        with tempfile.TemporaryDirectory() as out, sinter.Context() as ctx:
            with sinter.Scene(ctx, COPPER_SCENE) as scene:
                self.assertEqual(scene.end_time, 1000.0)
                samples = []
                self.assertTrue(scene.run(out, progress=lambda t, end: samples.append(t)))
                stats = scene.stepper.sintering_stats()
                self.assertEqual(scene.stepper.time, 1000.0)
                copper = scene.particles.get_material(0)
            self.assertEqual(samples[-1], 1000.0)
            self.assertEqual(stats.links, 54)
            # "The packing shrinks equally along x, y and z, by the two-particle value (1.03 %
            # at 1000 s)": the scene's comment, and the free pair's model
            for axis in range(3):
                self.assertAlmostEqual(stats.shrinkage[axis], 0.0103, delta=0.00005)
            shrinkage, ratio = pair_shrinkage(ctx, copper, 1000.0)
            self.assertLess(abs(stats.shrinkage[0] - shrinkage), 1e-3 * shrinkage)
            self.assertLess(abs(stats.neck_ratio_mean - ratio), 1e-3 * ratio)
            # the run's series has the statistics as they grew
            series = sinter.Series.read_csv(ctx, os.path.join(out, "series.csv"))
            self.assertEqual(series.units[series.columns.index("shrinkage x")], "1")
            shrinking = series["shrinkage x"]
            ratios = series["neck ratio mean"]
            self.assertEqual(len(shrinking), 21)  # every 50 s from 0 to 1000 s
            self.assertTrue(all(b > a for a, b in zip(ratios[1:], ratios[2:])))
            self.assertTrue(all(b > a for a, b in zip(shrinking[1:], shrinking[2:])))
            self.assertAlmostEqual(shrinking[-1], stats.shrinkage[0], places=12)
            self.assertEqual(series["links"][-1], 54.0)

    def test_scene_stepper_continues_from_python(self):
        with tempfile.TemporaryDirectory() as out, sinter.Context() as ctx:
            with sinter.Scene(ctx, COPPER_SCENE) as scene:
                scene.end_time = 20.0
                scene.run(out)
                first = scene.stepper.sintering_stats()
                scene.stepper.advance(40.0)
                later = scene.stepper.sintering_stats()
            self.assertEqual(first.links, 54)
            self.assertGreater(later.shrinkage[0], first.shrinkage[0])
            self.assertGreater(later.neck_ratio_mean, first.neck_ratio_mean)


class HostNeckLawTest(unittest.TestCase):
    """A host neck law (Stepper.set_neck_law): a pair law whose free approach is a constant
    rate v makes two touching spheres shrink by exactly v t / (2 R) (the stepper's contract:
    the decrease of L_A + L_B is the free approach, and a free pair follows it), and the law's
    neck radius is what the statistics report."""

    def test_constant_rate_law_sets_the_shrinkage(self):
        ctx = sinter.Context()
        self.addCleanup(ctx.close)
        copper = sinter.Material(ctx, "copper", **COPPER)
        particles = sinter.Particles(ctx)
        particles.set_material(0, copper)
        particles.add([(0.0, 0.0, 0.0), (2 * R, 0.0, 0.0)], [R, R], temperature=T_SINTER)
        rate = 1e-9  # free approach [m/s]
        seen = []

        def advance(batch: sinter.NeckLawBatch) -> None:
            seen.append((len(batch), batch.dt, list(batch.schedule_temperature)))
            for k in range(len(batch)):
                batch.state[k, 3] -= 0.5 * rate * batch.dt
                batch.state[k, 6] -= 0.5 * rate * batch.dt
                batch.state[k, 0] = 0.2 * batch.radius_a[k]

        with sinter.Stepper(ctx, particles, kind="quasistatic", dt=1e-3) as stepper:
            stepper.set_neck_law(advance)
            self.assertEqual(stepper.get_option("qs_neck_law"), 2.0)
            stepper.advance(100.0)
            stats = stepper.sintering_stats()
            stepper.set_neck_law(None)
            self.assertEqual(stepper.get_option("qs_neck_law"), 0.0)
        self.assertGreater(len(seen), 5)
        self.assertEqual(seen[0][0], 1)
        self.assertAlmostEqual(sum(step[1] for step in seen), 100.0, places=9)
        # the network solve's tolerance (PCG 1e-7)
        self.assertAlmostEqual(stats.shrinkage[0] / (rate * 100.0 / (2 * R)), 1.0, places=6)
        self.assertAlmostEqual(stats.neck_ratio_mean, 0.2, places=12)

    def test_exception_in_the_law_is_raised_again(self):
        ctx = sinter.Context()
        self.addCleanup(ctx.close)
        copper, particles = lattice(ctx)

        def advance(batch: sinter.NeckLawBatch) -> None:
            raise ZeroDivisionError("law")

        with sinter.Stepper(ctx, particles, kind="quasistatic", dt=1e-3) as stepper:
            stepper.set_neck_law(advance)
            with self.assertRaises(ZeroDivisionError):
                stepper.advance(1.0)


if __name__ == "__main__":
    unittest.main()
