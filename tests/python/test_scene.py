"""Scenes, the neck model, packing helpers and output, from Python."""

import csv
import math
import os
import tempfile
import unittest

import sinter
from sinter import _lib

from _support import ArrayBackend, DROP_SCENE, as_lists, write_scene


class Stop(Exception):
    pass


class SceneTest(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.addCleanup(self.tmp.cleanup)
        self.ctx = sinter.Context()
        self.addCleanup(self.ctx.close)
        self.path = write_scene(self.tmp.name)

    def out(self, name="out"):
        return os.path.join(self.tmp.name, name)

    def test_load_and_run_with_progress(self):
        with sinter.Scene.load(self.ctx, self.path) as scene:
            self.assertEqual(scene.end_time, 0.01)
            n = len(scene.particles)
            self.assertGreater(n, 8)
            heights = [p[2] for p in as_lists(scene.particles.get("position"))]
            seen = []
            self.assertTrue(scene.run(self.out(), progress=lambda t, end: seen.append((t, end))))
            self.assertEqual(len(seen), 5)  # every output interval of 2 ms
            self.assertEqual(seen[-1], (0.01, 0.01))
            self.assertEqual(scene.stepper.time, 0.01)
            self.assertGreater(scene.stepper.stats.steps, 400)
            fallen = [p[2] for p in as_lists(scene.particles.get("position"))]
            self.assertLess(sum(fallen), sum(heights))  # gravity pulled them down
            with open(os.path.join(self.out(), "series.csv")) as series:
                rows = list(csv.reader(series))
            self.assertEqual(rows[0][0], "time [s]")
            self.assertEqual(rows[0][8], "floor force [N]")
            # then the stepper's columns: its time step, rejected steps and neighbour rebuilds,
            # and the solid fraction
            self.assertEqual(rows[0][-4:], ["time step [s]", "rejected steps [1]",
                                            "neighbour rebuilds [1]", "solid fraction [1]"])
            self.assertGreater(float(rows[-1][-2]), 0)
            # the spheres do not overlap much: the solid fraction is close to the volume
            # fraction, and not above it
            volume, solid = float(rows[-1][5]), float(rows[-1][-1])
            self.assertTrue(0.98 * volume < solid <= volume, (volume, solid))
            self.assertEqual(float(rows[-1][0]), 0.01)
            kinetic = [float(row[1]) for row in rows[1:]]
            self.assertLess(kinetic[-1], 0.1 * max(kinetic))  # landed, damped
            # The scene's stepper goes on after the run.
            self.assertEqual(scene.stepper.advance(0.012), 0.012)

    def test_progress_can_stop_the_run(self):
        scene = sinter.Scene(self.ctx, self.path)
        self.assertFalse(scene.run(self.out(), progress=lambda t, end: t >= 0.004))
        self.assertAlmostEqual(scene.stepper.time, 0.004, delta=1e-12)
        self.assertTrue(os.path.exists(os.path.join(self.out(), "series.csv")))

    def test_progress_exception_surfaces(self):
        scene = sinter.Scene(self.ctx, self.path)

        def progress(t, end):
            raise Stop(t)

        with self.assertRaises(Stop) as caught:
            scene.run(self.out(), progress=progress)
        self.assertAlmostEqual(caught.exception.args[0], 0.002, delta=1e-12)

    def test_python_model_added_to_a_scene(self):
        scene = sinter.Scene(self.ctx, self.path)
        pushes = []

        def push(state, force, torque):
            pushes.append(state.count)
            for i in range(state.count):
                force[i, 0] = 1e-6

        scene.stepper.add_force(sinter.ForceModel.from_callbacks(self.ctx, "push",
                                                                 particles=push))
        scene.stepper.advance(1e-3)
        self.assertEqual(set(pushes), {len(scene.particles)})
        self.assertTrue(all(v[0] > 0 for v in as_lists(scene.particles.get("velocity"))))

    def test_parse_error_names_file_and_line(self):
        broken = write_scene(self.tmp.name, DROP_SCENE.replace("normal = 0 0 1", "normal = 0 1"),
                             "broken.scene")
        with self.assertRaises(sinter.SinterError) as caught:
            sinter.Scene(self.ctx, broken)
        self.assertIs(caught.exception.status, sinter.Status.ERR_PARSE)
        self.assertIn("broken.scene:", caught.exception.message)
        with self.assertRaises(sinter.SinterError) as caught:
            sinter.Scene(self.ctx, os.path.join(self.tmp.name, "missing.scene"))
        self.assertIs(caught.exception.status, sinter.Status.ERR_IO)

    def test_check_refuses_a_particle_behind_a_wall(self):
        sinter.Scene(self.ctx, self.path).check()  # the drop scene is sound
        below = DROP_SCENE.replace("box_min = 0 0 0.0002", "box_min = 0 0 -0.0009")
        scene = sinter.Scene(self.ctx, write_scene(self.tmp.name, below, "below.scene"))
        with self.assertRaises(sinter.InvalidArgument) as caught:
            scene.check()
        self.assertIn("is behind wall 0 (floor)", caught.exception.message)


@unittest.skipIf("sinter_neck_two_particles" in _lib.missing_functions,
                 "the library has no sinter_neck_two_particles")
class NeckCases(ArrayBackend):
    def setUp(self):
        super().setUp()
        self.ctx = sinter.Context()
        self.addCleanup(self.ctx.close)

    def test_copper_pair_matches_reference(self):
        # docs/7dof.md sec. 6.2: copper, R = 25 um, 1293 K.
        copper = sinter.Material(self.ctx, "copper")
        model = sinter.NeckModel(self.ctx, rtol=1e-8)
        self.assertEqual(model["rtol"], 1e-8)
        result = model.two_particles(copper, 25e-6, 25e-6, 0.0, 1293.0, [1.0, 100.0, 5000.0],
                                     state=True)
        self.assertEqual(len(result.state), 3)
        self.assertEqual(len(result.state[0]), 7)
        for got, expected in zip(as_lists(result.neck_ratio), [0.0892, 0.1856, 0.3618]):
            self.assertAlmostEqual(got, expected, delta=2e-3 * expected)
        for got, expected in zip(as_lists(result.shrinkage), [3.49e-4, 3.47e-3, 2.123e-2]):
            self.assertAlmostEqual(got, expected, delta=1e-2 * expected)
        self.assertEqual(as_lists(result.time), [1.0, 100.0, 5000.0])
        stats = model.stats
        self.assertGreater(stats.steps, 10)
        self.assertEqual(stats.as_dict()["segments"], 1)

    def test_errors(self):
        copper = sinter.Material(self.ctx, "copper")
        model = sinter.NeckModel(self.ctx)
        with self.assertRaises(sinter.NotFound):
            model["no_such_option"] = 1.0
        with self.assertRaises(sinter.InvalidArgument):
            model.two_particles(copper, -1.0, 25e-6, 0.0, 1293.0, [1.0])
        with self.assertRaises(ValueError):
            model.two_particles(copper, 25e-6, 25e-6, [0.0, 1.0], [1293.0], [1.0])


class NeckNumpyTest(NeckCases, unittest.TestCase):
    use_numpy = True


class NeckListTest(NeckCases, unittest.TestCase):
    use_numpy = False


class PackingTest(unittest.TestCase):
    def setUp(self):
        self.ctx = sinter.Context()
        self.addCleanup(self.ctx.close)
        self.glass = sinter.Material(self.ctx, "glass", density=2500.0, youngs_modulus=1e7,
                                     damping_ratio=0.5)
        self.ps = sinter.Particles(self.ctx)
        self.ps.set_material(0, self.glass)

    def test_pack_random(self):
        lo, hi = (0.0, 0.0, 0.0), (0.01, 0.01, 0.01)
        placed = sinter.pack_random(self.ps, 50, lo, hi, radius=5e-4, distribution="uniform",
                                    spread=1e-4, gap=1e-5, seed=7, temperature=400.0)
        self.assertEqual(placed, 50)
        radii = as_lists(self.ps.get("radius"))
        for p, r in zip(as_lists(self.ps.get("position")), radii):
            for d in range(3):
                self.assertTrue(lo[d] + r <= p[d] <= hi[d] - r)
        self.assertTrue(all(4e-4 <= r <= 6e-4 for r in radii))
        self.assertEqual(set(as_lists(self.ps.get("temperature"))), {400.0})
        again = sinter.Particles(self.ctx)
        again.set_material(0, self.glass)
        sinter.pack_random(again, 50, lo, hi, radius=5e-4, distribution="uniform",
                           spread=1e-4, gap=1e-5, seed=7, temperature=400.0)
        self.assertEqual(as_lists(again.get("position")), as_lists(self.ps.get("position")))
        with self.assertRaises(TypeError):
            sinter.pack_random(self.ps, 1, lo, hi, colour="red")
        with self.assertRaises(sinter.InvalidArgument):
            sinter.pack_random(self.ps, 1, hi, lo)

    def test_pack_compact(self):
        """Loose spheres compacted to a cube half filled; bad options name themselves."""
        copper = sinter.Material(self.ctx, "copper", density=8960.0, youngs_modulus=72e9,
                                 poisson_ratio=0.3)
        ps = sinter.Particles(self.ctx)
        ps.set_material(0, copper)
        r = 25e-6
        self.assertEqual(sinter.pack_random(ps, 60, (0, 0, 0), (20 * r,) * 3, radius=r,
                                            seed=3), 60)
        side = (60 * 4.0 / 3.0 * math.pi * r ** 3 / 0.45) ** (1.0 / 3.0)
        before = as_lists(ps.get("position"))
        with self.assertRaises(sinter.InvalidArgument) as raised:
            sinter.pack_compact(ps, (0, 0, 0), (side,) * 3, friction=-1.0)
        self.assertIn("friction = -1", str(raised.exception))
        with self.assertRaises(TypeError):
            sinter.pack_compact(ps, (0, 0, 0), (side,) * 3, colour="red")
        self.assertEqual(as_lists(ps.get("position")), before)  # unchanged on error
        result = sinter.pack_compact(ps, (0, 0, 0), (side,) * 3, velocity=1.0)
        self.assertEqual(result["box_max"], [side] * 3)
        self.assertAlmostEqual(result["volume_fraction"], 0.45, places=12)
        self.assertFalse(result["jammed"])
        self.assertLess(result["max_overlap_ratio"], 0.01)
        for p in as_lists(ps.get("position")):
            for d in range(3):
                self.assertTrue(r * 0.85 <= p[d] <= side - r * 0.85)
        self.assertEqual(set(c for v in as_lists(ps.get("velocity")) for c in v), {0.0})

    def test_lattice_and_pour(self):
        r = 5e-4
        placed = sinter.pack_lattice(self.ps, (0, 0, 2 * r), (5 * r, 5 * r, 4 * r), r,
                                     spacing=2.1 * r)
        self.assertEqual(placed, len(self.ps))
        self.assertEqual(placed, 4)  # 2 x 2 x 1 centres fit in that box
        walls = sinter.Walls(self.ctx)
        walls.add_plane((0, 0, 0), (0, 0, 1), self.glass)
        st = sinter.Stepper(self.ctx, self.ps, walls, forces=[
            sinter.ForceModel(self.ctx, "hertz_mindlin"), sinter.ForceModel(self.ctx, "gravity")])
        st.dt = st.stable_dt_hertz(1.0)
        mass = as_lists(self.ps.get("mass"))[0]
        t = sinter.pour(st, 1e-3 * mass * 9.81 * r, t_min=0.01, t_max=0.5)
        self.assertTrue(0.01 <= t < 0.5)
        for p in as_lists(self.ps.get("position")):
            self.assertAlmostEqual(p[2], r, delta=0.05 * r)


class OutputTest(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.addCleanup(self.tmp.cleanup)
        self.ctx = sinter.Context()
        self.addCleanup(self.ctx.close)

    def test_series(self):
        with sinter.Series(self.ctx, [("time", "s"), ("temperature", "K"), "count"]) as series:
            for k in range(4):
                series.append([0.1 * k, 300.0 + k, float("nan") if k == 2 else k])
            self.assertEqual(len(series), 4)
            self.assertEqual(series[1, "temperature"], 301.0)
            self.assertEqual(series["time"][3], 0.1 * 3)
            self.assertTrue(math.isnan(series.get(2, 2)))
            self.assertEqual(series.units, ["s", "K", "1"])
            with self.assertRaises(ValueError):
                series.append([1.0])
            with self.assertRaises(KeyError):
                series.column("pressure")
            csv_path = os.path.join(self.tmp.name, "s.csv")
            svg_path = os.path.join(self.tmp.name, "s.svg")
            series.write_csv(csv_path)
            series.write_svg(svg_path, panels=[["temperature"], [2]], title="test")
        with open(csv_path) as f:
            self.assertEqual(f.readline().strip(), "time [s],temperature [K],count [1]")
        with open(svg_path) as f:
            self.assertIn("<svg", f.read())

    def test_vtu_and_pvd(self):
        material = sinter.Material(self.ctx)
        ps = sinter.Particles(self.ctx)
        ps.set_material(0, material)
        ps.add([(0, 0, 0), (1, 0, 0)], 0.1)
        frame = os.path.join(self.tmp.name, "f0.vtu")
        sinter.write_vtu(ps, frame, extra={"contacts": [0.0, 1.0],
                                           "arrow": [(1, 0, 0), (0, 1, 0)]})
        with open(frame) as f:
            text = f.read()
        self.assertIn('Name="contacts"', text)
        self.assertIn('Name="arrow"', text)
        with self.assertRaises(ValueError):
            sinter.write_vtu(ps, frame, extra={"bad": [1.0]})
        pvd = os.path.join(self.tmp.name, "all.pvd")
        sinter.write_pvd(self.ctx, pvd, [0.0], ["f0.vtu"])
        with open(pvd) as f:
            self.assertIn("f0.vtu", f.read())


if __name__ == "__main__":
    unittest.main()
