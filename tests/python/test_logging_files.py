"""Library messages reach Python's logging; missing files raise FileNotFoundError; unknown keys
name the valid ones."""

import logging
import os
import tempfile
import unittest

import sinter

from _support import write_scene


class _Records(logging.Handler):
    def __init__(self):
        super().__init__(logging.DEBUG)
        self.records = []

    def emit(self, record):
        self.records.append(record)


class LoggingTest(unittest.TestCase):
    def setUp(self):
        self.logger = logging.getLogger("sinter")
        self.handler = _Records()
        saved = (self.logger.level, self.logger.propagate)
        self.logger.addHandler(self.handler)
        self.logger.propagate = False

        def restore():
            self.logger.removeHandler(self.handler)
            self.logger.setLevel(saved[0])
            self.logger.propagate = saved[1]

        self.addCleanup(restore)

    def messages(self, level=None):
        return [r.getMessage() for r in self.handler.records
                if level is None or r.levelno == level]

    def test_messages_go_to_the_sinter_logger_at_its_level(self):
        self.logger.setLevel(logging.DEBUG)
        with sinter.Context() as ctx:  # the library logs every error's detail at DEBUG
            with self.assertRaises(sinter.InvalidArgument):
                ctx.threads = -1
        self.assertIn("sinter_ctx_set_threads: thread count -1 is negative",
                      self.messages(logging.DEBUG))
        self.assertEqual(self.handler.records[0].name, "sinter")

    def test_nothing_below_the_logger_level(self):
        self.logger.setLevel(logging.WARNING)
        with sinter.Context() as ctx:
            with self.assertRaises(sinter.InvalidArgument):
                ctx.threads = -1
        self.assertEqual(self.messages(), [])

    def test_level_change_followed_before_a_run(self):
        self.logger.setLevel(logging.WARNING)
        with sinter.Context() as ctx, tempfile.TemporaryDirectory() as directory:
            self.logger.setLevel(logging.INFO)  # after the context was made
            scene = write_scene(directory)
            with sinter.Scene(ctx, scene) as first:
                first.end_time = 0.004
                first.run(os.path.join(directory, "a"))
                first.write_checkpoint(os.path.join(directory, "a.bin"))
            with sinter.Scene(ctx, scene) as second:  # restarted into a fresh directory
                second.restart(os.path.join(directory, "a.bin"))
                second.end_time = 0.006
                second.run(os.path.join(directory, "b"))
        self.assertTrue(any(m.startswith("restart:") for m in self.messages(logging.INFO)),
                        self.messages())

    def test_another_logger_or_none(self):
        other = logging.getLogger("test_logging_files.other")
        handler = _Records()
        other.addHandler(handler)
        other.setLevel(logging.DEBUG)
        self.addCleanup(other.removeHandler, handler)
        with sinter.Context(logger=other) as ctx:
            with self.assertRaises(sinter.InvalidArgument):
                ctx.threads = -1
        self.assertEqual(len(handler.records), 1)
        self.logger.setLevel(logging.DEBUG)
        with sinter.Context(logger=None) as ctx:
            with self.assertRaises(sinter.InvalidArgument):
                ctx.threads = -1
        self.assertEqual(self.messages(), [])

    def test_level_mapping(self):
        self.assertEqual(sinter.LogLevel.from_logging(logging.DEBUG), sinter.LogLevel.DEBUG)
        self.assertEqual(sinter.LogLevel.from_logging(logging.INFO), sinter.LogLevel.INFO)
        self.assertEqual(sinter.LogLevel.from_logging(logging.WARNING), sinter.LogLevel.WARNING)
        self.assertEqual(sinter.LogLevel.from_logging(logging.CRITICAL), sinter.LogLevel.ERROR)
        self.assertEqual(sinter.LogLevel.INFO.logging_level, logging.INFO)


class MissingFileTest(unittest.TestCase):
    def setUp(self):
        self.ctx = sinter.Context()
        self.addCleanup(self.ctx.close)
        self.directory = tempfile.mkdtemp()
        self.missing = os.path.join(self.directory, "missing")

    def tearDown(self):
        import shutil
        shutil.rmtree(self.directory)

    def assert_not_found(self, call):
        with self.assertRaises(FileNotFoundError) as caught:
            call()
        self.assertIsInstance(caught.exception, sinter.SinterError)
        self.assertEqual(caught.exception.filename, self.missing)
        self.assertIn("missing", str(caught.exception))
        return caught.exception

    def test_scene(self):
        self.assert_not_found(lambda: sinter.Scene(self.ctx, self.missing))

    def test_checkpoints(self):
        with sinter.Scene(self.ctx, write_scene(self.directory)) as scene:
            self.assert_not_found(lambda: scene.restart(self.missing))
            self.assert_not_found(lambda: scene.stepper.read_checkpoint(self.missing))

    def test_series_and_plot(self):
        self.assert_not_found(lambda: sinter.Series.read_csv(self.ctx, self.missing))
        self.assert_not_found(lambda: sinter.plot_run(self.ctx, self.missing))

    def test_existing_but_bad_file_is_not_file_not_found(self):
        path = os.path.join(self.directory, "bad.scene")
        with open(path, "w") as bad:
            bad.write("[nonsense\n")
        with self.assertRaises(sinter.SinterError) as caught:
            sinter.Scene(self.ctx, path)
        self.assertNotIsInstance(caught.exception, FileNotFoundError)


