"""The preprocessed public header parses as a cffi cdef and agrees with the ctypes table."""

import ctypes
import os
import tempfile
import unittest

import sinter
from sinter import _cdef, _lib

try:
    import cffi
except ImportError:
    cffi = None


def ctypes_shape(ctype):
    """A C type of the ctypes table as a comparable string: 'i4', 'f8', '*char', 'fn'..."""
    if ctype is None:
        return "void"
    if ctype is ctypes.c_char_p:
        return "*char"
    if ctype is ctypes.c_void_p:
        return "*void"
    if issubclass(ctype, ctypes._CFuncPtr):
        return "fn"
    if issubclass(ctype, ctypes._Pointer):
        return "*" + ctypes_shape(ctype._type_)
    if issubclass(ctype, ctypes.Structure):
        return ctype._cname
    if ctype in (ctypes.c_double, ctypes.c_float):
        return "f%d" % ctypes.sizeof(ctype)
    return "%s%d" % ("i" if ctype(-1).value < 0 else "u", ctypes.sizeof(ctype))


def cffi_shape(ffi, ctype):
    """The same string for a cffi type (array parameters decay to pointers)."""
    if ctype.kind in ("pointer", "array"):
        return "*" + cffi_shape(ffi, ctype.item)
    if ctype.kind == "function":
        return "fn"
    if ctype.kind == "struct":
        return ctype.cname.replace("struct ", "")
    if ctype.kind == "enum":
        return "i%d" % ffi.sizeof(ctype)  # enums are passed as C int
    if ctype.cname in ("void", "char"):
        return ctype.cname
    if ctype.cname in ("double", "float"):
        return "f%d" % ffi.sizeof(ctype)
    return "%s%d" % ("i" if int(ffi.cast(ctype, -1)) < 0 else "u", ffi.sizeof(ctype))


@unittest.skipIf(cffi is None, "cffi is not installed for this interpreter")
class CdefTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        from sinter import cffi_backend

        cls.ffi, cls.lib = cffi_backend.load()

    def test_header_parses_as_cdef(self):
        text = _cdef.preprocess()
        self.assertNotIn("#", text)
        self.assertIn("sinter_particles_view", text)
        _cdef.check_cdef(text)

    def test_version_through_cffi(self):
        self.assertEqual(self.lib.sinter_version_number(), sinter.version_number())
        self.assertEqual(self.ffi.string(self.lib.sinter_version_string()).decode(),
                         sinter.__version__)

    def test_enum_constants_match(self):
        for status in sinter.Status:
            self.assertEqual(getattr(self.lib, "SINTER_" + status.name), status)
        for field in sinter.FIELDS.values():
            self.assertEqual(getattr(self.lib, "SINTER_FIELD_" + field.name.upper()), field.id)
        self.assertEqual(self.lib.SINTER_FIELD_COUNT_, len(sinter.FIELDS))
        self.assertEqual(self.lib.SINTER_MAT_PARAM_COUNT_, len(sinter.Material.keys()))

    def test_ctypes_signatures_match_header(self):
        # Functions the library lacks have no cffi function object; test_library reports them.
        for name in set(_lib.SIGNATURES) - set(_lib.missing_functions):
            restype, argtypes = _lib.SIGNATURES[name]
            function = self.ffi.typeof(getattr(self.lib, name))
            self.assertEqual(ctypes_shape(restype), cffi_shape(self.ffi, function.result), name)
            self.assertEqual([ctypes_shape(t) for t in argtypes],
                             [cffi_shape(self.ffi, t) for t in function.args], name)

    def test_struct_layouts_match_header(self):
        structs = [value for value in vars(_lib).values() if isinstance(value, type)
                   and issubclass(value, ctypes.Structure) and hasattr(value, "_fields_")]
        self.assertGreaterEqual(len(structs), 3)
        for struct in structs:
            cname = struct._cname
            self.assertEqual([name for name, _ in struct._fields_],
                             [name for name, _ in self.ffi.typeof(cname).fields], cname)
            self.assertEqual(ctypes.sizeof(struct), self.ffi.sizeof(cname), cname)
            for field, _ in struct._fields_:
                self.assertEqual(getattr(struct, field).offset, self.ffi.offsetof(cname, field),
                                 "%s.%s" % (cname, field))

@unittest.skipIf(cffi is None, "cffi is not installed for this interpreter")
class SceneThroughCffiTest(unittest.TestCase):
    """The second implementation path: a scene run end to end through cffi alone."""

    def test_scene_end_to_end_matches_ctypes(self):
        from sinter import cffi_backend

        from _support import as_lists, write_scene

        with tempfile.TemporaryDirectory() as tmp:
            path = write_scene(tmp)
            seen = []
            result = cffi_backend.run_scene(path, os.path.join(tmp, "cffi"),
                                            progress=lambda t, end: seen.append(t))
            self.assertEqual(result["time"], result["end_time"])
            self.assertEqual(len(seen), 5)
            self.assertTrue(os.path.exists(os.path.join(tmp, "cffi", "series.csv")))
            with sinter.Context() as ctx, sinter.Scene(ctx, path) as scene:
                scene.run(os.path.join(tmp, "ctypes"))
                positions = [tuple(p) for p in as_lists(scene.particles.get("position"))]
                self.assertEqual(result["steps"], scene.stepper.stats.steps)
            self.assertEqual(result["position"], positions)  # the same library, bit for bit
            self.assertEqual(len(result["temperature"]), len(positions))

    def test_errors_and_callback_exceptions(self):
        from sinter import cffi_backend

        from _support import write_scene

        with tempfile.TemporaryDirectory() as tmp:
            with self.assertRaises(cffi_backend.CffiError) as caught:
                cffi_backend.run_scene(os.path.join(tmp, "missing.scene"), tmp)
            self.assertEqual(caught.exception.status, sinter.Status.ERR_IO)

            def progress(t, end):
                raise ZeroDivisionError

            with self.assertRaises(ZeroDivisionError):
                cffi_backend.run_scene(write_scene(tmp), os.path.join(tmp, "out"), progress)


if __name__ == "__main__":
    unittest.main()
