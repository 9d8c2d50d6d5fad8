"""Snapshots of contacts and links from Python: NumPy arrays or memoryviews, copied."""

import base64
import math
import os
import struct
import tempfile
import unittest
import xml.etree.ElementTree as ET

import sinter
from sinter import snapshot as snapshot_module

from _support import DROP_SCENE, ArrayBackend, as_lists, write_scene

G = 9.81


def flat(array):
    """Rows of a 2-D array (NumPy or memoryview) as lists."""
    return [list(row) for row in as_lists(array)]


class SnapshotCases(ArrayBackend):
    """Four columns of three spheres settled on a floor: the contact forces against the wall's reaction and
    the particles' forces, and the links of a quasi-static pair."""

    def make_pile(self, steps=4000):
        ctx = sinter.Context()
        self.addCleanup(ctx.close)
        material = sinter.Material(ctx, "glass", youngs_modulus=1e7, poisson_ratio=0.3,
                                   density=2500.0, damping_ratio=0.3, friction_static=0.3,
                                   friction_dynamic=0.3)
        particles = sinter.Particles(ctx)
        particles.set_material(0, material)
        walls = sinter.Walls(ctx)
        walls.add_plane((0, 0, 0), (0, 0, 1), material)
        stepper = sinter.Stepper(ctx, particles, walls, dt=1e-5,
                                 forces=[sinter.ForceModel(ctx, "hertz_mindlin"),
                                         sinter.ForceModel(ctx, "gravity")])
        # four columns of three spheres, slightly pressed together
        particles.add([(2.5e-3 * (k % 2), 2.5e-3 * ((k // 2) % 2), 0.999e-3 + 1.998e-3 * (k // 4))
                       for k in range(12)], 1e-3)
        if steps is not None:
            stepper.step(steps)
        return ctx, particles, walls, stepper

    def test_contact_forces_sum_to_the_wall_and_the_particles(self):
        _, particles, walls, stepper = self.make_pile()
        snap = stepper.snapshot()
        self.assertEqual(snap.time, stepper.time)
        self.assertGreater(snap.pair_contacts, 0)
        self.assertGreater(snap.wall_contacts, 0)
        self.assertEqual(snap.link_count, 0)
        c = snap.contacts
        self.assertEqual(set(c), set(snapshot_module.CONTACT_DATA))
        total = snap.pair_contacts + snap.wall_contacts
        for name in snapshot_module.CONTACT_DATA:
            self.assertEqual(len(c[name]), total, name)
        if self.use_numpy:
            self.assertEqual(c["normal"].shape, (total, 3))
            self.assertEqual(c["id_a"].dtype.kind, "u")
        else:
            self.assertIsInstance(c["normal"], memoryview)
        normal, tangential = flat(c["normal"]), flat(c["tangential_force"])
        fn, wall = as_lists(c["normal_force"]), as_lists(c["wall"])
        ids = as_lists(particles.get("id"))
        index = {identity: k for k, identity in enumerate(ids)}
        mass, force = as_lists(particles.get("mass")), flat(particles.get("force"))
        sums = [[0.0, 0.0, -m * G] for m in mass]
        floor = [0.0, 0.0, 0.0]
        for q in range(total):
            f = [tangential[q][d] - fn[q] * normal[q][d] for d in range(3)]
            a = index[c["id_a"][q]]
            for d in range(3):
                sums[a][d] += f[d]
            if q < snap.pair_contacts:
                self.assertEqual(wall[q], -1)
                b = index[c["id_b"][q]]
                for d in range(3):
                    sums[b][d] -= f[d]
            else:
                self.assertEqual(wall[q], 0)
                for d in range(3):
                    floor[d] -= f[d]
        weight = sum(mass) * G
        reaction = walls.force(0) if hasattr(walls, "force") else None
        if reaction is not None:
            for d in range(3):
                self.assertAlmostEqual(floor[d], reaction[d], delta=1e-9 * weight)
        self.assertAlmostEqual(floor[2], -weight, delta=0.05 * weight)  # at rest: the weight
        for i in range(len(mass)):
            for d in range(3):
                self.assertAlmostEqual(sums[i][d], force[i][d], delta=1e-9 * weight)

    def test_copies_survive_the_stepper(self):
        ctx, _, _, stepper = self.make_pile(steps=100)
        snap = stepper.snapshot()
        before = as_lists(snap.contacts["overlap"])
        stepper.step(100)
        ctx.close()
        self.assertEqual(as_lists(snap.contacts["overlap"]), before)
        self.assertIn("pair_contacts", repr(snap))

    def test_stale_state_is_refused(self):
        _, particles, _, stepper = self.make_pile(steps=None)
        with self.assertRaises(sinter.SinterError) as caught:
            stepper.snapshot()
        self.assertEqual(caught.exception.status, sinter.Status.ERR_STATE)
        stepper.step(1)
        stepper.snapshot()
        with particles.view("position"):
            pass
        with self.assertRaises(sinter.SinterError):
            stepper.snapshot()
        stepper.step(0)
        self.assertGreater(stepper.snapshot().wall_contacts, 0)

    def test_links_of_a_quasistatic_pair(self):
        ctx = sinter.Context()
        self.addCleanup(ctx.close)
        copper = sinter.Material(ctx, "copper", youngs_modulus=72e9, density=8960.0)
        particles = sinter.Particles(ctx)
        particles.set_material(0, copper)
        r = 25e-6
        particles.add([(0.0, 0.0, 0.0), (2 * r, 0.0, 0.0)], r, temperature=1293.0)
        stepper = sinter.Stepper(ctx, particles, kind="quasistatic")
        stepper.advance(100.0)
        snap = stepper.snapshot()
        self.assertEqual(snap.pair_contacts + snap.wall_contacts, 0)
        self.assertEqual(snap.link_count, stepper.sintering_stats().links)
        links = snap.links
        self.assertEqual(set(links), set(snapshot_module.LINK_DATA))
        self.assertEqual(sorted([links["id_a"][0], links["id_b"][0]]), [0, 1])
        self.assertAlmostEqual(links["neck_ratio"][0], stepper.sintering_stats().neck_ratio_mean,
                               delta=1e-12)
        self.assertAlmostEqual(links["neck_radius"][0], links["neck_ratio"][0] * r, delta=1e-15)
        self.assertEqual(len(flat(links["beam_force"])[0]), 3)


class FrameFilesTest(unittest.TestCase):
    """[output] contacts = yes, walls = yes: beside each frame a .vtp of lines (one per contact)
    and one of polygons (one per wall), well-formed, listed in the .pvd as parts 1 and 2."""

    def test_contacts_and_walls_files(self):
        for vtu_format in ("binary", "ascii"):
            with self.subTest(vtu_format=vtu_format):
                self.check_files(vtu_format)

    @staticmethod
    def values(array):
        """The numbers of a DataArray, ascii or inline binary (base64, UInt64 byte count)."""
        if array.get("format") == "ascii":
            kind = float if array.get("type").startswith("Float") else int
            return [kind(v) for v in (array.text or "").split()]
        text = "".join((array.text or "").split())
        size = int.from_bytes(base64.b64decode(text[:12]), "little")
        data = base64.b64decode(text[12:])
        assert len(data) == size, (len(data), size)
        code = {"Float64": "d", "Int64": "q", "UInt64": "Q", "Int32": "i"}[array.get("type")]
        return list(struct.unpack("<%d%s" % (size // struct.calcsize(code), code), data))

    def test_wall_kinds_drawn(self):
        """A disc floor, a rectangle and a finite cylinder around the drop: the walls' .vtp has
        one polygon for the disc (32 points on its rim), one for the rectangle (its 4 corners)
        and 32 quads for the cylinder, each cell naming its wall."""
        tmp = tempfile.TemporaryDirectory()
        self.addCleanup(tmp.cleanup)
        text = DROP_SCENE.replace("vtu = no", "vtu = yes\nwalls = yes\nvtu_format = ascii").replace(
            "[wall floor]\npoint = 0 0 0\nnormal = 0 0 1\n",
            "[wall floor]\nkind = disc\npoint = 0.00175 0.00175 0\nnormal = 0 0 1\n"
            "radius = 0.004\nmaterial = glass\n"
            "[wall shelf]\nkind = rectangle\npoint = 0.00175 0.00175 -0.001\nnormal = 0 0 1\n"
            "edge = 1 0 0\nhalf_lengths = 0.003 0.002\nmaterial = glass\n"
            "[wall die]\nkind = cylinder\npoint = 0.00175 0.00175 0\naxis = 0 0 1\n"
            "radius = 0.004\nhalf_length = 0.004\n")
        path = write_scene(tmp.name, text)
        out = os.path.join(tmp.name, "out")
        ctx = sinter.Context()
        self.addCleanup(ctx.close)
        with sinter.Scene.load(ctx, path) as scene:
            scene.run(out)
        walls = sorted(f for f in os.listdir(os.path.join(out, "frames")) if f.startswith("walls_"))
        piece = ET.parse(os.path.join(out, "frames", walls[-1])).find("PolyData/Piece")
        self.assertEqual(int(piece.get("NumberOfPolys")), 1 + 1 + 32)
        self.assertEqual(int(piece.get("NumberOfPoints")), 32 + 4 + 4 * 32)
        index = self.values(piece.find("CellData/DataArray[@Name='wall']"))
        self.assertEqual(index, [0, 1] + [2] * 32)
        offsets = self.values(piece.find("Polys/DataArray[@Name='offsets']"))
        self.assertEqual(offsets[:3], [32, 36, 40])
        points = self.values(piece.find("Points/DataArray"))
        rim = [math.hypot(points[3 * k] - 0.00175, points[3 * k + 1] - 0.00175) for k in range(32)]
        self.assertAlmostEqual(min(rim), 0.004, delta=1e-15)
        self.assertAlmostEqual(max(rim), 0.004, delta=1e-15)

    def check_files(self, vtu_format):
        tmp = tempfile.TemporaryDirectory()
        self.addCleanup(tmp.cleanup)
        text = DROP_SCENE.replace("vtu = no", "vtu = yes\ncontacts = yes\nwalls = yes\n"
                                  "vtu_format = " + vtu_format).replace(
            "end_time = 0.01", "end_time = 0.03")  # landed on the floor
        self.assertIn("contacts = yes", text)
        path = write_scene(tmp.name, text)
        out = os.path.join(tmp.name, "out")
        ctx = sinter.Context()
        self.addCleanup(ctx.close)
        with sinter.Scene.load(ctx, path) as scene:
            scene.run(out)
            snap = scene.stepper.snapshot()
        values = self.values
        frames = sorted(os.listdir(os.path.join(out, "frames")))
        contacts = [f for f in frames if f.startswith("contacts_")]
        walls = [f for f in frames if f.startswith("walls_")]
        particles = [f for f in frames if f.startswith("frame_")]
        self.assertEqual(len(contacts), len(particles))
        self.assertEqual(len(walls), len(particles))
        # the last frame is the state the snapshot was taken of
        tree = ET.parse(os.path.join(out, "frames", contacts[-1]))
        self.assertEqual(tree.getroot().get("type"), "PolyData")
        piece = tree.find("PolyData/Piece")
        lines = int(piece.get("NumberOfLines"))
        self.assertEqual(lines, snap.pair_contacts + snap.wall_contacts)
        self.assertGreater(snap.wall_contacts, 0)
        self.assertEqual(int(piece.get("NumberOfPoints")), 2 * lines)
        points = piece.find("Points/DataArray")
        self.assertEqual(len(values(points)), 3 * 2 * lines)
        connectivity = piece.find("Lines/DataArray[@Name='connectivity']")
        offsets = piece.find("Lines/DataArray[@Name='offsets']")
        self.assertEqual(values(connectivity), list(range(2 * lines)))
        self.assertEqual(values(offsets), [2 * (k + 1) for k in range(lines)])
        arrays = {a.get("Name"): a for a in piece.find("CellData")}
        self.assertEqual(set(arrays), set(snapshot_module.CONTACT_DATA))
        for name, array in arrays.items():
            components = int(array.get("NumberOfComponents", "1"))
            self.assertEqual(len(values(array)), lines * components, name)
        self.assertEqual(values(arrays["normal_force"]),
                         [float(v) for v in as_lists(snap.contacts["normal_force"])])
        self.assertEqual(values(arrays["id_a"]), [int(v) for v in as_lists(snap.contacts["id_a"])])
        # the walls: one polygon (the floor) clipped to the particles' box, in its plane
        tree = ET.parse(os.path.join(out, "frames", walls[-1]))
        piece = tree.find("PolyData/Piece")
        self.assertEqual(int(piece.get("NumberOfPolys")), 1)
        corners = values(piece.find("Points/DataArray"))
        self.assertEqual(int(piece.get("NumberOfPoints")), 4)
        self.assertEqual(len(corners), 3 * 4)
        self.assertEqual(corners[2::3], [0.0] * 4)  # z = 0: the floor's plane
        self.assertEqual(values(piece.find("Polys/DataArray[@Name='offsets']")), [4])
        # the collection: each time three parts
        pvd = [d.attrib for d in ET.parse(os.path.join(out, "drop.pvd")).iter("DataSet")]
        self.assertEqual(len(pvd), 3 * len(particles))
        for k in range(len(particles)):
            group = pvd[3 * k:3 * k + 3]
            self.assertEqual([d["part"] for d in group], ["0", "1", "2"])
            self.assertEqual(len({d["timestep"] for d in group}), 1)
            self.assertEqual(group[1]["file"], "frames/" + contacts[k])


class SnapshotNumpy(SnapshotCases, unittest.TestCase):
    use_numpy = True


class SnapshotMemoryview(SnapshotCases, unittest.TestCase):
    use_numpy = False


if __name__ == "__main__":
    unittest.main()
