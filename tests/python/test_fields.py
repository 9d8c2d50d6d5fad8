"""Coarse-grained fields and lamina profiles from Python (sinter.coarse_grain, issue 37).

- touching spheres on a cubic lattice: the solid fraction inside is pi / 6, as an array of
  shape (nz, ny, nx);
- spheres settled on a floor under gravity: the vertical stress integrated over space is
  -g sum m_i z_i (the virial of a body in equilibrium on a floor at z = 0), to the grid's
  bound (docs/models.md) and the pile's residual forces;
- the laminae of seed 001 eq. 48 hold the spheres' volume;
- a subdomain's shares (sinter.fields.coarse_sums, lamina_sums; issue 44): without ghosts
  the density and the laminae they hold are sinter.coarse_grain's and lamina_profile's bit
  for bit, and write_vti_sums writes them.
"""

import math
import os
import tempfile
import unittest

import sinter

from _support import ArrayBackend, as_lists

G = 9.81


def grid_sum_bound(cutoff, ratio):
    """docs/models.md: the error of a grid sum of the kernel (spacing / width = ratio)."""
    norm = math.erf(cutoff / math.sqrt(2)) - math.sqrt(2 / math.pi) * cutoff * math.exp(
        -0.5 * cutoff ** 2)
    return (6 * math.exp(-2 * math.pi ** 2 / ratio ** 2) + ratio * 4 * math.pi * cutoff ** 2
            * math.exp(-0.5 * cutoff ** 2) / ((2 * math.pi) ** 1.5 * norm))


def flatten(array):
    """Every value of an array (NumPy of any shape, or a flat memoryview) as a list."""
    return [float(v) for v in (array.ravel() if hasattr(array, "ravel") else array)]


