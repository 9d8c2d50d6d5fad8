"""Context: settings, errors, logging and the life cycle of handles."""

import gc
import unittest
from unittest import mock

import sinter
from sinter import _lib


class ContextTest(unittest.TestCase):
    def setUp(self):
        self.ctx = sinter.Context()
        self.addCleanup(self.ctx.close)

    def test_threads(self):
        self.assertEqual(self.ctx.threads, 1)
        self.ctx.threads = 4
        self.assertEqual(self.ctx.threads, 4)
        self.assertEqual(sinter.Context(threads=0).threads, 0)

    def test_error_carries_library_message(self):
        with self.assertRaises(sinter.InvalidArgument) as caught:
            self.ctx.threads = -2
        error = caught.exception
        self.assertIs(error.status, sinter.Status.ERR_INVALID)
        self.assertEqual(error.message, "sinter_ctx_set_threads: thread count -2 is negative")
        self.assertIn(error.message, str(error))
        self.assertEqual(self.ctx.last_error, error.message)
        self.assertIs(self.ctx.last_status, sinter.Status.ERR_INVALID)
        self.ctx.clear_error()
        self.assertEqual(self.ctx.last_error, "")
        self.assertIs(self.ctx.last_status, sinter.Status.OK)

    def test_log_callback_receives_error_detail(self):
        received = []
        self.ctx.set_log(lambda level, message: received.append((level, message)),
                         sinter.LogLevel.DEBUG)
        gc.collect()  # the callback object must be kept alive by the context
        with self.assertRaises(sinter.InvalidArgument):
            self.ctx.threads = -1
        self.assertEqual(received, [(sinter.LogLevel.DEBUG,
                                     "sinter_ctx_set_threads: thread count -1 is negative")])
        self.ctx.set_log(None)
        with self.assertRaises(sinter.InvalidArgument):
            self.ctx.threads = -1
        self.assertEqual(len(received), 1)

    def test_log_level_out_of_range(self):
        with self.assertRaises(sinter.InvalidArgument) as caught:
            self.ctx.set_log(print, 7)
        self.assertIn("log level 7", caught.exception.message)


class LifeCycleTest(unittest.TestCase):
    def test_context_manager_closes(self):
        with sinter.Context() as ctx:
            self.assertFalse(ctx.closed)
        self.assertTrue(ctx.closed)
        with self.assertRaisesRegex(ValueError, "closed"):
            ctx.threads
        ctx.close()  # twice is fine

    def test_closing_context_closes_its_objects_first(self):
        ctx = sinter.Context()
        material = sinter.Material(ctx, "a")
        particles = sinter.Particles(ctx)
        with sinter.Particles(ctx) as closed_early:
            pass
        self.assertTrue(closed_early.closed)
        ctx.close()
        self.assertTrue(material.closed and particles.closed and ctx.closed)
        with self.assertRaisesRegex(ValueError, "Material is closed"):
            material["density"]
        with self.assertRaisesRegex(ValueError, "Particles is closed"):
            len(particles)

    def test_objects_keep_their_context_alive(self):
        particles = sinter.Particles(sinter.Context())
        gc.collect()
        self.assertFalse(particles.context.closed)
        self.assertEqual(len(particles), 0)
        particles.close()

    def record_destroy_calls(self):
        """Wrap the C destroy functions; return the list of names they append to."""
        calls = []
        for name in ("sinter_ctx_destroy", "sinter_material_destroy", "sinter_particles_destroy"):
            def record(handle, name=name, original=getattr(_lib.lib, name)):
                calls.append(name)
                original(handle)

            patcher = mock.patch.object(_lib.lib, name, record)
            patcher.start()
            self.addCleanup(patcher.stop)
        return calls

    def test_finalized_context_waits_for_its_objects(self):
        calls = self.record_destroy_calls()
        ctx = sinter.Context()
        particles = sinter.Particles(ctx)
        ctx.__del__()  # as the garbage collector may do first in a reference cycle
        self.assertTrue(ctx.closed)
        self.assertEqual(calls, [])
        particles.close()
        self.assertEqual(calls, ["sinter_particles_destroy", "sinter_ctx_destroy"])

    def test_garbage_cycle_destroys_context_last(self):
        calls = self.record_destroy_calls()
        ctx = sinter.Context()
        ctx.cycle = (sinter.Particles(ctx), sinter.Material(ctx))
        del ctx
        gc.collect()
        self.assertEqual(sorted(calls[:2]),
                         ["sinter_material_destroy", "sinter_particles_destroy"])
        self.assertEqual(calls[2:], ["sinter_ctx_destroy"])

    def test_objects_of_a_closed_context_cannot_be_made(self):
        ctx = sinter.Context()
        ctx.close()
        with self.assertRaises(ValueError):
            sinter.Material(ctx)
        with self.assertRaises(ValueError):
            sinter.Particles(ctx)


if __name__ == "__main__":
    unittest.main()
