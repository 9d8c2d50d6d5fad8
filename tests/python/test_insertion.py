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


if __name__ == "__main__":
    unittest.main()
