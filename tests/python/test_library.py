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
    """Names of the functions declared with SINTER_API in the public headers."""
    names = []
    for name in ("sinter.h", "sinter_submodel.h", "sinter_domain.h"):
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


#: Header functions no module of the sinter package calls, each with the reason.
UNUSED_BY_DESIGN = {
    # (none at present: every function of sinter.h and sinter_submodel.h has a Python path)
}

PACKAGE_DIR = os.path.dirname(os.path.abspath(sinter.__file__))


def package_sources():
    """{file name: text} of the package's modules other than the declaration table."""
    sources = {}
    for name in sorted(os.listdir(PACKAGE_DIR)):
        if name.endswith(".py") and name != "_lib.py":
            with open(os.path.join(PACKAGE_DIR, name)) as source:
                sources[name] = source.read()
    return sources


class CoverageTest(unittest.TestCase):
    """Every header function is reachable from Python, through ctypes and through cffi."""

    def test_every_header_function_is_used_by_a_module(self):
        # A use is `lib.<name>` or the name as a string the module looks up on lib
        # (destroy functions by _destroy_function, the models' create/get/set by role).
        text = "\n".join(package_sources().values())
        unused = []
        for name in header_functions():
            if re.search(r"\blib\.%s\b|[\"']%s[\"']" % (name, name), text) is None:
                unused.append(name)
        self.assertEqual(sorted(set(unused) - set(UNUSED_BY_DESIGN)), [],
                         "header functions no Python module uses: wrap them, or list them in "
                         "UNUSED_BY_DESIGN with the reason")
        self.assertEqual(sorted(set(UNUSED_BY_DESIGN) - set(unused)), [],
                         "used now: remove them from UNUSED_BY_DESIGN")

    def test_every_header_function_is_in_the_cffi_lib(self):
        try:
            import cffi  # noqa: F401
        except ImportError:
            self.skipTest("cffi is not installed for this interpreter")
        from sinter import cffi_backend

        ffi, cffi_lib = cffi_backend.load()
        missing = []
        for name in header_functions():
            try:
                function = getattr(cffi_lib, name)
            except (AttributeError, NotImplementedError) as error:
                missing.append("%s (%s)" % (name, error))
                continue
            self.assertTrue(callable(function), name)
            self.assertEqual(ffi.typeof(function).kind, "function", name)
        self.assertEqual(missing, [], "the cffi backend cannot reach these")

    def test_enums_of_the_header_are_python_enums(self):
        """Every enum of the headers has a Python enum with the header's names and values."""
        code = ""
        for header in ("sinter.h", "sinter_submodel.h", "sinter_domain.h"):
            with open(_cdef.find_header(header)) as text:
                code += re.sub(r"/\*.*?\*/", " ", text.read(), flags=re.S)
        pairs = {
            "sinter_status": (sinter.Status, "SINTER_"),
            "sinter_log_level": (sinter.LogLevel, "SINTER_LOG_"),
            "sinter_material_param": (sinter.MaterialParam, "SINTER_MAT_"),
            "sinter_field": (sinter.Field, "SINTER_FIELD_"),
            "sinter_dtype": (sinter.DType, "SINTER_DTYPE_"),
            "sinter_particle_flag": (sinter.ParticleFlag, "SINTER_PARTICLE_"),
            "sinter_wall_motion": (sinter.WallMotion, "SINTER_WALL_"),
            "sinter_wall_kind": (sinter.WallKind, "SINTER_WALL_"),
            "sinter_stepper_kind": (sinter.StepperKind, "SINTER_STEPPER_"),
            "sinter_thermal_scheme": (sinter.ThermalScheme, "SINTER_THERMAL_"),
            "sinter_wall_electric_mode": (sinter.WallElectric, "SINTER_WALL_"),
            "sinter_wall_thermal_mode": (sinter.WallThermal, "SINTER_WALL_"),
            "sinter_radius_distribution": (sinter.RadiusDistribution, "SINTER_RADII_"),
            "sinter_size_basis": (sinter.packing.SizeBasis, "SINTER_SIZE_BY_"),
            "sinter_insertion_region": (sinter.InsertionRegion, "SINTER_INSERT_"),
            "sinter_callback_result": (sinter.CallbackResult, "SINTER_CALLBACK_"),
            "sinter_contact_kind": (sinter.ContactKind, "SINTER_CONTACT_"),
            "sinter_contact_data": (sinter.snapshot.ContactData, "SINTER_CONTACT_DATA_"),
            "sinter_link_data": (sinter.snapshot.LinkData, "SINTER_LINK_DATA_"),
            "sinter_coarse_quantity": (sinter.CoarseQuantity, "SINTER_COARSE_"),
            "sinter_property": (sinter.Property, "SINTER_PROPERTY_"),
            "sinter_reduce_op": (sinter.domain.ReduceOp, "SINTER_REDUCE_"),
            "sinter_reduce_type": (sinter.domain.ReduceType, "SINTER_REDUCE_"),
            "sinter_halo_dir": (sinter.domain.HaloDir, "SINTER_HALO_"),
        }
        declared = set(re.findall(r"typedef enum (\w+) \{", code))
        self.assertEqual(declared - set(pairs), set(), "give these C enums a Python enum")
        for c_name, (python_enum, prefix) in pairs.items():
            if c_name == "sinter_status":  # an X-macro list, compared in StatusTest
                continue
            body = re.search(r"typedef enum %s \{(.*?)\}" % c_name, code, re.S).group(1)
            values = {name[len(prefix):]: int(value)
                      for name, value in re.findall(r"(\w+) = (-?\d+)", body)
                      if not name.endswith("_")}  # SINTER_FIELD_COUNT_ and the like
            self.assertEqual({m.name: int(m) for m in python_enum}, values, c_name)


