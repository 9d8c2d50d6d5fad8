"""Bad input that used to get through the binding (issue 35): integers too large for their C
type wrapped around, and a NumPy view kept after its particle set was closed wrote into
freed memory."""

import gc
import unittest

import sinter
import sinter.particles

from _support import ArrayBackend

try:
    import cffi
except ImportError:
    cffi = None


class IntegerOverflowTest(unittest.TestCase):
    """ctypes keeps an integer's low bits; the binding raises OverflowError instead."""

    def setUp(self):
        self.ctx = sinter.Context()
        self.addCleanup(self.ctx.close)
        self.steel = sinter.Material(self.ctx, "steel", density=7800.0)
        self.ps = sinter.Particles(self.ctx)
        self.ps.set_material(0, self.steel)

    def test_material_id_past_int32(self):
        with self.assertRaises(OverflowError) as caught:
            self.ps.set_material(2**40, self.steel)  # was material 0
        self.assertIn("sinter_particles_set_material argument 2", str(caught.exception))
        with self.assertRaises(OverflowError):
            self.ps.add([(0.0, 0.0, 0.0)], 1e-3, material_id=2**40)
        with self.assertRaises(OverflowError):
            self.ps.add([(0.0, 0.0, 0.0)], 1e-3, material_id=-2**31 - 1)
        self.assertEqual(self.ps.count, 0)
        self.ps.add([(0.0, 0.0, 0.0)], 1e-3, material_id=0)  # in range: fine
        self.assertEqual(self.ps.count, 1)

    def test_negative_and_huge_sizes(self):
        with self.assertRaises(OverflowError):
            self.ps.reserve(-1)  # was SIZE_MAX
        with self.assertRaises(OverflowError):
            self.ps.reserve(2**64)
        with self.assertRaises(OverflowError):
            self.ps.find_id(-1)
        with self.assertRaises(OverflowError):
            self.ctx.threads = 2**32  # was 0: every core

    def test_struct_fields(self):
        with self.assertRaises(OverflowError):
            sinter.packing_options(material=2**40)
        with self.assertRaises(OverflowError):
            sinter.packing_options(seed=-1)
        self.assertEqual(sinter.packing_options(seed=2**64 - 1).seed, 2**64 - 1)


@unittest.skipIf(cffi is None, "cffi is not installed for this interpreter")
class IntegerOverflowThroughCffiTest(unittest.TestCase):
    """The cffi backend refuses the same integers (cffi checks them itself)."""

    def test_material_id_past_int32(self):
        from sinter import cffi_backend
        ffi, lib = cffi_backend.load()
        ctx_out = ffi.new("sinter_ctx **")
        self.assertEqual(lib.sinter_ctx_create(ctx_out, ffi.NULL), 0)
        ctx = ctx_out[0]
        self.addCleanup(lib.sinter_ctx_destroy, ctx)
        ps_out, mat_out = ffi.new("sinter_particles **"), ffi.new("sinter_material **")
        self.assertEqual(lib.sinter_particles_create(ps_out, ctx), 0)
        self.addCleanup(lib.sinter_particles_destroy, ps_out[0])
        self.assertEqual(lib.sinter_material_create(mat_out, ctx, b"steel"), 0)
        self.addCleanup(lib.sinter_material_destroy, mat_out[0])
        with self.assertRaises(OverflowError):
            lib.sinter_particles_set_material(ps_out[0], 2**40, mat_out[0])
        with self.assertRaises(OverflowError):
            lib.sinter_particles_reserve(ps_out[0], -1)
        self.assertEqual(lib.sinter_particles_set_material(ps_out[0], 0, mat_out[0]), 0)


class KeptViewCases(ArrayBackend):
    """A view array kept after its ``with`` block, and its set closed."""

    def setUp(self):
        super().setUp()
        self.ctx = sinter.Context()
        self.addCleanup(self.ctx.close)
        steel = sinter.Material(self.ctx, "steel", density=7800.0)
        self.ps = sinter.Particles(self.ctx)
        self.ps.set_material(0, steel)
        self.ps.add([(0.0, 0.0, 0.0), (3e-3, 0.0, 0.0)], 1e-3)

    def test_closing_the_set_keeps_its_memory_while_an_array_lives(self):
        with self.ps.view("position") as x:
            pass
        self.ps.close()
        self.assertTrue(self.ps.closed)
        if isinstance(x, memoryview):  # released at the end of the block: unusable
            with self.assertRaises(ValueError):
                x[0, 0] = 1.0
            del x
            gc.collect()
        else:  # NumPy: the set's memory stays allocated while the array lives
            self.assertIsNotNone(self.ps._handle)
            x[0, 0] = 1.0  # into the live set, not freed memory
            self.assertEqual(x[1, 0], 3e-3)
            del x
            gc.collect()
        self.assertIsNone(self.ps._handle)  # destroyed once no array is left

    def test_closing_the_context_waits_too(self):
        with self.ps.view("radius") as r:
            pass
        self.ctx.close()
        if not isinstance(r, memoryview):
            self.assertIsNotNone(self.ps._handle)
            self.assertEqual(float(r[1]), 1e-3)
        del r
        gc.collect()
        self.assertIsNone(self.ps._handle)
        self.assertIsNone(self.ctx._handle)

    def test_views_inside_the_block_still_release(self):
        with self.ps.view("velocity") as v:
            v[0, 0] = 0.5
            self.assertEqual(self.ps.views_out, 1)
        self.assertEqual(self.ps.views_out, 0)
        self.ps.add([(0.0, 3e-3, 0.0)], 1e-3)  # not busy


class KeptViewNumpyTest(KeptViewCases, unittest.TestCase):
    use_numpy = True


class KeptViewMemoryviewTest(KeptViewCases, unittest.TestCase):
    use_numpy = False


if __name__ == "__main__":
    unittest.main()
