"""Python functions as C callbacks: exception transport and zero-copy struct views.

A Python exception must never unwind through the C library. Every
trampoline catches it, stores it here (per thread) and returns a failure
code; the library then stops (SINTER_ERR_CALLBACK, keeping the last accepted
state) and the Python method that made the C call raises the stored
exception itself, with its original traceback.

The structs a host submodel receives (sinter_state_view, sinter_contact_batch)
are wrapped by StateView and ContactBatch, whose array attributes are built
on first access as NumPy arrays over the library's memory (memoryviews
without NumPy) and are valid only while the callback runs.
"""

import ctypes
import enum
import signal
import threading

from ._errors import check
from ._lib import lib, text

_pending = threading.local()


def store(exception):
    """Remember the first exception raised by a callback during the current C call."""
    if getattr(_pending, "exception", None) is None:
        _pending.exception = exception


def clear():
    """Forget an exception left by an earlier C call (called before each guarded call)."""
    _pending.exception = None


def take():
    """The stored exception (or None), forgetting it."""
    exception = getattr(_pending, "exception", None)
    _pending.exception = None
    return exception


class CallbackResult(enum.IntEnum):
    """sinter_callback_result: what a host submodel's function may return (None means OK)."""

    OK = 0
    RETRY = 1  #: ask the stepper to retry the step with a smaller one
    FATAL = -1  #: stop the stepper (SINTER_ERR_CALLBACK)


class ContactKind(enum.IntEnum):
    """sinter_contact_kind: the kind of the contacts of a ContactBatch (.contact_kind)."""

    PARTICLE = 0  #: particle i with particle j
    WALL = 1  #: particle i with wall j


def result_code(value):
    """A callback's return value as the library's int: None/0 -> 0, > 0 -> 1 (retry), < 0 -> -1."""
    if value is None or value is False:
        return 0
    value = int(value)
    return (value > 0) - (value < 0)


def call(ctx_handle, function, c_function, *args, stopped=None, interruptible=False):
    # function: the C function's name for messages (c_function may be a test's wrapper)
    """Call c_function(*args), which may run Python callbacks, and check the status.

    If a callback raised, that exception is raised here (the library's error
    text is added as a note where Python supports notes). `stopped`, when
    given, is a callable returning true when a callback asked to stop: a
    SINTER_ERR_CALLBACK or SINTER_ERR_INTERRUPTED status is then not an error.

    interruptible: a run (advance, step, scene run) that Ctrl-C must stop. Called from the
    main thread, the C function then runs in a worker thread (ctypes releases the GIL) while
    the main thread waits, so that SIGINT is handled at once: it asks the library to stop
    (sinter_ctx_request_stop), which ends the run after its current step with the last
    accepted state kept, and KeyboardInterrupt is raised here.
    Returns the status.
    """
    interrupted = False
    if interruptible and ctx_handle and threading.current_thread() is threading.main_thread():
        status, exception, interrupted = _run_interruptible(ctx_handle, c_function, args)
    else:
        clear()
        try:
            status = c_function(*args)
        finally:
            exception = take()
    if exception is not None:
        if status != 0 and ctx_handle and hasattr(exception, "add_note"):
            message = _last_error(ctx_handle)
            if message:
                exception.add_note("libsinter: %s" % message)
        raise exception
    if interrupted:
        raise KeyboardInterrupt
    if stopped is not None and status != 0 and stopped():
        return status
    check(status, ctx_handle, function)
    return status


#: How often [s] the main thread wakes while a run goes on in the worker thread.
_POLL_SECONDS = 0.05


def _run_interruptible(ctx_handle, c_function, args):
    """(status, exception raised by a callback or None, True if SIGINT stopped the run)."""
    outcome = {}

    def work():
        clear()
        try:
            outcome["status"] = c_function(*args)
        except BaseException as exception:  # an argument ctypes refused
            outcome["error"] = exception
        finally:
            outcome["exception"] = take()

    interrupted = []

    def on_sigint(signum, frame):
        interrupted.append(signum)
        lib.sinter_ctx_request_stop(ctx_handle)

    previous = _install_sigint(on_sigint)
    worker = threading.Thread(target=work, name="sinter-run", daemon=True)
    try:
        worker.start()
        try:
            while worker.is_alive():
                worker.join(_POLL_SECONDS)
        except BaseException:
            # A Python-level SIGINT handler of the host (or another signal's handler) raised:
            # stop the run at its current step, wait for it, and let the exception go on.
            lib.sinter_ctx_request_stop(ctx_handle)
            _join(worker, ctx_handle)
            raise
    finally:
        if previous is not None:
            signal.signal(signal.SIGINT, previous)
    if "error" in outcome:
        raise outcome["error"]
    return outcome["status"], outcome["exception"], bool(interrupted)


