"""Particle sets, run once with NumPy views and once with memoryview views."""

import math
import unittest

import sinter
import sinter.particles

try:
    import numpy
except ImportError:
    numpy = None

DENSITY = 7800.0  # kg/m^3
POSITIONS = [(0.0, 0.0, 0.0), (3e-3, 0.0, 0.0), (0.0, 3e-3, 0.0), (0.0, 0.0, 3e-3),
             (3e-3, 3e-3, 3e-3)]  # m
RADII = [1e-3, 1.25e-3, 5e-4, 2e-4, 1.5e-3]  # m


def rows(array):
    """A view, copy or list as nested Python lists."""
    return array.tolist() if hasattr(array, "tolist") else list(array)


class ParticlesCases:
    """The tests; subclasses choose the array backend."""

    use_numpy = None

    def setUp(self):
        saved = sinter.particles.USE_NUMPY
        sinter.particles.USE_NUMPY = self.use_numpy
        self.addCleanup(setattr, sinter.particles, "USE_NUMPY", saved)
        self.ctx = sinter.Context()
        self.addCleanup(self.ctx.close)
        self.steel = sinter.Material(self.ctx, "steel", density=DENSITY)
        self.ps = sinter.Particles(self.ctx)
        self.ps.set_material(0, self.steel)
        self.assertEqual(self.ps.add(POSITIONS, RADII, temperature=300.0), range(0, 5))

    def test_property_tables_and_enthalpy(self):
        """C(theta) tabulated: the table read back (linear, clamped), the specific enthalpy its
        integral (C0 theta below the table, then the trapezoid); a latent heat adds L above
        the melting interval; a backwards table is refused with the library's message."""
        if "sinter_particles_set_property_table" in sinter._lib.missing_functions:
            self.skipTest("the library has no property tables")
        self.ps.set_property_table(0, sinter.Property.HEAT_CAPACITY, [300, 1300], [400, 600])
        self.assertEqual(self.ps.property_at(0, sinter.Property.HEAT_CAPACITY, 800.0), 500.0)
        self.assertEqual(self.ps.property_at(0, sinter.Property.HEAT_CAPACITY, 2000.0), 600.0)
        h = self.ps.specific_enthalpy(0, 1300.0)
        self.assertAlmostEqual(h, 400.0 * 300.0 + 0.5 * (400.0 + 600.0) * 1000.0, delta=1e-6)
        self.steel.update(melting_temperature=1000.0, latent_heat=2e5, melting_range=10.0)
        self.ps.set_material(0, self.steel)
        self.assertAlmostEqual(self.ps.specific_enthalpy(0, 1300.0) - h, 2e5, delta=1e-6)
        with self.assertRaises(sinter.InvalidArgument) as caught:
            self.ps.set_property_table(0, sinter.Property.THERMAL_CONDUCTIVITY, [400, 300],
                                       [1, 1])
        self.assertIn("strictly increasing", str(caught.exception))

    def test_array_type(self):
        with self.ps.view("radius") as radius:
            self.assertEqual(isinstance(radius, memoryview), not self.use_numpy)

    def test_add_computes_mass_and_inertia(self):
        self.assertEqual((len(self.ps), self.ps.count), (5, 5))
        self.assertGreaterEqual(self.ps.capacity, 5)
        mass, inertia = rows(self.ps.get("mass")), rows(self.ps.get("inertia"))
        for i, r in enumerate(RADII):
            expected = DENSITY * 4.0 / 3.0 * math.pi * r ** 3
            self.assertLessEqual(abs(mass[i] - expected), 1e-14 * expected)
            self.assertLessEqual(abs(inertia[i] - 0.4 * expected * r * r), 1e-14 * inertia[i])
        self.assertEqual(rows(self.ps.get("temperature")), [300.0] * 5)
        self.assertEqual(rows(self.ps.get("position")), [list(p) for p in POSITIONS])
        self.assertEqual(rows(self.ps.get("velocity")), [[0.0] * 3] * 5)
        self.assertEqual(rows(self.ps.get("id")), [0, 1, 2, 3, 4])

    def test_add_flat_positions_and_one_radius(self):
        added = self.ps.add([1.0, 2.0, 3.0, 4.0, 5.0, 6.0], 2e-3, temperature=400.0)
        self.assertEqual(added, range(5, 7))
        self.assertEqual(rows(self.ps.get("position"))[5:], [[1.0, 2.0, 3.0], [4.0, 5.0, 6.0]])
        self.assertEqual(rows(self.ps.get("radius"))[5:], [2e-3, 2e-3])

    def test_add_rejects_bad_values_with_library_message(self):
        with self.assertRaises(sinter.InvalidArgument) as caught:
            self.ps.add([(0, 0, 0), (1, 0, 0)], [1e-3, -0.002])
        self.assertIn("radius of new particle 1 is -0.002 m; radii must be positive and finite",
                      caught.exception.message)
        with self.assertRaises(sinter.InvalidArgument) as caught:
            self.ps.add([(0, math.inf, 0)], [1e-3])
        self.assertIn("position.y of new particle 0", caught.exception.message)
        with self.assertRaises(sinter.NotFound) as caught:
            self.ps.add([(0, 0, 0)], [1e-3], material_id=3)
        self.assertIn("material id 3 is not registered", caught.exception.message)
        self.assertEqual(len(self.ps), 5)  # nothing was added

    def test_write_through_view_reaches_library(self):
        with self.ps.view("position") as x:
            x[1, 2] = 7.5e-3
        with self.ps.view("velocity") as v:
            v[4, 0] = -0.25
        with self.ps.view("flags") as flags:
            flags[2] = 5
        with self.ps.view("position", writable=False) as x:
            self.assertEqual(x[1, 2], 7.5e-3)
        self.assertEqual(rows(self.ps.get("velocity"))[4], [-0.25, 0.0, 0.0])
        self.assertEqual(rows(self.ps.get("flags")), [0, 0, 5, 0, 0])
        self.assertEqual(self.ps.views_out, 0)

    def test_view_shapes_and_read_only(self):
        with self.ps.view("position") as x, self.ps.view("id") as ids:
            self.assertEqual(tuple(x.shape), (5, 3))
            self.assertEqual(tuple(ids.shape), (5,))
            self.assertEqual(self.ps.views_out, 2)
            with self.assertRaises((TypeError, ValueError)):
                ids[0] = 9
        with self.assertRaises(sinter.InvalidArgument) as caught:
            self.ps.view("id", writable=True).__enter__()
        self.assertIn("read-only", caught.exception.message)
        with self.assertRaises(sinter.NotFound):
            self.ps.view("colour")

    def test_busy_while_a_view_is_out(self):
        with self.ps.view("radius"):
            for action in (lambda: self.ps.add([(1, 1, 1)], [1e-3]),
                           lambda: self.ps.remove([0]),
                           lambda: self.ps.reserve(1000)):
                with self.assertRaises(sinter.BusyError) as caught:
                    action()
                self.assertIs(caught.exception.status, sinter.Status.ERR_BUSY)
                self.assertIn("view(s) of the particle set are still out",
                              caught.exception.message)
        self.ps.add([(1, 1, 1)], [1e-3])
        self.assertEqual(len(self.ps), 6)

    def test_view_released_when_block_raises(self):
        with self.assertRaises(ZeroDivisionError):
            with self.ps.view("mass"):
                1 / 0
        self.assertEqual(self.ps.views_out, 0)

    def test_validate_names_particle_and_field(self):
        self.ps.validate()
        with self.ps.view("velocity") as v:
            v[3, 1] = math.nan
        with self.assertRaises(sinter.InvalidArgument) as caught:
            self.ps.validate()
        self.assertIn("velocity.y of particle 3 (id 3) is nan", caught.exception.message)
        self.assertEqual(caught.exception.index, 3)

    def test_remove_keeps_order_and_ids(self):
        self.ps.remove([3, 0])
        self.assertEqual(rows(self.ps.get("id")), [1, 2, 4])
        self.assertEqual(rows(self.ps.get("position")), [list(POSITIONS[i]) for i in (1, 2, 4)])
        self.assertEqual(rows(self.ps.get("radius")), [RADII[i] for i in (1, 2, 4)])
        self.assertEqual(self.ps.find_id(4), 2)
        with self.assertRaises(sinter.NotFound) as caught:
            self.ps.find_id(0)
        self.assertIn("no particle has id 0", caught.exception.message)
        with self.assertRaises(sinter.RangeError):
            self.ps.remove([7])
        with self.assertRaises(sinter.InvalidArgument):
            self.ps.remove([1, 1])
        self.ps.remove(0)
        self.assertEqual(rows(self.ps.get("id")), [2, 4])

    def test_add_with_ids(self):
        added = self.ps.add([(9e-3, 0.0, 0.0), (12e-3, 0.0, 0.0)], 1e-3, ids=[70, 40])
        self.assertEqual(list(added), [5, 6])
        self.assertEqual(rows(self.ps.get("id"))[5:], [70, 40])
        self.assertEqual(self.ps.find_id(40), 6)
        with self.assertRaises(sinter.InvalidArgument) as caught:
            self.ps.add([(0.0, 9e-3, 0.0)], 1e-3, ids=[70])
        self.assertIn("id 70 of new particle 0 is held by particle 5", caught.exception.message)
        with self.assertRaises(ValueError):
            self.ps.add([(0.0, 9e-3, 0.0)], 1e-3, ids=[1, 2])
        self.ps.add([(0.0, 12e-3, 0.0)], 1e-3)  # the set's counter continues above 70
        self.assertEqual(rows(self.ps.get("id"))[-1], 71)

    def test_set_whole_field(self):
        self.ps.set("temperature", [400.0, 401.0, 402.0, 403.0, 404.0])
        self.assertEqual(rows(self.ps.get("temperature")), [400.0, 401.0, 402.0, 403.0, 404.0])
        self.ps.set("spin", 2.0)
        self.assertEqual(rows(self.ps.get("spin")), [[2.0] * 3] * 5)
        self.ps.set("velocity", [[i, 0.0, -i] for i in range(5)])
        self.assertEqual(rows(self.ps.get("velocity"))[3], [3.0, 0.0, -3.0])
        with self.assertRaises(ValueError):
            self.ps.set("radius", [1e-3, 2e-3])

    def test_get_returns_a_copy(self):
        radii = self.ps.get("radius")
        radii[0] = 99.0
        self.assertEqual(rows(self.ps.get("radius"))[0], RADII[0])

    def test_material_replacement_recomputes_mass(self):
        light = self.steel.clone()
        light["density"] = 1000.0
        self.ps.set_material(0, light)
        mass = rows(self.ps.get("mass"))
        self.assertAlmostEqual(mass[0] / (1000.0 * 4.0 / 3.0 * math.pi * RADII[0] ** 3), 1.0,
                               places=14)
        copy = self.ps.get_material(0)
        self.assertEqual(copy["density"], 1000.0)
        with self.assertRaises(sinter.NotFound):
            self.ps.get_material(9)
        with self.assertRaises(sinter.RangeError):
            self.ps.set_material(256, light)

    def test_empty_set(self):
        empty = sinter.Particles(self.ctx)
        with empty.view("position") as x:
            self.assertEqual(len(x), 0)
        self.assertEqual(len(rows(empty.get("mass"))), 0)
        self.assertEqual(empty.add([], []), range(0, 0))
        empty.validate()

    def test_closed_set(self):
        with sinter.Particles(self.ctx) as other:
            view = other.view("radius")
            view.__enter__()
        self.assertTrue(other.closed)
        view.release()  # nothing to release in a destroyed set
        with self.assertRaisesRegex(ValueError, "closed"):
            other.add([(0, 0, 0)], [1e-3])


