"""Optional cffi access to libsinter, built from the public headers (needs cffi).

    from sinter import cffi_backend
    ffi, lib = cffi_backend.load()
    lib.sinter_version_number()

The cdef comes from preprocessing sinter_submodel.h, which includes sinter.h
(see sinter._cdef for the compiler and include directories used); the library
opened is the one the ctypes binding loaded (sinter.library_path).

This is the second, deliberately small, implementation path: the ctypes
classes (sinter.Scene, sinter.Stepper, ...) are the supported API. run_scene()
runs a scene file end to end through cffi alone, which the tests compare with
the ctypes path.
"""

import os

import cffi  # noqa: F401  (ImportError here means cffi is not installed)

from . import _cdef
from ._lib import library_path

_loaded = {}


class CffiError(RuntimeError):
    """A libsinter call made through cffi failed: .status, .message."""

    def __init__(self, status, message):
        super().__init__("%s [status %d]" % (message, status))
        self.status = status
        self.message = message


def load(path=None):
    """(ffi, lib): the headers' declarations and libsinter opened with ffi.dlopen.

    Cached per path: the header is preprocessed once.
    """
    path = path or library_path
    if path not in _loaded:
        ffi = _cdef.check_cdef()
        _loaded[path] = (ffi, ffi.dlopen(path))
    return _loaded[path]


def run_scene(scene_path, out_dir, progress=None, path=None):
    """Load and run a scene file through cffi only; return its final state.

    progress(time, end_time), if given, is called after each output interval
    (an ffi.callback); a true result stops the run. Returns a dict: end_time,
    time [s], steps, and per particle position [(x, y, z)] [m] and
    temperature [K] (plain lists). Raises CffiError on a failing call.
    """
    ffi, lib = load(path)
    ctx_out = ffi.new("sinter_ctx **")
    _check(lib, None, lib.sinter_ctx_create(ctx_out, ffi.NULL), ffi)
    ctx = ctx_out[0]
    scene = ffi.NULL
    try:
        scene_out = ffi.new("sinter_scene **")
        _check(lib, ctx, lib.sinter_scene_load(scene_out, ctx, os.fsencode(scene_path)), ffi)
        scene = scene_out[0]
        raised = []

        @ffi.callback("int(double, double, void *)")
        def on_progress(time, end_time, user):
            try:
                return 1 if progress(time, end_time) else 0
            except BaseException as exception:  # never unwind through C
                raised.append(exception)
                return 1

        status = lib.sinter_scene_run(scene, os.fsencode(out_dir),
                                      on_progress if progress is not None else ffi.NULL,
                                      ffi.NULL)
        if raised:
            raise raised[0]
        _check(lib, ctx, status, ffi)
        return _final_state(ffi, lib, ctx, scene)
    finally:
        if scene != ffi.NULL:
            lib.sinter_scene_destroy(scene)
        lib.sinter_ctx_destroy(ctx)


def _final_state(ffi, lib, ctx, scene):
    stepper_out = ffi.new("sinter_stepper **")
    particles_out = ffi.new("sinter_particles **")
    _check(lib, ctx, lib.sinter_scene_get_stepper(scene, stepper_out), ffi)
    _check(lib, ctx, lib.sinter_scene_get_particles(scene, particles_out), ffi)
    end_time, time = ffi.new("double *"), ffi.new("double *")
    _check(lib, ctx, lib.sinter_scene_end_time(scene, end_time), ffi)
    _check(lib, ctx, lib.sinter_stepper_time(stepper_out[0], time), ffi)
    stats = ffi.new("sinter_stepper_stats *")
    stats.struct_size = ffi.sizeof("sinter_stepper_stats")
    _check(lib, ctx, lib.sinter_stepper_get_stats(stepper_out[0], stats), ffi)
    fields = {}
    for name, field in (("position", lib.SINTER_FIELD_POSITION),
                        ("temperature", lib.SINTER_FIELD_TEMPERATURE)):
        data, count, components = ffi.new("void **"), ffi.new("size_t *"), ffi.new("size_t *")
        ps = particles_out[0]
        _check(lib, ctx, lib.sinter_particles_view_read(ps, field, data, count, components), ffi)
        try:
            values = ffi.cast("const double *", data[0])
            flat = [values[k] for k in range(count[0] * components[0])]
        finally:
            lib.sinter_particles_release(ps, field)
        width = components[0]
        fields[name] = (flat if width == 1 else
                        [tuple(flat[k:k + width]) for k in range(0, len(flat), width)])
    return {"end_time": end_time[0], "time": time[0], "steps": stats.steps,
            "position": fields["position"], "temperature": fields["temperature"]}


def _check(lib, ctx, status, ffi):
    if status != 0:
        message = ffi.string(lib.sinter_last_error(ctx)).decode("utf-8", "replace") \
            if ctx is not None else ""
        if not message:
            message = ffi.string(lib.sinter_status_string(status)).decode()
        raise CffiError(status, message)