def _install_sigint(handler):
    """Install `handler` for SIGINT while Python's default handler (KeyboardInterrupt) is in
    place; return the handler to restore, or None when nothing was installed (SIGINT ignored,
    or a host's own handler, which then runs as usual)."""
    try:
        if signal.getsignal(signal.SIGINT) is not signal.default_int_handler:
            return None
        return signal.signal(signal.SIGINT, handler)
    except (ValueError, OSError, AttributeError):  # not the main interpreter, no signals
        return None


def _join(worker, ctx_handle):
    """Wait for the worker; a further Ctrl-C asks the library to stop again."""
    while worker.is_alive():
        try:
            worker.join(_POLL_SECONDS)
        except BaseException:
            lib.sinter_ctx_request_stop(ctx_handle)


def _last_error(ctx_handle):
    return text(lib.sinter_last_error(ctx_handle))


# --- zero-copy arrays over C memory -------------------------------------

_CTYPES = {"d": ctypes.c_double, "i": ctypes.c_int32, "I": ctypes.c_uint32}


def array(address, shape, fmt, writable):
    """A NumPy array (or memoryview) of `shape` over C memory at `address`, without copying.

    None when the pointer is NULL and the array would not be empty.
    """
    size = 1
    for extent in shape:
        size *= extent
    from . import particles  # the switch USE_NUMPY lives there (imported late: no cycle)

    numpy = particles.numpy if particles.USE_NUMPY else None
    if size == 0:
        if numpy is not None:
            empty = numpy.zeros(shape, dtype=fmt)
            empty.flags.writeable = writable
            return empty
        return memoryview(bytearray() if writable else b"").cast(fmt)
    if not address:
        return None
    buffer = memoryview((_CTYPES[fmt] * size).from_address(address)).cast("B")
    if not writable:
        buffer = buffer.toreadonly()
    if numpy is not None:
        return numpy.frombuffer(buffer, dtype=fmt).reshape(shape)
    return buffer.cast(fmt, shape)


class _StructArrays:
    """Lazy array attributes over a borrowed C struct; unusable after invalidate()."""

    # attribute -> (struct field, element format, rows attribute, columns (int or attribute
    # name), writable)
    _ARRAYS = {}
    _SCALARS = ()

    def __init__(self, struct: ctypes.Structure) -> None:
        self._struct = struct
        self._valid = True
        self._made = []

    def __getattr__(self, name):
        spec = type(self)._ARRAYS.get(name)
        if spec is None:
            if name in type(self)._SCALARS:
                self._require_valid()
                return getattr(self._struct, name)
            raise AttributeError("%s has no attribute %r" % (type(self).__name__, name))
        self._require_valid()
        field, fmt, rows, columns, writable = spec
        rows = getattr(self._struct, rows)
        columns = columns if isinstance(columns, int) else getattr(self._struct, columns)
        shape = (rows,) if columns == 1 and name not in ("history", "history_trial") \
            else (rows, columns)
        address = getattr(self._struct, field)
        # Outputs a model may not write (a heat model's force) are NULL: None, not an array.
        value = None if writable and not address else array(address, shape, fmt, writable)
        self.__dict__[name] = value
        self._made.append(name)
        return value

    def _require_valid(self):
        if not self._valid:
            raise ValueError("%s used after its callback returned: its arrays belonged to the "
                             "library for the duration of the call only" % type(self).__name__)

    def invalidate(self) -> None:
        """Drop the arrays (memoryviews are released, so later use raises ValueError)."""
        self._valid = False
        for name in self._made:
            value = self.__dict__.pop(name, None)
            if isinstance(value, memoryview):
                try:
                    value.release()
                except BufferError:  # the callback kept a derived view
                    pass
        self._made = []
        self._struct = None

    def __repr__(self):
        if not self._valid:
            return "<sinter.%s (expired)>" % type(self).__name__
        return "<sinter.%s count=%d>" % (type(self).__name__, self._struct.count)


