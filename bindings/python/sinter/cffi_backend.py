"""Optional cffi access to libsinter, built from the public header (needs cffi).

    from sinter import cffi_backend
    ffi, lib = cffi_backend.load()
    lib.sinter_version_number()

The cdef comes from preprocessing sinter.h (see sinter._cdef for the
compiler and include directories used); the library opened is the one the
ctypes binding loaded (sinter.library_path).
"""

import cffi  # noqa: F401  (ImportError here means cffi is not installed)

from . import _cdef
from ._lib import library_path


def load(path=None):
    """(ffi, lib): the header's declarations and libsinter opened with ffi.dlopen."""
    ffi = _cdef.check_cdef()
    return ffi, ffi.dlopen(path or library_path)
