"""The library context, the common life cycle of handles, and the version."""

import ctypes
import enum
import logging
import weakref
from typing import Callable, Optional, Union

from . import _callbacks
from ._errors import Status, check
from ._lib import CtxPtr, LogFn, lib, text


def version_string() -> str:
    """Runtime version of libsinter, "major.minor.patch"."""
    return text(lib.sinter_version_string())


def version_number() -> int:
    """Runtime version of libsinter as major*10000 + minor*100 + patch."""
    return lib.sinter_version_number()


class LogLevel(enum.IntEnum):
    """sinter_log_level, most severe first."""

    ERROR = 0
    WARNING = 1
    INFO = 2
    DEBUG = 3

    @property
    def logging_level(self) -> int:
        """The matching level of Python's logging module (logging.ERROR, ...)."""
        return _LOGGING_LEVELS[self]

    @classmethod
    def from_logging(cls, level: int) -> "LogLevel":
        """The most verbose LogLevel a logger of effective level `level` lets through."""
        if level <= logging.DEBUG:
            return cls.DEBUG
        if level <= logging.INFO:
            return cls.INFO
        if level <= logging.WARNING:
            return cls.WARNING
        return cls.ERROR


_LOGGING_LEVELS = {LogLevel.ERROR: logging.ERROR, LogLevel.WARNING: logging.WARNING,
                   LogLevel.INFO: logging.INFO, LogLevel.DEBUG: logging.DEBUG}

#: The logger that receives the library's messages by default.
LOGGER_NAME = "sinter"


class Context:
    """A sinter_ctx: owns the last error text, the log callback and the thread count.

    Every Material and Particles keeps a reference to its Context. close()
    (or leaving a ``with`` block) closes those objects first, then the context.

    threads: threads the library may use (None: the library's default, 1; 0: all).
    logger: where the library's messages go: a logging.Logger or a logger name (default
    "sinter"), at the logger's effective level (read again before each run, so that
    logging.getLogger("sinter").setLevel(logging.INFO) takes effect), or None for no
    messages at all. set_log installs a callback instead.
    """

    _handle = None
    _open_children = 0
    _close_pending = False

    def __init__(self, threads: Optional[int] = None,
                 logger: Union[logging.Logger, str, None] = LOGGER_NAME) -> None:
        handle = CtxPtr()
        check(lib.sinter_ctx_create(ctypes.byref(handle), None), None, "sinter_ctx_create")
        self._handle = handle
        self._children = weakref.WeakSet()
        self._open_children = 0
        self._close_pending = False
        self._log_function = None  # the installed CFUNCTYPE, kept alive here
        self._logger = None  # the logging.Logger messages go to, if any
        self._log_level = None  # the LogLevel installed for it
        if threads is not None:
            self.threads = threads
        if logger is not None:
            self.log_to(logger)

    # --- life cycle -----------------------------------------------------

    @property
    def closed(self) -> bool:
        """True once close() was called."""
        return self._handle is None or self._close_pending

    @property
    def _ptr(self):
        if self.closed:
            raise ValueError("the sinter Context is closed")
        return self._handle

    def close(self) -> None:
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
    def threads(self) -> int:
        """Threads the library may use internally (1 by default, 0 = all available)."""
        threads = ctypes.c_int()
        self._check(lib.sinter_ctx_get_threads(self._ptr, ctypes.byref(threads)),
                    "sinter_ctx_get_threads")
        return threads.value

    @threads.setter
    def threads(self, threads: int) -> None:
        self._check(lib.sinter_ctx_set_threads(self._ptr, threads), "sinter_ctx_set_threads")

    @property
    def last_error(self) -> str:
        """Detail of the last error reported on this context ("" if none)."""
        return text(lib.sinter_last_error(self._ptr))

    @property
    def last_status(self) -> Status:
        """Status of the last error reported on this context (Status.OK if none)."""
        return Status(lib.sinter_last_status(self._ptr))

    def request_stop(self) -> None:
        """Ask the running step loop of this context to stop after its current step.

        Safe from a signal handler or another thread; the run then fails with the status
        SINTER_ERR_INTERRUPTED, its last accepted state readable and checkpointable.
        """
        self._check(lib.sinter_ctx_request_stop(self._ptr), "sinter_ctx_request_stop")

    def clear_error(self) -> None:
        """Forget the last error."""
        self._check(lib.sinter_clear_error(self._ptr), "sinter_clear_error")

    def log_to(self, logger: Union[logging.Logger, str] = LOGGER_NAME) -> None:
        """Send the library's messages to a logging.Logger (or the logger of that name), at
        the logger's effective level: ERROR, WARNING, INFO and DEBUG messages become records
        of those levels."""
        if isinstance(logger, str):
            logger = logging.getLogger(logger)
        python_level = {level: level.logging_level for level in LogLevel}

        def forward(c_level, message, user):
            try:
                level = python_level.get(c_level, logging.DEBUG)
                logger.log(level, "%s", text(message))
            except BaseException:  # noqa: never unwind through C; logging reports its own
                pass

        function = LogFn(forward)
        level = LogLevel.from_logging(logger.getEffectiveLevel())
        self._check(lib.sinter_ctx_set_log(self._ptr, function, int(level), None),
                    "sinter_ctx_set_log")
        self._log_function, self._logger, self._log_level = function, logger, level

    def _sync_log_level(self) -> None:
        """Follow a change of the logger's level (called before each run)."""
        logger = self._logger
        if logger is None or self._handle is None:
            return
        level = LogLevel.from_logging(logger.getEffectiveLevel())
        if level != self._log_level:
            self._check(lib.sinter_ctx_set_log(self._handle, self._log_function, int(level),
                                               None), "sinter_ctx_set_log")
            self._log_level = level

    def set_log(self, callback: Optional[Callable[[LogLevel, str], None]],
                level: Union[LogLevel, int] = LogLevel.WARNING) -> None:
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
        self._log_function, self._logger, self._log_level = function, None, None