class StateView(_StructArrays):
    """The state a host submodel reads (sinter_state_view), read-only, SI units.

    Arrays: position, velocity, spin (count, 3); radius, mass, inertia,
    temperature (count,); material (count,) int32; wall_point, wall_normal,
    wall_velocity (wall_count, 3). Scalars: count, wall_count, time [s], dt [s].
    """

    _ARRAYS = {
        "position": ("position", "d", "count", 3, False),
        "velocity": ("velocity", "d", "count", 3, False),
        "spin": ("spin", "d", "count", 3, False),
        "radius": ("radius", "d", "count", 1, False),
        "mass": ("mass", "d", "count", 1, False),
        "inertia": ("inertia", "d", "count", 1, False),
        "temperature": ("temperature", "d", "count", 1, False),
        "material": ("material", "i", "count", 1, False),
        "wall_point": ("wall_point", "d", "wall_count", 3, False),
        "wall_normal": ("wall_normal", "d", "wall_count", 3, False),
        "wall_velocity": ("wall_velocity", "d", "wall_count", 3, False),
    }
    _SCALARS = ("count", "wall_count", "time", "dt")


class ContactBatch(_StructArrays):
    """A batch of active contacts (sinter_contact_batch), SI units.

    kind is "particle" (i with particle j) or "wall" (i with wall j). Read-only
    arrays: i, j (count,) uint32; normal (count, 3) from i towards j; overlap,
    distance, contact_radius, area, branch (count,); history (count,
    history_size). Written by a force model: force, torque_i, torque_j
    (count, 3), zeroed before the call, and history_trial (count,
    history_size). In the batches of a heat model the written arrays are None.
    """

    _ARRAYS = {
        "i": ("i", "I", "count", 1, False),
        "j": ("j", "I", "count", 1, False),
        "normal": ("normal", "d", "count", 3, False),
        "overlap": ("overlap", "d", "count", 1, False),
        "distance": ("distance", "d", "count", 1, False),
        "contact_radius": ("contact_radius", "d", "count", 1, False),
        "area": ("area", "d", "count", 1, False),
        "branch": ("branch", "d", "count", 1, False),
        "history": ("history", "d", "count", "history_size", False),
        "history_trial": ("history_trial", "d", "count", "history_size", True),
        "force": ("force", "d", "count", 3, True),
        "torque_i": ("torque_i", "d", "count", 3, True),
        "torque_j": ("torque_j", "d", "count", 3, True),
    }
    _SCALARS = ("count", "history_size")

    @property
    def kind(self) -> str:
        """"particle" or "wall" (the name of contact_kind in lower case)."""
        self._require_valid()
        return "wall" if self._struct.kind == 1 else "particle"

    @property
    def contact_kind(self) -> ContactKind:
        """ContactKind.PARTICLE or ContactKind.WALL."""
        self._require_valid()
        return ContactKind(self._struct.kind)

    def __len__(self):
        self._require_valid()
        return self._struct.count

    def __repr__(self):
        if not self._valid:
            return "<sinter.ContactBatch (expired)>"
        return "<sinter.ContactBatch %s count=%d>" % (self.kind, self._struct.count)


class NeckLawBatch(_StructArrays):
    """The quasi-static stepper's links for a host neck law (sinter_neck_law_batch), SI units.

    Scalars: count, time [s], dt [s] (advance each pair freely from time to time + dt),
    schedule_count. Read-only arrays: schedule_time [s], schedule_temperature [K]
    (schedule_count,): T(t) piecewise linear, constant outside; a, b (count,) uint32 particle
    indices; material (count,) int32 of particle a; radius_a, radius_b (count,) [m].
    Written: state (count, 7; index it as state[k, i]), in at time, out at time + dt: [0] the neck radius x, [3] and [6]
    L_A, L_B (centre to neck plane; their decrease is the free approach), [1] and [4] the
    radii, [2] and [5] the law's own; every value finite and > 0.
    """

    _ARRAYS = {
        "schedule_time": ("schedule_time", "d", "schedule_count", 1, False),
        "schedule_temperature": ("schedule_temperature", "d", "schedule_count", 1, False),
        "a": ("a", "I", "count", 1, False),
        "b": ("b", "I", "count", 1, False),
        "material": ("material", "i", "count", 1, False),
        "radius_a": ("radius_a", "d", "count", 1, False),
        "radius_b": ("radius_b", "d", "count", 1, False),
        "state": ("state", "d", "count", 7, True),
    }
    _SCALARS = ("count", "time", "dt", "schedule_count")

    def __len__(self):
        self._require_valid()
        return self._struct.count
