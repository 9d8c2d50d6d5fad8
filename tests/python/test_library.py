"""Loading, version, status codes and the declaration table of the binding."""

import os
import re
import subprocess
import sys
import tempfile
import unittest
from unittest import mock

import sinter
from sinter import _cdef, _lib

PYPROJECT = os.path.join(os.path.dirname(os.path.dirname(sinter.__file__)), "pyproject.toml")


def header_defines(name):
    """{macro: value text} of the simple #defines in a header of the include dirs."""
    with open(_cdef.find_header(name)) as header:
        return dict(re.findall(r"^#define[ \t]+(\w+)[ \t]+(.+?)[ \t]*$", header.read(), re.M))


def header_functions():
    """Names of the functions declared with SINTER_API in sinter.h and sinter_submodel.h."""
    names = []
    for name in ("sinter.h", "sinter_submodel.h"):
        with open(_cdef.find_header(name)) as header:
            code = re.sub(r"/\*.*?\*/", " ", header.read(), flags=re.S)
        names += re.findall(r"SINTER_API\s+[\w\s*]*?\b(sinter_\w+)\s*\(", code)
    return names


class VersionTest(unittest.TestCase):
    def test_version_matches_generated_header(self):
        defines = header_defines("sinter_version.h")
        self.assertEqual(sinter.__version__, defines["SINTER_VERSION_STRING"].strip('"'))
        self.assertEqual(sinter.version_string(), sinter.__version__)
        major, minor, patch = (int(defines["SINTER_VERSION_" + part])
                               for part in ("MAJOR", "MINOR", "PATCH"))
        self.assertEqual(sinter.version_number(), major * 10000 + minor * 100 + patch)

    def test_pyproject_version_matches_library(self):
        if not os.path.exists(PYPROJECT):
            self.skipTest("not running from the source tree")
        with open(PYPROJECT) as project:
            version = re.search(r'^version\s*=\s*"([^"]+)"', project.read(), re.M).group(1)
        self.assertEqual(version, sinter.__version__)


class StatusTest(unittest.TestCase):
    def test_generated_from_library(self):
        self.assertEqual(sinter.Status.OK, 0)
        self.assertEqual(sinter.Status.ERR_NULL, -1)
        self.assertEqual(sinter.Status.ERR_BUSY.message,
                         "the object is locked by an outstanding view")
        values = [int(s) for s in sinter.Status]
        self.assertEqual(values, list(range(0, -len(values), -1)))  # contiguous 0, -1, ...
        self.assertGreaterEqual(len(values), 19)

    def test_matches_header_list(self):
        with open(_cdef.find_header("sinter.h")) as header:
            listed = re.findall(r"X\(SINTER_(\w+), (-?\d+),", header.read())
        self.assertEqual({name: int(value) for name, value in listed},
                         {s.name: int(s) for s in sinter.Status})

    def test_error_classes(self):
        self.assertTrue(issubclass(sinter.SinterError, RuntimeError))
        self.assertTrue(issubclass(sinter.InvalidArgument, ValueError))
        self.assertTrue(issubclass(sinter.NotFound, KeyError))
        self.assertTrue(issubclass(sinter.LibraryNotFound, OSError))


class DeclarationTest(unittest.TestCase):
    def test_every_header_function_is_declared(self):
        declared = set(_lib.SIGNATURES)
        in_header = set(header_functions())
        self.assertGreaterEqual(len(in_header), 36)
        self.assertEqual(in_header - declared, set(), "declare these in sinter/_lib.py")
        self.assertEqual(declared - in_header, set(), "not in the headers any more")
        for name in in_header - set(_lib.missing_functions):
            function = getattr(_lib.lib, name)
            self.assertIsNotNone(function.argtypes, name)

    def test_library_defines_every_declared_function(self):
        # Reported as a skip, not a failure: the header may be ahead of the build.
        if _lib.missing_functions:
            self.skipTest("%s lacks %d functions of sinter.h: %s" % (
                sinter.library_path, len(_lib.missing_functions),
                " ".join(_lib.missing_functions)))


class DiscoveryTest(unittest.TestCase):
    def test_sinter_library_is_the_only_candidate(self):
        self.assertEqual(_lib.library_candidates({"SINTER_LIBRARY": "/x/libsinter.so"}),
                         ["/x/libsinter.so"])

    def test_default_candidates(self):
        candidates = _lib.library_candidates({})
        self.assertTrue(candidates[0].endswith(os.path.join("lib", "libsinter.so")))
        self.assertIn("libsinter.so.0", candidates)

    def test_bundled_library_comes_first(self):
        # an installed wheel holds sinter/libsinter.so (bindings/python/setup.py): tried first
        with tempfile.TemporaryDirectory() as tmp:
            bundled = os.path.join(tmp, "libsinter.so")
            open(bundled, "wb").close()
            with mock.patch.object(_lib, "_bundled_library", return_value=bundled):
                candidates = _lib.library_candidates({})
        self.assertEqual(candidates[0], bundled)
        self.assertTrue(candidates[1].endswith(os.path.join("lib", "libsinter.so")))

    def test_missing_library_lists_what_was_tried(self):
        missing = "/nonexistent/dir/libsinter.so"
        with self.assertRaises(sinter.LibraryNotFound) as caught:
            _lib.load_library({"SINTER_LIBRARY": missing})
        self.assertIn(missing, str(caught.exception))
        self.assertIn("SINTER_LIBRARY", str(caught.exception))

    def test_loaded_library_is_the_requested_one(self):
        requested = os.environ.get("SINTER_LIBRARY")
        if not requested:
            self.skipTest("SINTER_LIBRARY is not set")
        self.assertEqual(sinter.library_path, requested)

    def test_no_numpy_environment_switch(self):
        code = "import sinter.particles as p; print(p.USE_NUMPY, p.numpy)"
        package_root = os.path.dirname(os.path.dirname(sinter.__file__))
        env = dict(os.environ, SINTER_NO_NUMPY="1", PYTHONPATH=package_root)
        out = subprocess.run([sys.executable, "-c", code], env=env, check=True,
                             stdout=subprocess.PIPE, universal_newlines=True).stdout
        self.assertEqual(out.split(), ["False", "None"])


if __name__ == "__main__":
    unittest.main()
