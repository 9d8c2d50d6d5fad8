"""The library context, the common life cycle of handles, and the version."""

import ctypes
import enum
import weakref

from ._errors import Status, check
from ._lib import CtxPtr, LogFn, lib, text


def version_string():
    """Runtime version of libsinter, "major.minor.patch"."""
    return text(lib.sinter_version_string())


def version_number():
    """Runtime version of libsinter as major*10000 + minor*100 + patch."""
    return lib.sinter_version_number()


class LogLevel(enum.IntEnum):
    """sinter_log_level, most severe first."""

    ERROR = 0
    WARNING = 1
    INFO = 2
    DEBUG = 3


class Context:
    """A sinter_ctx: owns the last error text, the log callback and the thread count.

    Every Material and Particles keeps a reference to its Context. close()
    (or leaving a ``with`` block) closes those objects first, then the context.
    """

    _handle = None
    _open_children = 0
    _close_pending = False

    def __init__(self, threads=None):
        handle = CtxPtr()
        check(lib.sinter_ctx_create(ctypes.byref(handle), None), None, "sinter_ctx_create")
        self._handle = handle
        self._children = weakref.WeakSet()
        self._open_children = 0
        self._close_pending = False
        self._log_function = None  # the installed CFUNCTYPE, kept alive here
        if threads is not None:
            self.threads = threads

    # --- life cycle -----------------------------------------------------

    @property
    def closed(self):
        return self._handle is None or self._close_pending

    @property
    def _ptr(self):
        if self.closed:
            raise ValueError("the sinter Context is closed")
        return self._handle

    def close(self):
        """Close every object made from this context, then the context itself."""
        for child in list(self._children):
            child.close()
        self._destroy_when_unused()

    def _destroy_when_unused(self):
        # Children still open here are being finalized in the same garbage
        # cycle as this context; the last of them destroys it (_unregister).
        if self._open_children > 0:
            self._close_pending = True
            return
        handle, self._handle = self._handle, None
        if handle is not None:
            lib.sinter_ctx_destroy(handle)
        self._log_function = None

    def _register(self, child):
        self._children.add(child)
        self._open_children += 1

    def _unregister(self, child):
        self._children.discard(child)
        self._open_children -= 1
        if self._close_pending and self._open_children == 0:
            self._close_pending = False
            self._destroy_when_unused()

    def __enter__(self):
        self._ptr
        return self

    def __exit__(self, *exc_info):
        self.close()

    def __del__(self):
        try:
            self._destroy_when_unused()
        except Exception:  # interpreter shutdown: modules may be gone
            pass

    def __repr__(self):
        return "<sinter.Context %s>" % ("closed" if self.closed else "threads=%d" % self.threads)

    # --- settings and errors ----------------------------------------------

    def _check(self, status, function):
        check(status, self._handle, function)

    @property
    def threads(self):
        """Threads the library may use internally (1 by default, 0 = all available)."""
        threads = ctypes.c_int()
        self._check(lib.sinter_ctx_get_threads(self._ptr, ctypes.byref(threads)),
                    "sinter_ctx_get_threads")
        return threads.value

    @threads.setter
    def threads(self, threads):
        self._check(lib.sinter_ctx_set_threads(self._ptr, threads), "sinter_ctx_set_threads")

    @property
    def last_error(self):
        """Detail of the last error reported on this context ("" if none)."""
        return text(lib.sinter_last_error(self._ptr))

    @property
    def last_status(self):
        """Status of the last error reported on this context (Status.OK if none)."""
        return Status(lib.sinter_last_status(self._ptr))

    def clear_error(self):
        """Forget the last error."""
        self._check(lib.sinter_clear_error(self._ptr), "sinter_clear_error")

    def set_log(self, callback, level=LogLevel.WARNING):
        """Install callback(level: LogLevel, message: str), or None to remove it.

        Messages up to `level` (most verbose level passed) reach the callback,
        synchronously. Exceptions raised by the callback cannot cross the C
        library; ctypes prints them to stderr.
        """
        if callback is None:
            function = LogFn()  # NULL
        else:
            def trampoline(c_level, message, user):
                callback(LogLevel(c_level), text(message))

            function = LogFn(trampoline)
        self._check(lib.sinter_ctx_set_log(self._ptr, function, int(level), None),
                    "sinter_ctx_set_log")
        self._log_function = function


class _Handle:
    """Life cycle shared by the objects made from a Context (Material, Particles)."""

    _destroy_function = None  # name of the C destroy function
    _handle = None

    def __init__(self, context, handle):
        self._context = context
        self._handle = handle
        context._register(self)

    @property
    def context(self):
        return self._context

    @property
    def closed(self):
        return self._handle is None

    @property
    def _ptr(self):
        if self._handle is None:
            raise ValueError("the sinter %s is closed" % type(self).__name__)
        return self._handle

    def _check(self, status, function):
        check(status, self._context._handle, function)

    def close(self):
        """Destroy the C object. Safe to call twice."""
        handle, self._handle = self._handle, None
        if handle is not None:
            getattr(lib, self._destroy_function)(handle)
            self._context._unregister(self)

    def __enter__(self):
        self._ptr
        return self

    def __exit__(self, *exc_info):
        self.close()

    def __del__(self):
        try:
            self.close()
        except Exception:  # interpreter shutdown: modules may be gone
            pass