class SeriesReadTest(unittest.TestCase):
    def test_read_back(self):
        with sinter.Context() as ctx, tempfile.TemporaryDirectory() as directory:
            path = os.path.join(directory, "t.csv")
            with sinter.Series(ctx, [("time", "s"), ("temperature", "K"), "count"]) as series:
                series.append([0.0, 300.0, 1.0])
                series.append([1.0, 310.5, 2.0])
                series.write_csv(path)
            with sinter.Series.read_csv(ctx, path) as back:
                self.assertEqual(back.columns, ["time", "temperature", "count"])
                self.assertEqual(back.units, ["s", "K", "1"])
                self.assertEqual(back.rows, 2)
                self.assertEqual(back["temperature"], [300.0, 310.5])


class EnumArgumentTest(unittest.TestCase):
    def test_enums_stand_for_names(self):
        with sinter.Context() as ctx:
            material = sinter.Material(ctx, "m", density=3000.0)
            self.assertEqual(material[sinter.MaterialParam.DENSITY], 3000.0)
            material[sinter.MaterialParam.EMISSIVITY] = 0.5
            self.assertEqual(material["emissivity"], 0.5)
            particles = sinter.Particles(ctx)
            particles.set_material(0, material)
            particles.add([(0.0, 0.0, 0.0)], [1e-3])
            self.assertEqual(list(particles.get(sinter.Field.RADIUS)), [1e-3])
            particles.set(sinter.Field.FLAGS, [sinter.ParticleFlag.FIXED
                                               | sinter.ParticleFlag.NO_ROTATION])
            self.assertEqual(sinter.ParticleFlag(list(particles.get("flags"))[0]),
                             sinter.ParticleFlag.FIXED | sinter.ParticleFlag.NO_ROTATION)
            walls = sinter.Walls(ctx)
            walls.add_plane((0, 0, 0), (0, 0, 1), material)
            walls.set_electric(0, sinter.WallElectric.CURRENT, 2.0)
            walls.set_electric(0, "potential", 1.0)
            with sinter.Stepper(ctx, particles, walls, kind=sinter.StepperKind.EXPLICIT,
                                thermal=sinter.ThermalScheme.IMPLICIT) as stepper:
                self.assertIs(stepper.thermal_scheme, sinter.ThermalScheme.IMPLICIT)


class UnknownKeyTest(unittest.TestCase):
    def setUp(self):
        self.ctx = sinter.Context()
        self.addCleanup(self.ctx.close)

    def assert_lists(self, call, *keys):
        with self.assertRaises(sinter.NotFound) as caught:
            call()
        for key in keys:
            self.assertIn(key, str(caught.exception))

    def test_every_kind_of_key(self):
        self.assert_lists(lambda: sinter.Material(self.ctx, "m", {"densty": 1.0}), "density",
                          "youngs_modulus")
        self.assert_lists(lambda: sinter.ForceModel(self.ctx, "gravity", gq=1.0), "gx", "gz")
        self.assert_lists(lambda: sinter.ForceModel(self.ctx, "gravty"), "gravity",
                          "hertz_mindlin")
        self.assert_lists(lambda: sinter.HeatModel(self.ctx, "laser", intensty=1.0),
                          "intensity", "attenuation")
        self.assert_lists(lambda: sinter.ElectricModel(self.ctx, "network", tol=1.0),
                          "tolerance", "max_iterations")
        self.assert_lists(lambda: sinter.NeckModel(self.ctx, {"rtl": 1.0}), "rtol", "epsilon")
        particles = sinter.Particles(self.ctx)
        particles.set_material(0, sinter.Material(self.ctx, "m"))
        with sinter.Stepper(self.ctx, particles, kind="staggered") as stepper:
            self.assert_lists(lambda: stepper.set_option("phy", 0.5), "phi", "tolerance")
        with sinter.Stepper(self.ctx, particles, kind="quasistatic") as stepper:
            self.assert_lists(lambda: stepper.set_option("strategy", 2), "qs_strategy")


if __name__ == "__main__":
    unittest.main()
