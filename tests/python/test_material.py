"""Material parameters by key: defaults, ranges, errors."""

import math
import unittest

import sinter


class MaterialTest(unittest.TestCase):
    def setUp(self):
        self.ctx = sinter.Context()
        self.addCleanup(self.ctx.close)

    def test_defaults_match_describe(self):
        material = sinter.Material(self.ctx, "glass")
        self.assertEqual(material.name, "glass")
        params = material.params()
        self.assertEqual(list(params), sinter.Material.keys())
        self.assertIn("youngs_modulus", params)
        for key, value in params.items():
            info = sinter.Material.describe(key)
            self.assertEqual(value, info.default, key)
            self.assertTrue(info.min <= info.default <= info.max, key)

    def test_describe(self):
        unit, meaning, default, low, high = sinter.Material.describe("youngs_modulus")
        self.assertEqual(unit, "Pa")
        self.assertIn("elasticity", meaning)
        self.assertEqual((low, default > 0, high > default), (0.0, True, True))
        self.assertEqual(sinter.Material.describe("density").unit, "kg/m^3")

    def test_set_get(self):
        material = sinter.Material(self.ctx, "steel", density=7800.0, poisson_ratio=0.29)
        material["youngs_modulus"] = 1e9
        material.update(emissivity=0.5)
        self.assertEqual(material["youngs_modulus"], 1e9)
        self.assertEqual(material["density"], 7800.0)
        self.assertEqual(material.params()["poisson_ratio"], 0.29)
        self.assertEqual(material["emissivity"], 0.5)

    def test_invalid_value_names_the_key(self):
        material = sinter.Material(self.ctx, "steel")
        for key, value in (("youngs_modulus", -1.0), ("density", 0.0),
                           ("emissivity", math.nan), ("softening_law", 1.5)):
            with self.assertRaises(sinter.InvalidArgument) as caught:
                material[key] = value
            self.assertIs(caught.exception.status, sinter.Status.ERR_INVALID)
            self.assertIn(key, caught.exception.message)
            self.assertIn("'steel'", caught.exception.message)
        default = sinter.Material.describe("youngs_modulus").default
        self.assertEqual(material["youngs_modulus"], default)  # refused values left no trace

    def test_invalid_constructor_parameter(self):
        with self.assertRaises(sinter.InvalidArgument) as caught:
            sinter.Material(self.ctx, "bad", poisson_ratio=0.7)
        self.assertIn("poisson_ratio = 0.7", caught.exception.message)

    def test_unknown_key(self):
        material = sinter.Material(self.ctx)
        for action in (lambda: material["stiffness"], lambda: material.update({"stiffness": 1.0}),
                       lambda: sinter.Material.describe("stiffness")):
            with self.assertRaises(sinter.NotFound) as caught:
                action()
            self.assertIsInstance(caught.exception, KeyError)
            self.assertIn("'stiffness'", caught.exception.message)

    def test_name_too_long(self):
        with self.assertRaises(sinter.InvalidArgument) as caught:
            sinter.Material(self.ctx, "x" * 200)
        self.assertIn("longer than", caught.exception.message)

    def test_clone_is_independent(self):
        with sinter.Material(self.ctx, "a", density=1000.0) as original:
            copy = original.clone()
            original["density"] = 2000.0
        self.assertTrue(original.closed)
        self.assertEqual((copy.name, copy["density"]), ("a", 1000.0))


if __name__ == "__main__":
    unittest.main()
