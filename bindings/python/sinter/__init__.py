"""Python bindings of libsinter (DEM simulation of powder sintering), via ctypes.

Units are SI throughout: m, kg, s, K, N, Pa, W, A, V.

    import sinter
    with sinter.Context() as ctx:
        steel = sinter.Material(ctx, "steel", density=7800.0, youngs_modulus=2e11)
        ps = sinter.Particles(ctx)
        ps.set_material(0, steel)
        ps.add([(0.0, 0.0, 0.0), (2e-3, 0.0, 0.0)], [1e-3, 1e-3])
        with ps.view("velocity") as v:   # zero-copy, NumPy if available
            v[0, 0] = 0.1

The shared library is found through SINTER_LIBRARY, the source tree's
lib/libsinter.so, or the system's libsinter.so.0 (see sinter._lib).
"""

from ._errors import (BusyError, InvalidArgument, NotFound, RangeError, SinterError,
                      Status)
from ._lib import LibraryNotFound, library_path
from .context import Context, LogLevel, version_number, version_string
from .material import Material, ParamInfo
from .particles import FIELDS, FieldInfo, FieldView, Particles

__version__ = version_string()

__all__ = [
    "BusyError", "Context", "FIELDS", "FieldInfo", "FieldView", "InvalidArgument",
    "LibraryNotFound", "LogLevel", "Material", "NotFound", "ParamInfo", "Particles",
    "RangeError", "SinterError", "Status", "library_path", "version_number",
    "version_string",
]
