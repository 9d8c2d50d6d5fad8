"""Powder size distributions through the Python package (issue 38): the log-normal and table
options of pack_random, read_psd_csv, size_quantiles and a mixture by mass fraction."""

import os
import tempfile
import unittest

import sinter
import sinter.packing
import sinter.particles
from sinter.packing import pack_random, read_psd_csv, size_quantiles


class PsdCase(unittest.TestCase):
    def setUp(self):
        self.ctx = sinter.Context()
        self.copper = sinter.Material(self.ctx, "cu", density=8960.0)
        self.alumina = sinter.Material(self.ctx, "al", density=2700.0)
        self.ps = sinter.particles.Particles(self.ctx)
        self.ps.set_material(0, self.copper)
        self.ps.set_material(1, self.alumina)
        self.dir = tempfile.TemporaryDirectory()

    def tearDown(self):
        self.ctx.close()
        self.dir.cleanup()

    def write(self, text):
        path = os.path.join(self.dir.name, "psd.csv")
        with open(path, "w") as f:
            f.write(text)
        return path

    def test_table_by_volume_from_csv(self):
        path = self.write("size_um,Q3_percent\n10,0\n20,10\n30,30\n60,80\n100,100\n")
        d, q = read_psd_csv(self.ctx, path, unit=1e-6, percent=True)
        self.assertEqual(len(d), 5)
        self.assertAlmostEqual(d[-1], 100e-6)
        self.assertEqual(q[-1], 1.0)
        placed = pack_random(self.ps, 200, (0, 0, 0), (1.5e-3, 1.5e-3, 1.5e-3),
                             distribution="table", table_diameter=d, table_cumulative=q,
                             table_basis="volume", seed=3)
        self.assertEqual(placed, 200)
        d10, d50, d90 = size_quantiles(self.ps, basis="volume")
        self.assertTrue(10e-6 <= d10 <= d50 <= d90 <= 100e-6)
        n10, n50, n90 = size_quantiles(self.ps, basis="number")
        self.assertLess(n50, d50)

    def test_sequences_must_pair(self):
        with self.assertRaises(ValueError):
            sinter.packing.packing_options(table_diameter=[1e-5, 2e-5], table_cumulative=[1.0])
        with self.assertRaises(ValueError):
            sinter.packing.packing_options(mixture_materials=[0, 1])

    def test_bad_csv_names_the_line(self):
        path = self.write("10,0\n20,0.5\n15,1\n")
        with self.assertRaises(sinter.SinterError) as caught:
            read_psd_csv(self.ctx, path)
        self.assertIn("psd.csv:3:", str(caught.exception))

    def test_lognormal_mixture(self):
        placed = pack_random(self.ps, 300, (0, 0, 0), (1, 1, 1), distribution="lognormal",
                             radius_median=0.01, gsd=1.3, mixture_materials=[0, 1],
                             mixture_mass_fractions=[0.6, 0.4])
        self.assertEqual(placed, 300)
        self.assertEqual(len(size_quantiles(self.ps, fractions=[0.5])), 1)


if __name__ == "__main__":
    unittest.main()
