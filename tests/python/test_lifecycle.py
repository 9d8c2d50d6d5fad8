"""Handles as context managers; what a stepper or scene borrows stays alive; safe teardown."""

import gc
import tempfile
import unittest
from unittest import mock

import sinter
from sinter import _lib

from _support import write_scene

DESTROY_FUNCTIONS = ("sinter_ctx_destroy", "sinter_material_destroy", "sinter_particles_destroy",
                     "sinter_walls_destroy", "sinter_force_model_destroy",
                     "sinter_heat_model_destroy", "sinter_electric_model_destroy",
                     "sinter_stepper_destroy", "sinter_scene_destroy", "sinter_series_destroy",
                     "sinter_neck_model_destroy")


def build(ctx):
    """A particle set, walls, two force models, a heat model and a stepper over them."""
    material = sinter.Material(ctx, youngs_modulus=1e7)
    ps = sinter.Particles(ctx)
    ps.set_material(0, material)
    ps.add([(0.0, 0.0, 1.2e-3)], 1e-3)
    walls = sinter.Walls(ctx)
    walls.add_plane((0, 0, 0), (0, 0, 1), material)
    stepper = sinter.Stepper(ctx, ps, walls, dt=1e-5,
                             forces=[sinter.ForceModel(ctx, "hertz_mindlin"),
                                     sinter.ForceModel(ctx, "gravity")],
                             heat=[sinter.HeatModel(ctx, "conduction")])
    return material, ps, walls, stepper