class TypingTest(unittest.TestCase):
    def test_py_typed_marker_is_package_data(self):
        self.assertTrue(os.path.exists(os.path.join(PACKAGE_DIR, "py.typed")))
        if not os.path.exists(PYPROJECT):
            self.skipTest("not running from the source tree")
        with open(PYPROJECT) as project:
            self.assertRegex(project.read(), r'package-data\s*=\s*\{[^}]*"sinter"\s*=\s*\[[^]]*'
                                             r'"py\.typed"')


#: Public signatures allowed a **kwargs, with the reason.
VAR_KEYWORDS_BY_DESIGN = {
    "_KeyedModel.__init__": "a built-in model's parameters depend on its name (sinter.h lists "
                            "them; an unknown one raises NotFound listing the model's keys)",
    "_KeyedModel.update": "as __init__",
}


def public_callables():
    """(qualified name, function) of every public function, method, property accessor and
    __init__ of the names sinter exports, base classes of the package included."""
    import inspect

    seen = set()
    for name in sinter.__all__:
        obj = getattr(sinter, name)
        if inspect.isclass(obj):
            if issubclass(obj, BaseException) or not obj.__module__.startswith("sinter"):
                continue
            for cls in obj.__mro__:
                if not cls.__module__.startswith("sinter") or cls in seen:
                    continue
                seen.add(cls)
                for attr, member in vars(cls).items():
                    if attr.startswith("_") and attr != "__init__":
                        continue
                    qualified = "%s.%s" % (cls.__name__, attr)
                    if isinstance(member, property):
                        for accessor in (member.fget, member.fset):
                            if accessor is not None:
                                yield qualified, accessor
                    elif isinstance(member, (staticmethod, classmethod)):
                        yield qualified, member.__func__
                    elif inspect.isfunction(member):
                        yield qualified, member
        elif inspect.isfunction(obj):
            yield name, obj


class AnnotationTest(unittest.TestCase):
    def test_public_signatures_are_typed_and_named(self):
        import inspect

        problems = []
        for name, function in public_callables():
            if issubclass(getattr(function, "__class__", object), type):
                continue
            signature = inspect.signature(function)
            for parameter in signature.parameters.values():
                if parameter.name in ("self", "cls"):
                    continue
                if parameter.annotation is inspect.Parameter.empty:
                    problems.append("%s: parameter %s has no type" % (name, parameter.name))
                if (parameter.kind is parameter.VAR_KEYWORD
                        and name not in VAR_KEYWORDS_BY_DESIGN):
                    problems.append("%s: **%s (name the keywords)" % (name, parameter.name))
            if (signature.return_annotation is inspect.Signature.empty
                    and not name.endswith("__init__")):
                problems.append("%s: no return type" % name)
        self.assertEqual(problems, [])
        self.assertGreater(len(list(public_callables())), 100)

    def test_material_keywords_are_the_library_keys(self):
        import inspect

        self.assertEqual(list(sinter.Material.KEYWORDS), sinter.Material.keys())
        for function in (sinter.Material.__init__, sinter.Material.update):
            keywords = [p.name for p in inspect.signature(function).parameters.values()
                        if p.kind is p.KEYWORD_ONLY]
            self.assertEqual(keywords, sinter.Material.keys())
            for key in keywords:  # the docstring gives each key's unit and range
                self.assertIn(key, sinter.Material.__init__.__doc__)


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
