"""Continuous insertion through the Python package (issue 38): the mass rate met within one
sphere's mass per interval, the velocity given, and bad options refused."""

import math
import unittest

import sinter
from sinter.packing import packing_options

RHO = 2500.0


class InsertionCase(unittest.TestCase):
    def setUp(self):
        self.ctx = sinter.Context()
        material = sinter.Material(self.ctx, "glass", youngs_modulus=1e7, poisson_ratio=0.3,
                                   density=RHO)
        self.ps = sinter.Particles(self.ctx)
        self.ps.set_material(0, material)
        self.walls = sinter.Walls(self.ctx)
        self.walls.add_plane((0, 0, 0), (0, 0, 1), material)
        self.stepper = sinter.Stepper(self.ctx, self.ps, self.walls, dt=1e-6,
                                      forces=[sinter.ForceModel(self.ctx, "hertz_mindlin"),
                                              sinter.ForceModel(self.ctx, "gravity")])
        self.powder = packing_options(box_min=(-1e-3, -1e-3, 3e-3), box_max=(1e-3, 1e-3, 4e-3),
                                      distribution="uniform", radius=1e-4, spread=2e-5, seed=4)

    def tearDown(self):
        self.ctx.close()

    def test_mass_rate_and_velocity(self):
        self.stepper.set_insertion(self.powder, region="cylinder", mass_rate=2e-5,
                                   interval=1e-3, velocity=(0.0, 0.0, -0.2))
        m_max = RHO * 4.0 / 3.0 * math.pi * (1.2e-4) ** 3
        for k in range(5):
            self.stepper.advance((k + 0.5) * 1e-3)
            done, target, count, crowded = self.stepper.insertion()
            self.assertAlmostEqual(target, 2e-5 * (k + 1) * 1e-3, delta=1e-18)
            self.assertLessEqual(done, target * (1 + 1e-12))
            self.assertLess(target - done, m_max)
            self.assertEqual(crowded, 0)
            self.assertEqual(count, len(self.ps))
        self.assertGreater(len(self.ps), 5)

    def test_bad_options_refused(self):
        with self.assertRaises(sinter.SinterError):
            self.stepper.set_insertion(self.powder, mass_rate=-1.0)
        with self.assertRaises(sinter.SinterError):
            self.stepper.set_insertion(self.powder, interval=0.0)
        with self.assertRaises(KeyError):
            self.stepper.set_insertion(self.powder, region="sphere")
        self.stepper.set_insertion(None)
        self.assertEqual(self.stepper.insertion(), (0.0, 0.0, 0, 0))

    def test_mixture_with_own_sizes(self):
        """A mixture of two materials by mass, each with its own sizes: the masses by
        material (insertion_mixture) add up to the mass inserted and each is within one
        sphere's mass of its share (the apportionment's bound)."""
        steel = sinter.Material(self.ctx, "steel", youngs_modulus=1e7, poisson_ratio=0.3,
                                density=7800.0)
        self.ps.set_material(1, steel)
        fine = packing_options(distribution="uniform", radius=6e-5, spread=1e-5)
        coarse = packing_options(radius=1e-4)
        powder = packing_options(box_min=(-1e-3, -1e-3, 3e-3), box_max=(1e-3, 1e-3, 4e-3),
                                 seed=5, mixture_materials=[0, 1],
                                 mixture_mass_fractions=[0.3, 0.7],
                                 mixture_sizes=[fine, coarse])
        self.stepper.set_insertion(powder, mass_rate=4e-5, velocity=(0.0, 0.0, -0.2))
        self.stepper.advance(5.5e-3)
        done = self.stepper.insertion()[0]
        by_material = self.stepper.insertion_mixture()
        self.assertEqual(len(by_material), 2)
        self.assertAlmostEqual(sum(by_material), done, delta=1e-12 * done)
        m_max = 7800.0 * 4.0 / 3.0 * math.pi * 1e-4 ** 3
        self.assertGreater(done, 5 * m_max)
        for mass, share in zip(by_material, (0.3, 0.7)):
            self.assertLessEqual(abs(mass - share * done), m_max)
        with self.assertRaises(ValueError):
            packing_options(mixture_materials=[0, 1], mixture_mass_fractions=[0.3, 0.7],
                            mixture_sizes=[fine])
        self.stepper.set_insertion(None)
        self.assertEqual(self.stepper.insertion_mixture(), [])


if __name__ == "__main__":
    unittest.main()
