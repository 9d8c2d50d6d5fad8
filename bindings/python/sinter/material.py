"""Materials: named sets of parameters with SI units, defaults and valid ranges."""

import collections
import ctypes
import itertools

from ._errors import NotFound, Status, check
from ._lib import MaterialPtr, c_enum, lib, text
from .context import _Handle

#: What Material.describe() returns; values in the parameter's SI unit.
ParamInfo = collections.namedtuple("ParamInfo", "unit meaning default min max")


def _param_id(key):
    """The sinter_material_param of a key such as "youngs_modulus"."""
    param = c_enum()
    status = lib.sinter_material_param_find(key.encode("utf-8"), ctypes.byref(param))
    if status == Status.ERR_NOT_FOUND:
        raise NotFound(Status.ERR_NOT_FOUND,
                       "unknown material parameter %r; known keys: %s"
                       % (key, ", ".join(Material.keys())))
    check(status, None, "sinter_material_param_find")
    return param.value


def _param_info(param):
    """(key, ParamInfo) of a parameter id, or None past the last parameter."""
    key, unit, meaning = ctypes.c_char_p(), ctypes.c_char_p(), ctypes.c_char_p()
    default, low, high = ctypes.c_double(), ctypes.c_double(), ctypes.c_double()
    status = lib.sinter_material_param_info(
        param, ctypes.byref(key), ctypes.byref(unit), ctypes.byref(meaning),
        ctypes.byref(default), ctypes.byref(low), ctypes.byref(high))
    if status == Status.ERR_RANGE:
        return None
    check(status, None, "sinter_material_param_info")
    return text(key.value), ParamInfo(text(unit.value), text(meaning.value),
                                      default.value, low.value, high.value)


class Material(_Handle):
    """A sinter_material: Material(ctx, "steel", density=7800.0, youngs_modulus=2e11).

    Parameters are read and written by key, m["density"] (SI units, see
    Material.describe). Values outside a parameter's range raise
    InvalidArgument with the library's message naming the key.
    """

    _destroy_function = "sinter_material_destroy"

    def __init__(self, context, name=None, **params):
        handle = MaterialPtr()
        encoded = None if name is None else name.encode("utf-8")
        check(lib.sinter_material_create(ctypes.byref(handle), context._ptr, encoded),
              context._handle, "sinter_material_create")
        super().__init__(context, handle)
        try:
            self.update(params)
        except Exception:
            self.close()
            raise

    @classmethod
    def _from_handle(cls, context, handle):
        material = cls.__new__(cls)
        _Handle.__init__(material, context, handle)
        return material

    @staticmethod
    def keys():
        """Every parameter key, in the library's order."""
        keys = []
        for param in itertools.count():
            info = _param_info(param)
            if info is None:
                return keys
            keys.append(info[0])

    @staticmethod
    def describe(key):
        """ParamInfo(unit, meaning, default, min, max) of a parameter key."""
        return _param_info(_param_id(key))[1]

    @property
    def name(self):
        return text(lib.sinter_material_name(self._ptr))

    def __getitem__(self, key):
        value = ctypes.c_double()
        self._check(lib.sinter_material_get(self._ptr, _param_id(key), ctypes.byref(value)),
                    "sinter_material_get")
        return value.value

    def __setitem__(self, key, value):
        self._check(lib.sinter_material_set(self._ptr, _param_id(key), float(value)),
                    "sinter_material_set")

    def update(self, params=(), **more):
        """Set several parameters from a mapping and/or keywords."""
        for key, value in itertools.chain(dict(params).items(), more.items()):
            self[key] = value

    def params(self):
        """{key: value} of every parameter."""
        return {key: self[key] for key in self.keys()}

    def clone(self):
        """An independent copy (name and every parameter)."""
        handle = MaterialPtr()
        self._check(lib.sinter_material_clone(ctypes.byref(handle), self._ptr),
                    "sinter_material_clone")
        return Material._from_handle(self._context, handle)

    def __repr__(self):
        return "<sinter.Material %s>" % ("closed" if self.closed else repr(self.name))
