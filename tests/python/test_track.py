"""Particles followed in series.csv ([output] track; seed 003 Fig. 5) and the two-particle
reference of a quasi-static scene ([output] pair_reference; seed 001 Figs. 11, 19), from scene
runs.

examples/scenes/copper_lattice.scene with pair_reference: every link of a simple cubic lattice
shrinks as a free pair (the lattice is symmetric and its principal planes only hold it), so
the packing's mean neck ratio and its shrinkage along x, y, z are the two-particle model's, to
the neck integrators' tolerance (relative 1e-8 per step: 1e-6 over the run's steps).

examples/scenes/hot_floor.scene (seed 003 sec. 5.1: one sphere on a floor at 700 K) shortened
to 4 s and sampled every 50 ms, following particle 0:
  - its contact force is its weight m g once the critically damped contact has settled (the
    paper's 1.23e-4 N; gravity is the only other force);
  - its conductive heat flow balances its temperature change: m c (T(t + h) - T(t)) equals the
    trapezoidal integral of the flow over the sample interval h, to the trapezoid's error
    h^3 / 12 max|Q''| (Q'' from the series' second differences, doubled) plus the explicit
    temperature update's: it adds dt Q at each step's start, dt / 2 (Q(t + h) - Q(t)) less than
    the integral (dt = 20 us, the scene's step);
  - its contact area grows as the particle softens (seed 003 Fig. 5d).
"""

import csv
import math
import os
import tempfile
import unittest

import sinter

EXAMPLES = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "examples",
                        "scenes")


@unittest.skipUnless(os.path.isdir(EXAMPLES), "not running from the source tree")
class HotFloorTrack(unittest.TestCase):
    def test_single_particle_histories(self):
        with open(os.path.join(EXAMPLES, "hot_floor.scene")) as f:
            text = f.read()
        text = text.replace("end_time = 40", "end_time = 4").replace(
            "interval = 0.2", "interval = 0.05").replace("vtu = no", "vtu = no\ntrack = 0")
        with tempfile.TemporaryDirectory() as tmp:
            path = os.path.join(tmp, "hot_floor.scene")
            with open(path, "w") as f:
                f.write(text)
            with sinter.Context() as ctx, sinter.Scene.load(ctx, path) as scene:
                scene.run(os.path.join(tmp, "out"))
            with open(os.path.join(tmp, "out", "series.csv")) as f:
                rows = list(csv.reader(f))
        header = rows[0]
        names = ["particle 0 temperature [K]", "particle 0 contact force [N]",
                 "particle 0 largest overlap [m]", "particle 0 contact area [m^2]",
                 "particle 0 heat flow [W]"]
        self.assertEqual(header[-5:], names)
        data = [[float(v) for v in row] for row in rows[1:]]
        self.assertGreaterEqual(len(data), 81)  # (and the end, where the last step lands)
        t = [r[0] for r in data]
        temp, force, area, heat = ([r[header.index(n)] for r in data] for n in
                                   (names[0], names[1], names[3], names[4]))
        r, rho, c = 1e-3, 3000.0, 100.0
        m = rho * 4 / 3 * math.pi * r ** 3
        for k in range(10, len(data)):  # settled after 0.5 s
            self.assertAlmostEqual(force[k] / (m * 9.81), 1.0, delta=1e-6)
        self.assertAlmostEqual(force[-1], 1.23e-4, delta=0.005e-4)  # the paper's value
        for k in range(2, len(data) - 2):
            h = t[k + 1] - t[k]
            stored = m * c * (temp[k + 1] - temp[k])
            flowed = 0.5 * (heat[k] + heat[k + 1]) * h
            curvature = max(abs(heat[j + 1] - 2 * heat[j] + heat[j - 1]) / h ** 2
                            for j in (k, k + 1))
            euler = 0.5 * 2e-5 * abs(heat[k + 1] - heat[k])
            self.assertLess(abs(stored - flowed), 2 * h ** 3 / 12 * curvature + 1.1 * euler,
                            (t[k], stored, flowed))
        self.assertGreater(area[-1], area[10])  # softening: a larger contact


@unittest.skipUnless(os.path.isdir(EXAMPLES), "not running from the source tree")
class CopperLatticeReference(unittest.TestCase):
    def test_lattice_follows_the_pair(self):
        with open(os.path.join(EXAMPLES, "copper_lattice.scene")) as f:
            text = f.read().replace("vtu = yes", "vtu = no\npair_reference = yes")
        with tempfile.TemporaryDirectory() as tmp:
            path = os.path.join(tmp, "copper_lattice.scene")
            with open(path, "w") as f:
                f.write(text)
            with sinter.Context() as ctx, sinter.Scene.load(ctx, path) as scene:
                scene.run(os.path.join(tmp, "out"))
            with open(os.path.join(tmp, "out", "series.csv")) as f:
                rows = list(csv.reader(f))
            with open(os.path.join(tmp, "out", "series.svg")) as f:
                plot = f.read()
        header = rows[0]
        self.assertEqual(header[-2:], ["two-particle neck ratio [1]", "two-particle shrinkage [1]"])
        self.assertIn("two-particle neck ratio", plot)  # overlaid on the packing's
        data = [[float(v) for v in row] for row in rows[2:]]  # after the first step
        self.assertEqual(len(data), 20)
        ratio, pair_ratio = header.index("neck ratio mean [1]"), len(header) - 2
        for row in data:
            self.assertAlmostEqual(row[ratio] / row[pair_ratio], 1.0, delta=1e-6)
            for axis in "xyz":
                value = row[header.index("shrinkage %s [1]" % axis)]
                self.assertAlmostEqual(value / row[-1], 1.0, delta=1e-6)
        self.assertAlmostEqual(data[-1][-1], 0.0103, delta=0.00005)  # the example's 1.03 %


if __name__ == "__main__":
    unittest.main()