@unittest.skipIf(sinter.particles.numpy is None, "NumPy missing, or SINTER_NO_NUMPY is set")
class NumpyParticlesTest(ParticlesCases, unittest.TestCase):
    use_numpy = True

    def test_view_is_zero_copy(self):
        with self.ps.view("position") as x:
            self.assertIsInstance(x, numpy.ndarray)
            self.assertEqual((x.dtype, x.flags.c_contiguous, x.flags.owndata),
                             (numpy.float64, True, False))
            x[:, 0] += 1.0
            address = x.__array_interface__["data"][0]
        with self.ps.view("position") as again:
            self.assertEqual(again.__array_interface__["data"][0], address)
            self.assertEqual(again[:, 0].tolist(), [p[0] + 1.0 for p in POSITIONS])
        with self.ps.view("id") as ids:
            self.assertEqual((ids.dtype, ids.flags.writeable), (numpy.uint64, False))
        with self.ps.view("material") as material:
            self.assertEqual(material.dtype, numpy.int32)

    def test_add_numpy_arrays(self):
        xyz = numpy.arange(12.0).reshape(4, 3)
        added = self.ps.add(xyz, numpy.full(4, 1e-3), temperature=500.0)
        self.assertEqual(added, range(5, 9))
        numpy.testing.assert_array_equal(self.ps.get("position")[5:], xyz)
        with self.assertRaises(ValueError):
            self.ps.add(numpy.zeros((2, 2)), [1e-3, 1e-3])


class MemoryviewParticlesTest(ParticlesCases, unittest.TestCase):
    use_numpy = False

    def test_view_is_memoryview_over_library_memory(self):
        with self.ps.view("position") as x:
            self.assertEqual((x.format, x.shape, x.readonly), ("d", (5, 3), False))
            x[0, 0] = 0.5
        with self.assertRaises(ValueError):  # released on exit
            x[0, 0]
        with self.ps.view("id") as ids:
            self.assertEqual((ids.format, ids.readonly), ("Q", True))
            self.assertEqual(ids.tolist(), [0, 1, 2, 3, 4])
        with self.ps.view("material") as material, self.ps.view("flags") as flags:
            self.assertEqual((material.format, flags.format), ("i", "I"))
        self.assertEqual(self.ps.get("position")[0], [0.5, 0.0, 0.0])


if __name__ == "__main__":
    unittest.main()
