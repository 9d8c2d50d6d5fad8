"""A copper lattice's frames opened with VTK's own XML readers (issue 37).

examples/scenes/copper_lattice.scene, shortened to 100 s, with `[output] contacts = yes` and a
`[fields]` section, run by sinter.Scene:
  - frames/links_NNNNN.vtp (vtkXMLPolyDataReader): one line per link of the sintering
    statistics, carrying `neck_radius` cell data whose mean is the statistics' neck mean;
  - frames/fields_NNNNN.vti (vtkXMLImageDataReader): the grid of the section, whose solid
    fraction summed times the cell volume is the spheres' volume to the bound of
    docs/models.md (a grid of spacing w / 2, a kernel cut at 5 w, all inside the grid);
  - frames/profile_z_NNNNN.csv: the laminae hold the spheres' volume (seed 001 eq. 48).
Written in double precision, then again with `[output] vtu_precision = single` (Float32
arrays: the values agree to a float's rounding, 2^-24 relative) and with `vtu_format =
appended` (raw appended data, the same values). Skipped where VTK's Python
module (Debian's python3-vtk9) is absent.
"""

import csv
import math
import os
import tempfile
import unittest

import sinter

try:
    import vtk
    from vtk.util.numpy_support import vtk_to_numpy
except ImportError:  # python3-vtk9 not installed (or no NumPy)
    vtk = None

EXAMPLES = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "examples",
                        "scenes")
FIELDS = """
contacts = yes
vtu_precision = %s
vtu_format = %s

[fields]
width = 25e-6
cutoff = 5
spacing = 12.5e-6
box_min = -150e-6 -150e-6 -150e-6
box_max = 300e-6 300e-6 300e-6
profiles = z
laminae = 6
"""


def bound(cutoff, ratio):
    """docs/models.md: the error of a grid sum of the kernel (spacing / width = ratio)."""
    norm = math.erf(cutoff / math.sqrt(2)) - math.sqrt(2 / math.pi) * cutoff * math.exp(
        -0.5 * cutoff ** 2)
    return (6 * math.exp(-2 * math.pi ** 2 / ratio ** 2) + ratio * 4 * math.pi * cutoff ** 2
            * math.exp(-0.5 * cutoff ** 2) / ((2 * math.pi) ** 1.5 * norm))


@unittest.skipUnless(vtk is not None, "VTK's Python module (python3-vtk9) is not installed")
@unittest.skipUnless(os.path.isdir(EXAMPLES), "not running from the source tree")
class CopperLatticeFiles(unittest.TestCase):
    precision = "double"
    format = "binary"
    rounding = 1e-12  # relative, of a value read back

    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        with open(os.path.join(EXAMPLES, "copper_lattice.scene")) as f:
            text = f.read().replace("end_time = 1000", "end_time = 100")
        path = os.path.join(cls.tmp.name, "copper_lattice.scene")
        with open(path, "w") as f:
            f.write(text + FIELDS % (cls.precision, cls.format))
        cls.out = os.path.join(cls.tmp.name, "out")
        with sinter.Context() as ctx, sinter.Scene.load(ctx, path) as scene:
            scene.run(cls.out)
            stats = scene.stepper.sintering_stats()
            cls.links, cls.neck_mean = stats.links, stats.neck_mean
            radius = scene.particles.get("radius")
            cls.volume = sum(4 / 3 * math.pi * r ** 3 for r in radius)

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def frame(self, name):
        return os.path.join(self.out, "frames", name)

    def test_links_carry_their_neck_radius(self):
        reader = vtk.vtkXMLPolyDataReader()
        reader.SetFileName(self.frame("links_00002.vtp"))
        reader.Update()
        lines = reader.GetOutput()
        self.assertEqual(lines.GetNumberOfLines(), self.links)
        self.assertEqual(self.links, 54)  # the 3 x 3 x 3 lattice's neighbour pairs
        neck = vtk_to_numpy(lines.GetCellData().GetArray("neck_radius"))
        self.assertEqual(len(neck), self.links)
        self.assertTrue((neck > 0).all())
        self.assertEqual(neck.dtype.itemsize, 8 if self.precision == "double" else 4)
        mean = neck.astype("d").mean()  # (a float32 sum would add its own rounding)
        self.assertAlmostEqual(mean / self.neck_mean, 1.0, delta=self.rounding)

    def test_fields_hold_the_spheres_volume(self):
        reader = vtk.vtkXMLImageDataReader()
        reader.SetFileName(self.frame("fields_00002.vti"))
        reader.Update()
        image = reader.GetOutput()
        self.assertEqual(image.GetDimensions(), (37, 37, 37))
        h = image.GetSpacing()[0]
        self.assertAlmostEqual(h, 12.5e-6, delta=1e-18)
        data = image.GetPointData()
        for name, components in (("solid_fraction", 1), ("density", 1), ("temperature", 1),
                                 ("velocity", 3), ("stress", 9)):
            self.assertEqual(data.GetArray(name).GetNumberOfComponents(), components, name)
        phi = vtk_to_numpy(data.GetArray("solid_fraction"))
        self.assertLess(abs(phi.sum() * h ** 3 / self.volume - 1), bound(5.0, 0.5) + self.rounding)
        temperature = vtk_to_numpy(data.GetArray("temperature"))
        held = temperature[phi > 1e-3 * phi.max()]
        self.assertTrue((abs(held - 1293) < 1293 * self.rounding).all())

    def test_profile_holds_the_spheres_volume(self):
        with open(self.frame("profile_z_00002.csv")) as f:
            rows = list(csv.reader(f))
        self.assertEqual(rows[0], ["position [m]", "solid_fraction [1]", "temperature [K]"])
        self.assertEqual(len(rows), 7)
        lamina = 450e-6 ** 2 * 75e-6
        total = sum(float(row[1]) for row in rows[1:]) * lamina
        self.assertAlmostEqual(total / self.volume, 1.0, delta=1e-12)


class CopperLatticeFilesSingle(CopperLatticeFiles):
    precision = "single"
    rounding = 2.0 ** -24 * 2  # one float rounding of each value, and of their mean


class CopperLatticeFilesAppended(CopperLatticeFiles):
    """The same arrays as raw appended data (`vtu_format = appended`), read by VTK to the bit."""
    format = "appended"

    def test_files_are_appended(self):
        for name in ("links_00002.vtp", "fields_00002.vti", "frame_00002.vtu"):
            with open(self.frame(name), "rb") as f:
                data = f.read()
            self.assertIn(b'<AppendedData encoding="raw">', data, name)
            self.assertIn(b'format="appended"', data, name)
            self.assertNotIn(b'format="binary"', data, name)
        reader = vtk.vtkXMLUnstructuredGridReader()
        reader.SetFileName(self.frame("frame_00002.vtu"))
        reader.Update()
        grid = reader.GetOutput()
        self.assertEqual(grid.GetNumberOfPoints(), 27)
        radius = vtk_to_numpy(grid.GetPointData().GetArray("radius"))
        self.assertTrue((radius == 25e-6).all())


if __name__ == "__main__":
    unittest.main()