class FieldCases(ArrayBackend):
    def context(self):
        ctx = sinter.Context()
        self.addCleanup(ctx.close)
        material = sinter.Material(ctx, "glass", youngs_modulus=1e7, poisson_ratio=0.3,
                                   density=2500.0, damping_ratio=0.3, friction_static=0.3,
                                   friction_dynamic=0.3)
        particles = sinter.Particles(ctx)
        particles.set_material(0, material)
        return ctx, material, particles

    def test_lattice_solid_fraction(self):
        _, _, particles = self.context()
        r = 1e-3
        placed = sinter.pack_lattice(particles, (0, 0, 0), (28.01e-3, 28.01e-3, 28.01e-3), r)
        self.assertEqual(placed, 14 ** 3)
        phi = sinter.coarse_grain(particles, "solid_fraction", origin=11e-3, spacing=0.7e-3,
                                  points=(5, 6, 7), width=2 * r, cutoff=5.0)
        if self.use_numpy:
            self.assertEqual(phi.shape, (7, 6, 5))
        values = flatten(phi)
        self.assertEqual(len(values), 5 * 6 * 7)
        tol = grid_sum_bound(5.0, 1.0)
        for value in values:
            self.assertLess(abs(value / (math.pi / 6) - 1), tol)

    def test_settled_pile_stress(self):
        ctx, material, particles = self.context()
        walls = sinter.Walls(ctx)
        walls.add_plane((0, 0, 0), (0, 0, 1), material)
        stepper = sinter.Stepper(ctx, particles, walls, dt=1e-5,
                                 forces=[sinter.ForceModel(ctx, "hertz_mindlin"),
                                         sinter.ForceModel(ctx, "gravity")])
        self.addCleanup(stepper.close)
        particles.add([(2.5e-3 * (k % 2), 2.5e-3 * ((k // 2) % 2), 0.999e-3 + 1.998e-3 * (k // 4))
                       for k in range(12)], 1e-3)
        stepper.step(20000)
        width, cutoff, h = 0.5e-3, 5.0, 0.25e-3
        n = (int(11.5e-3 / h) + 1, int(11.5e-3 / h) + 1, int(13e-3 / h) + 1)
        sigma = sinter.coarse_grain(particles, "stress", origin=(-4e-3, -4e-3, -4e-3), spacing=h,
                                    points=n, width=width, cutoff=cutoff, stepper=stepper)
        values = flatten(sigma)
        self.assertEqual(len(values), 9 * n[0] * n[1] * n[2])
        szz = sum(values[8::9]) * h ** 3
        mass = as_lists(particles.get("mass"))
        z = [p[2] for p in as_lists(particles.get("position"))]
        force = [f[2] for f in as_lists(particles.get("force"))]
        expected = -G * sum(m * zi for m, zi in zip(mass, z))
        residual = sum(abs(f) * zi for f, zi in zip(force, z))  # sum z F_z: 0 at rest
        tol = grid_sum_bound(cutoff, h / width) * abs(expected) + residual
        self.assertLess(abs(szz - expected), tol, (szz, expected, residual))
        self.assertLess(residual, 1e-3 * abs(expected))  # the pile is at rest
        # no snapshot: at rest, almost no stress
        kinetic = flatten(sinter.coarse_grain(particles, "stress", origin=(-4e-3, -4e-3, -4e-3),
                                              spacing=h, points=n, width=width, cutoff=cutoff))
        self.assertLess(abs(sum(kinetic[8::9]) * h ** 3), 1e-6 * abs(expected))

    def test_laminae_hold_the_volume(self):
        _, _, particles = self.context()
        sinter.pack_lattice(particles, (0, 0, 0), (6.01e-3, 6.01e-3, 6.01e-3), 1e-3)
        fraction, temperature = sinter.lamina_profile(particles, "z", (0, 0, 0),
                                                      (6e-3, 6e-3, 6e-3), 12)
        values = flatten(fraction)
        self.assertEqual(len(values), 12)
        volume = sum(values) * 36e-6 * 0.5e-3
        self.assertAlmostEqual(volume / (27 * 4 / 3 * math.pi * 1e-9), 1.0, delta=1e-12)
        self.assertTrue(all(abs(t - 293.15) < 1e-9 for t in flatten(temperature)))
        with self.assertRaises(sinter.InvalidArgument):
            sinter.lamina_profile(particles, 1, (0, 0, 0), (6e-3, 6e-3, 6e-3), 0)
        with self.assertRaises(ValueError):
            sinter.coarse_grain(particles, "pressure", 0, 1e-3, 2, 1e-3)
        self.assertEqual(sinter.fields.quantity_info("stress"), ("stress", "Pa", 9))


    def test_shares_without_ghosts_are_the_whole(self):
        ctx, _, particles = self.context()
        sinter.pack_lattice(particles, (0, 0, 0), (4.01e-3, 4.01e-3, 4.01e-3), 1e-3)
        grid = dict(origin=-1e-3, spacing=1e-3, points=(6, 6, 6), width=1e-3)
        sums = sinter.fields.coarse_sums(particles, **grid)
        points = 6 ** 3
        self.assertEqual(len(sums), points * sinter.fields.COARSE_SUMS)
        density = flatten(sinter.coarse_grain(particles, "density", **grid))
        self.assertEqual([sums[15 * p + 1] for p in range(points)], density)
        self.assertEqual(sums[15 * points:], [0.0] * (9 * points))  # no contacts given
        laminae = sinter.fields.lamina_sums(particles, "z", (0, 0, 0), (4e-3, 4e-3, 4e-3), 8)
        fraction, _ = sinter.lamina_profile(particles, "z", (0, 0, 0), (4e-3, 4e-3, 4e-3), 8)
        self.assertEqual([v / (16e-6 * 0.5e-3) for v in laminae[:8]], flatten(fraction))
        with tempfile.TemporaryDirectory() as tmp:
            path = os.path.join(tmp, "fields.vti")
            sinter.fields.write_vti_sums(ctx, path, sums=sums, binary=False, **grid)
            with open(path) as f:
                self.assertIn('Name="temperature"', f.read())
            with self.assertRaises(sinter.InvalidArgument):
                sinter.fields.write_vti_sums(ctx, path, sums=sums[:5], **grid)


class PlotCsvTest(unittest.TestCase):
    """sinter.plot_csv (sinter_plot_csv, `sinter plot DIR --panel NAMES`): the chosen columns,
    by name or prefix, and nothing else, against the chosen x column."""

    def test_panels_by_name_and_prefix(self):
        with tempfile.TemporaryDirectory() as tmp, sinter.Context() as ctx:
            csv_path = os.path.join(tmp, "profile.csv")
            with open(csv_path, "w") as f:
                f.write("position [m],solid_fraction [1],temperature [K],coordination 0 [1],"
                        "coordination 1 [1]\n0,0.5,300,1,2\n1,0.6,310,0,3\n")
            svg = os.path.join(tmp, "p.svg")
            sinter.plot_csv(ctx, csv_path, svg, ["solid_fraction", "coordination"])
            with open(svg) as f:
                text = f.read()
            for name in ("solid_fraction", "coordination 0", "coordination 1", "position"):
                self.assertIn(name, text)
            self.assertNotIn("temperature", text)
            sinter.plot_csv(ctx, csv_path, svg, ["position"], x="temperature")
            with open(svg) as f:
                text = f.read()
            self.assertIn("temperature", text)
            self.assertNotIn("solid_fraction", text)
            with self.assertRaises(sinter.InvalidArgument):
                sinter.plot_csv(ctx, csv_path, svg, ["pressure"])
            with self.assertRaises(sinter.InvalidArgument):
                sinter.plot_csv(ctx, csv_path, svg, ["a"] * 9)
            with self.assertRaises(FileNotFoundError):
                sinter.plot_csv(ctx, os.path.join(tmp, "none.csv"), svg)


class FieldsNumpy(FieldCases, unittest.TestCase):
    use_numpy = True


class FieldsMemoryview(FieldCases, unittest.TestCase):
    use_numpy = False


if __name__ == "__main__":
    unittest.main()