class LifeCycleTest(unittest.TestCase):
    def record_destroy_calls(self):
        calls = []
        for name in DESTROY_FUNCTIONS:
            if name in _lib.missing_functions:
                continue

            def record(handle, name=name, original=getattr(_lib.lib, name)):
                calls.append(name.replace("sinter_", "").replace("_destroy", ""))
                original(handle)

            patcher = mock.patch.object(_lib.lib, name, record)
            patcher.start()
            self.addCleanup(patcher.stop)
        return calls

    def assert_stepper_first_context_last(self, calls):
        self.assertEqual(calls[-1], "ctx")
        for borrowed in ("particles", "walls", "force_model", "heat_model"):
            self.assertLess(calls.index("stepper"), calls.index(borrowed), calls)

    def test_every_handle_is_a_context_manager(self):
        with sinter.Context() as ctx:
            objects = [sinter.Walls(ctx), sinter.ForceModel(ctx, "gravity"),
                       sinter.HeatModel(ctx, "radiation"), sinter.ElectricModel(ctx, "averaged"),
                       sinter.Series(ctx, ["x"])]
            if "sinter_neck_model_create" not in _lib.missing_functions:
                objects.append(sinter.NeckModel(ctx))
            for handle in objects:
                with handle as same:
                    self.assertIs(same, handle)
                    self.assertFalse(handle.closed)
                self.assertTrue(handle.closed)
                handle.close()  # twice is fine
                self.assertIn("closed", repr(handle))
            with sinter.Particles(ctx) as ps:
                with sinter.Stepper(ctx, ps) as st:
                    st.advance(1e-4)
                self.assertTrue(st.closed)
                with self.assertRaisesRegex(ValueError, "Stepper is closed"):
                    st.advance(1.0)
        self.assertTrue(ctx.closed)

    def test_stepper_keeps_what_it_borrows_alive(self):
        ctx = sinter.Context()
        self.addCleanup(ctx.close)
        stepper = build(ctx)[3]
        gc.collect()  # nothing but the stepper refers to the particles, walls and models
        stepper.advance(8e-3)
        self.assertEqual(len(stepper.particles), 1)
        self.assertEqual(len(stepper.forces), 2)
        with stepper.particles.view("velocity") as v:
            self.assertGreater(v[0, 2], 0.0)  # bounced off the floor (undamped Hertz)

    def test_closing_a_borrowed_object_waits_for_the_stepper(self):
        calls = self.record_destroy_calls()
        ctx = sinter.Context()
        material, ps, walls, stepper = build(ctx)
        ps.close()
        stepper.forces[0].close()
        self.assertTrue(ps.closed)
        with self.assertRaisesRegex(ValueError, "Particles is closed"):
            len(ps)
        self.assertEqual(calls, [])  # the stepper still uses them
        stepper.advance(1e-3)  # and still works
        stepper.close()
        self.assertEqual(sorted(calls), ["force_model", "particles", "stepper"])
        self.assertEqual(calls[0], "stepper")
        ctx.close()
        self.assert_stepper_first_context_last(calls)

    def test_context_close_tears_down_in_a_safe_order(self):
        calls = self.record_destroy_calls()
        ctx = sinter.Context()
        objects = build(ctx)
        ctx.close()
        self.assertTrue(all(o.closed for o in objects))
        self.assert_stepper_first_context_last(calls)
        self.assertEqual(calls.count("force_model"), 2)

    def test_garbage_cycle_tears_down_in_a_safe_order(self):
        calls = self.record_destroy_calls()
        ctx = sinter.Context()
        ctx.cycle = build(ctx)  # the context refers to its objects, and they to it
        ctx.cycle[3].observer = lambda stepper, t: None
        del ctx
        gc.collect()
        self.assert_stepper_first_context_last(calls)

    def test_replaced_electric_model_is_released(self):
        calls = self.record_destroy_calls()
        with sinter.Context() as ctx:
            stepper = build(ctx)[3]
            first = sinter.ElectricModel(ctx, "averaged")
            stepper.electric = first
            first.close()
            self.assertNotIn("electric_model", calls)  # still in use
            stepper.electric = sinter.ElectricModel(ctx, "network")
            self.assertEqual(calls.count("electric_model"), 1)

    def test_scene_views_keep_the_scene_and_close_with_it(self):
        calls = self.record_destroy_calls()
        with tempfile.TemporaryDirectory() as tmp:
            ctx = sinter.Context()
            self.addCleanup(ctx.close)
            path = write_scene(tmp)
            particles = sinter.Scene(ctx, path).particles  # the scene itself is dropped
            gc.collect()
            self.assertEqual(calls, [])
            self.assertGreater(len(particles), 0)
            scene = sinter.Scene(ctx, path)
            stepper, walls = scene.stepper, scene.walls
            self.assertIs(stepper.particles, scene.particles)
            self.assertIs(stepper.walls, walls)
            scene.close()  # closes its views; destroys the C scene, never its parts
            self.assertTrue(stepper.closed and walls.closed and stepper.particles.closed)
            self.assertEqual(calls, ["scene"])
            particles.close()
            self.assertEqual(calls, ["scene", "scene"])

    def test_callbacks_given_to_scene_views_live_with_the_scene(self):
        with tempfile.TemporaryDirectory() as tmp, sinter.Context() as ctx:
            scene = sinter.Scene(ctx, write_scene(tmp))
            scene.walls.set_callback(0, lambda t: ((0, 0, -t), (0, 0, -1.0)))
            times = []
            scene.stepper.observer = lambda stepper, t: times.append(t)
            scene.stepper.add_force(sinter.ForceModel.from_callbacks(
                ctx, "nothing", particles=lambda state, force, torque: None))
            gc.collect()  # the views above are gone; their C objects and callbacks are not
            scene.stepper.advance(1e-3)
            self.assertEqual(len(times), scene.stepper.stats.steps)
            self.assertEqual(scene.walls.state(0)[0], (0.0, 0.0, -1e-3))
            self.assertEqual(len(scene.stepper.forces), 1)

    def test_user_stepper_over_scene_particles_delays_the_scene(self):
        calls = self.record_destroy_calls()
        with tempfile.TemporaryDirectory() as tmp:
            ctx = sinter.Context()
            self.addCleanup(ctx.close)
            scene = sinter.Scene(ctx, write_scene(tmp))
            mine = sinter.Stepper(ctx, scene.particles, dt=1e-5,
                                  forces=[sinter.ForceModel(ctx, "gravity")])
            scene.close()
            self.assertEqual(calls, [])
            mine.advance(1e-4)
            mine.close()
            self.assertEqual(calls[:2], ["stepper", "scene"])


if __name__ == "__main__":
    unittest.main()