class _Handle:
    """Life cycle shared by the objects made from a Context.

    A handle may borrow others (a Stepper borrows its Particles, Walls and
    submodels; a Scene's Particles borrows the Scene): it holds a Python
    reference to each and counts as one of its users. close() makes a handle
    unusable at once, but its C object is destroyed only when no other handle
    uses it any more, so the library never sees a dangling pointer whatever
    the order of close() calls or of garbage collection.

    A borrowed handle (owned=False) wraps an object another C object owns
    (the particles of a scene): closing it destroys nothing.
    """

    _destroy_function = None  # name of the C destroy function
    _handle = None
    _users = 0
    _close_pending = False
    _owned = True
    _borrowed = ()

    def __init__(self, context: Context, handle: ctypes.c_void_p, owned: bool = True) -> None:
        self._context = context
        self._handle = handle
        self._owned = owned
        self._users = 0
        self._close_pending = False
        self._borrowed = []  # handles this one uses, released when its C object is gone
        context._register(self)

    @property
    def context(self) -> Context:
        """The Context this object was made from."""
        return self._context

    @property
    def closed(self) -> bool:
        """True once close() was called (its C object may wait for its users)."""
        return self._handle is None or self._close_pending

    @property
    def _ptr(self):
        if self.closed:
            raise ValueError("the sinter %s is closed" % type(self).__name__)
        return self._handle

    def _check(self, status, function):
        check(status, self._context._handle, function)

    def _call(self, c_function, *args, stopped=None, interruptible=False):
        """c_function(*args) for a call that may run Python callbacks: an exception one of
        them raised is raised here; otherwise the status is checked. Returns the status.
        interruptible: a run that Ctrl-C stops (KeyboardInterrupt; see _callbacks.call)."""
        return _callbacks.call(self._context._handle, c_function.__name__, c_function, *args,
                               stopped=stopped, interruptible=interruptible)

    # --- borrowing ------------------------------------------------------

    def _borrow(self, other):
        """Keep `other` (a handle this one's C object uses) alive and undestroyed."""
        other._users += 1
        self._borrowed.append(other)

    def _unborrow(self, other):
        """The C object no longer uses `other`: drop one use of it."""
        for k, held in enumerate(self._borrowed):
            if held is other:
                del self._borrowed[k]
                other._users -= 1
                other._destroy_if_unused()
                return

    def _keep(self, key, value):
        """Keep `value` (a C function pointer the library stores) while the C object lives.

        A borrowed handle's C object lives as long as its owner (a Scene), whose views
        may come and go: the value is kept there. A later value under the same key
        replaces the earlier one.
        """
        holder = self if self._owned or not self._borrowed else self._borrowed[0]
        holder.__dict__.setdefault("_kept", {})[key] = value

    # --- closing --------------------------------------------------------

    def _close_dependents(self):
        """Hook: close what must go before this handle (a Scene's borrowed views)."""

    def _forget(self):
        """Hook: drop Python objects the C object needed (callbacks), after it is destroyed."""

    def close(self) -> None:
        """Destroy the C object (once nothing uses it any more). Safe to call twice."""
        if self._handle is None or self._close_pending:
            return
        self._close_pending = True
        self._close_dependents()
        self._destroy_if_unused()

    def _destroy_if_unused(self):
        if self._users > 0 or not self._close_pending:
            return
        handle, self._handle = self._handle, None
        self._close_pending = False
        if handle is not None and self._owned:
            getattr(lib, self._destroy_function)(handle)
        self.__dict__.pop("_kept", None)
        self._forget()
        borrowed, self._borrowed = self._borrowed, []
        for other in borrowed:
            other._users -= 1
            other._destroy_if_unused()
        if handle is not None:
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
