"""libsinter_mpi from Python (sinter_mpi.h, sinter_mpi_decomp.h; issue 44).

A Python host that runs under ``mpiexec`` hands libsinter_mpi an mpi4py communicator: a
Domain duplicates it, decomposes the global box into one part per rank, and is installed as
the collective operations of this rank's explicit stepper (attach), which then migrates
particles, trades ghosts and halos and reduces through MPI by itself::

    from mpi4py import MPI
    import sinter, sinter.mpi

    with sinter.mpi.Domain(MPI.COMM_WORLD, lo, hi) as dom:
        ...                               # every rank: Context, Particles (rank 0 fills it),
        dom.attach(stepper, particles)    # Walls and Stepper set up alike
        dom.distribute()                  # each particle to the rank whose part holds it
        stepper.step(100)

Importing this module needs neither MPI nor mpi4py: the companion library
``libsinter_mpi.so`` (a build with ``-DSINTER_MPI=ON``) is loaded at the first use, from
SINTER_MPI_LIBRARY when set, else next to the libsinter the package loaded, else from the
system; MpiUnavailable says what was tried when it is not there. Lengths in m, times in s.
Every call marked collective must be made by every rank of the communicator in the same order.
"""

import ctypes
import ctypes.util
import dataclasses
import enum
import os
from typing import Any, Dict, List, Optional, Sequence, Tuple

from . import _lib
from ._errors import error
from ._lib import LibraryNotFound, lib, text
from .domain import ReduceOp, ReduceType


class MpiUnavailable(LibraryNotFound):
    """libsinter_mpi or mpi4py cannot be loaded (a build without -DSINTER_MPI=ON, or no
    mpi4py for this interpreter); the message says what was tried."""


class DecompKind(enum.IntEnum):
    """sinter_mpi_decomp_kind."""

    BRICK = 0  #: g0 x g1 x g2 equal boxes (static)
    RCB = 1  #: recursive coordinate bisection with weights


#: sinter_mpi_attach's flag: rebalance at every neighbour-list rebuild.
ATTACH_BALANCE = 1

DomainPtr = _lib._opaque("sinter_mpi_domain")
DecompPtr = _lib._opaque("sinter_mpi_decomp")

_P = ctypes.POINTER
_int, _size, _double, _u64 = ctypes.c_int, ctypes.c_size_t, ctypes.c_double, ctypes.c_uint64
_status = _lib.c_status
_void = ctypes.c_void_p


class MpiOptions(ctypes.Structure):
    """struct sinter_mpi_options (lengths in m)."""

    _cname = "sinter_mpi_options"
    _fields_ = [("struct_size", _size), ("decomposition", _int), ("grid", _int * 3),
                ("lo", _double * 3), ("hi", _double * 3), ("balance_threshold", _double)]


class _CStats(ctypes.Structure):
    _cname = "sinter_mpi_stats"
    _fields_ = [("struct_size", _size), ("reductions", _u64), ("reduce_bytes", _u64),
                ("rebalances", _u64), ("seconds_comm", _double)]


class _CExchangeStats(ctypes.Structure):
    _cname = "sinter_mpi_exchange_stats"
    _fields_ = [("struct_size", _size), ("halos", _u64), ("redistributions", _u64),
                ("messages_sent", _u64), ("bytes_sent", _u64), ("bytes_received", _u64),
                ("migrated_out", _u64), ("migrated_in", _u64), ("global_migrations", _u64),
                ("graph_builds", _u64), ("ghosts", _u64), ("owned", _u64), ("neighbours", _int),
                ("imbalance", _double), ("seconds_comm", _double)]


@dataclasses.dataclass(frozen=True)
class MpiStats:
    """This rank's reduction counters (sinter_mpi_stats; seconds_comm in s)."""

    reductions: int
    reduce_bytes: int
    rebalances: int
    seconds_comm: float


@dataclasses.dataclass(frozen=True)
class ExchangeStats:
    """This rank's exchange counters of the attached stepper, cumulative since the attach
    (sinter_mpi_exchange_stats; seconds_comm in s): take differences for per-step figures."""

    halos: int
    redistributions: int
    messages_sent: int
    bytes_sent: int
    bytes_received: int
    migrated_out: int
    migrated_in: int
    global_migrations: int
    graph_builds: int
    ghosts: int
    owned: int
    neighbours: int
    imbalance: float
    seconds_comm: float


def _signatures(comm):
    """name: (restype, argtypes) of every function of sinter_mpi.h and sinter_mpi_decomp.h,
    in the headers' order; `comm` is the ctypes type of MPI_Comm in this MPI."""
    p_dom, p_dec = DomainPtr, DecompPtr
    return {
        # sinter_mpi_decomp.h
        "sinter_mpi_decomp_brick": (_status, [_P(p_dec), _int, _P(_int), _P(_double),
                                              _P(_double)]),
        "sinter_mpi_decomp_rcb": (_status, [_P(p_dec), _int, _P(_double), _P(_double),
                                            _P(_double), _P(_double), _size, _void, _void]),
        "sinter_mpi_decomp_destroy": (None, [p_dec]),
        "sinter_mpi_decomp_info": (_status, [p_dec, _P(_int), _P(_int)]),
        "sinter_mpi_decomp_grid": (_status, [p_dec, _P(_int)]),
        "sinter_mpi_decomp_box": (_status, [p_dec, _int, _P(_double), _P(_double)]),
        "sinter_mpi_decomp_owners": (_status, [p_dec, _P(_double), _size, _P(_int)]),
        "sinter_mpi_decomp_loads": (_status, [p_dec, _P(_double), _P(_double), _size, _void,
                                              _void, _P(_double)]),
        "sinter_mpi_imbalance": (_status, [_P(_double), _int, _P(_double)]),
        "sinter_mpi_decomp_rebalance": (_status, [p_dec, _P(_double), _P(_double), _size,
                                                  _double, _void, _void, _P(_double), _P(_int)]),
        # sinter_mpi.h
        "sinter_mpi_options_init": (_status, [_P(MpiOptions), _size]),
        "sinter_mpi_domain_create": (_status, [_P(p_dom), comm, _P(MpiOptions)]),
        "sinter_mpi_domain_destroy": (None, [p_dom]),
        "sinter_mpi_domain_rank": (_status, [p_dom, _P(_int), _P(_int)]),
        "sinter_mpi_domain_comm": (_status, [p_dom, _P(comm)]),
        "sinter_mpi_domain_decomp": (_status, [p_dom, _P(p_dec)]),
        "sinter_mpi_reduce": (_int, [_void, _size, _int, _int, _void]),
        "sinter_mpi_exscan": (_int, [_u64, _P(_u64), _P(_u64), _void]),
        "sinter_mpi_sum": (_status, [p_dom, _P(_double), _size, _P(_double)]),
        "sinter_mpi_balance": (_status, [p_dom, _P(_double), _P(_double), _size, _P(_double),
                                         _P(_int)]),
        "sinter_mpi_get_stats": (_status, [p_dom, _P(_CStats)]),
        "sinter_mpi_checkpoint_write": (_status, [_lib.StepperPtr, _lib.ParticlesPtr, comm,
                                                  ctypes.c_char_p]),
        "sinter_mpi_checkpoint_read": (_status, [_lib.StepperPtr, _lib.ParticlesPtr, comm,
                                                 ctypes.c_char_p, p_dec, _P(_size)]),
        "sinter_mpi_attach": (_status, [p_dom, _lib.StepperPtr, _lib.ParticlesPtr, _int]),
        "sinter_mpi_distribute": (_status, [p_dom]),
        "sinter_mpi_get_exchange_stats": (_status, [p_dom, _P(_CExchangeStats)]),
    }


#: The names of _signatures (the binding tests compare them with the headers).
FUNCTIONS = tuple(_signatures(_void))

_loaded: Dict[str, Any] = {}


def library_candidates(environ: Optional[Dict[str, str]] = None) -> List[str]:
    """The paths or names tried for libsinter_mpi, in order: SINTER_MPI_LIBRARY alone when
    set; else libsinter_mpi.so beside the loaded libsinter, then an installed one."""
    environ = os.environ if environ is None else environ
    explicit = environ.get("SINTER_MPI_LIBRARY")
    if explicit:
        return [explicit]
    candidates = []
    if _lib.library_path and os.path.sep in _lib.library_path:
        folder = os.path.dirname(os.path.realpath(_lib.library_path))
        candidates.append(os.path.join(folder, "libsinter_mpi.so"))
    installed = ctypes.util.find_library("sinter_mpi")
    if installed:
        candidates.append(installed)
    candidates.append("libsinter_mpi.so.0")
    return list(dict.fromkeys(candidates))


def _mpi4py():
    try:
        from mpi4py import MPI
    except ImportError as err:
        raise MpiUnavailable("sinter.mpi needs mpi4py (Debian: python3-mpi4py): %s" % err)
    return MPI


def _state():
    """(mpi4py's MPI, the declared libsinter_mpi, the ctypes type of MPI_Comm), loaded once."""
    if _loaded:
        return _loaded["MPI"], _loaded["lib"], _loaded["comm"]
    tried, cdll = [], None
    for candidate in library_candidates():
        try:
            cdll = ctypes.CDLL(candidate, mode=ctypes.RTLD_GLOBAL)
        except OSError as err:
            tried.append("%s (%s)" % (candidate, err))
            continue
        if hasattr(cdll, "sinter_mpi_domain_create"):
            break
        tried.append("%s (not libsinter_mpi)" % candidate)
        cdll = None
    if cdll is not None:  # then MPI itself (mpi4py initialises it on import)
        MPI = _mpi4py()
        # Open MPI's MPI_Comm is a pointer, MPICH's an int: the handle's size says which
        comm_type = _void if MPI._sizeof(MPI.Comm) == ctypes.sizeof(_void) else ctypes.c_int
        for name, (restype, argtypes) in _signatures(comm_type).items():
            function = getattr(cdll, name)
            function.restype, function.argtypes = restype, argtypes
        _loaded.update(MPI=MPI, lib=cdll, comm=comm_type, path=candidate)
        return MPI, cdll, comm_type
    raise MpiUnavailable("cannot load libsinter_mpi (build libsinter with -DSINTER_MPI=ON, or "
                         "set SINTER_MPI_LIBRARY); tried:\n  " + "\n  ".join(tried))


def available() -> bool:
    """True when mpi4py and libsinter_mpi both load."""
    try:
        _state()
    except MpiUnavailable:
        return False
    return True


def comm_handle(comm: Any) -> Any:
    """The C MPI_Comm of an mpi4py communicator, as its ctypes type (mpi4py's _handleof)."""
    MPI, _, comm_type = _state()
    if not isinstance(comm, MPI.Comm):
        raise TypeError("an mpi4py communicator is needed, not %r" % (comm,))
    return comm_type(MPI._handleof(comm))


def _check(status, function):
    if status != 0:
        raise error(status, "%s: %s" % (function, text(lib.sinter_status_string(status))))


def _doubles(values, per=1):
    """A flat ctypes double array of a sequence of numbers (per = 1) or of triples."""
    flat = [float(x) for row in values for x in (row if per > 1 else (row,))]
    if len(flat) % per:
        raise ValueError("a multiple of %d numbers is needed" % per)
    return (_double * max(1, len(flat)))(*flat), len(flat) // per


def _triple(values, name):
    values = [float(x) for x in values]
    if len(values) != 3:
        raise ValueError("%s: three numbers (x, y, z) are needed" % name)
    return (_double * 3)(*values)


class Decomposition:
    """A decomposition of space into parts 0 .. parts-1 (sinter_mpi_decomp): a brick or a
    recursive coordinate bisection. Not collective unless a method says so."""

    def __init__(self, handle: Any, owner: Any = None) -> None:
        """Wrap a C handle (use brick() or rcb()); `owner` is a Domain that owns the handle
        (a borrowed view, valid until that domain rebalances), None when this object owns it."""
        self._handle, self._owner = handle, owner

    @classmethod
    def brick(cls, parts: int, lo: Sequence[float], hi: Sequence[float],
              grid: Optional[Sequence[int]] = None) -> "Decomposition":
        """`parts` equal boxes over [lo, hi]; grid: boxes per axis (zeros chosen)."""
        _, mpi, _ = _state()
        out = DecompPtr()
        c_grid = (_int * 3)(*(grid if grid is not None else (0, 0, 0)))
        _check(mpi.sinter_mpi_decomp_brick(ctypes.byref(out), int(parts), c_grid,
                                           _triple(lo, "lo"), _triple(hi, "hi")),
               "sinter_mpi_decomp_brick")
        return cls(out)

    @classmethod
    def rcb(cls, parts: int, lo: Sequence[float], hi: Sequence[float],
            positions: Sequence[Sequence[float]], weights: Optional[Sequence[float]] = None,
            domain: Optional["Domain"] = None) -> "Decomposition":
        """A bisection of the points into `parts` boxes of [lo, hi]. With `domain`: collective
        over its ranks, each passing its own points; without: these points are all of them."""
        _, mpi, _ = _state()
        xyz, n = _doubles(positions, 3)
        w = _doubles(weights)[0] if weights is not None else None
        if weights is not None and len(weights) != n:
            raise ValueError("%d weights for %d points" % (len(weights), n))
        reduce, user = _reduce_of(domain)
        out = DecompPtr()
        _check(mpi.sinter_mpi_decomp_rcb(ctypes.byref(out), int(parts), _triple(lo, "lo"),
                                         _triple(hi, "hi"), xyz, w, n, reduce, user),
               "sinter_mpi_decomp_rcb")
        return cls(out)

    @property
    def _ptr(self) -> Any:
        if self._handle is None:
            raise ValueError("the Decomposition is closed")
        return self._handle

    def close(self) -> None:
        """Destroy an owned decomposition (a domain's view is only dropped). Safe twice."""
        if self._handle is not None and self._owner is None:
            _state()[1].sinter_mpi_decomp_destroy(self._handle)
        self._handle = None

    def __del__(self) -> None:
        try:
            self.close()
        except Exception:  # interpreter shutdown
            pass

    def info(self) -> Tuple[DecompKind, int]:
        """(kind, number of parts)."""
        kind, parts = _int(), _int()
        _check(_state()[1].sinter_mpi_decomp_info(self._ptr, ctypes.byref(kind),
                                                  ctypes.byref(parts)), "sinter_mpi_decomp_info")
        return DecompKind(kind.value), parts.value

    @property
    def kind(self) -> DecompKind:
        """BRICK or RCB."""
        return self.info()[0]

    @property
    def parts(self) -> int:
        """The number of parts."""
        return self.info()[1]

    @property
    def grid(self) -> Tuple[int, int, int]:
        """A brick's boxes per axis (SinterError, status ERR_STATE, for a bisection)."""
        grid = (_int * 3)()
        _check(_state()[1].sinter_mpi_decomp_grid(self._ptr, grid), "sinter_mpi_decomp_grid")
        return tuple(grid)

    def box(self, part: int) -> Tuple[Tuple[float, ...], Tuple[float, ...]]:
        """(lo, hi) of a part [m]."""
        lo, hi = (_double * 3)(), (_double * 3)()
        _check(_state()[1].sinter_mpi_decomp_box(self._ptr, int(part), lo, hi),
               "sinter_mpi_decomp_box")
        return tuple(lo), tuple(hi)

    def owners(self, positions: Sequence[Sequence[float]]) -> List[int]:
        """The part owning each point."""
        xyz, n = _doubles(positions, 3)
        parts = (_int * max(1, n))()
        _check(_state()[1].sinter_mpi_decomp_owners(self._ptr, xyz, n, parts),
               "sinter_mpi_decomp_owners")
        return list(parts)[:n]

    def loads(self, positions: Sequence[Sequence[float]],
              weights: Optional[Sequence[float]] = None,
              domain: Optional["Domain"] = None) -> List[float]:
        """The load of every part (the exact sum of the weights, 1 each by default, of the
        points it owns); collective over `domain`'s ranks when given."""
        xyz, n = _doubles(positions, 3)
        w = _doubles(weights)[0] if weights is not None else None
        reduce, user = _reduce_of(domain)
        parts = self.parts
        loads = (_double * parts)()
        _check(_state()[1].sinter_mpi_decomp_loads(self._ptr, xyz, w, n, reduce, user, loads),
               "sinter_mpi_decomp_loads")
        return list(loads)

    def rebalance(self, positions: Sequence[Sequence[float]], threshold: float = 1.1,
                  weights: Optional[Sequence[float]] = None,
                  domain: Optional["Domain"] = None) -> Tuple[float, bool]:
        """Bisect anew when the points' imbalance exceeds `threshold`; return (imbalance
        before, replaced). Collective over `domain`'s ranks when given."""
        if self._owner is not None:
            raise ValueError("a domain's decomposition changes through Domain.balance")
        xyz, n = _doubles(positions, 3)
        w = _doubles(weights)[0] if weights is not None else None
        reduce, user = _reduce_of(domain)
        imbalance, replaced = _double(), _int()
        _check(_state()[1].sinter_mpi_decomp_rebalance(
            self._ptr, xyz, w, n, float(threshold), reduce, user, ctypes.byref(imbalance),
            ctypes.byref(replaced)), "sinter_mpi_decomp_rebalance")
        return imbalance.value, bool(replaced.value)


def imbalance(loads: Sequence[float]) -> float:
    """The largest load over the mean (sinter_mpi_imbalance): 1 is perfect balance."""
    c_loads, n = _doubles(loads)
    out = _double()
    _check(_state()[1].sinter_mpi_imbalance(c_loads, n, ctypes.byref(out)),
           "sinter_mpi_imbalance")
    return out.value


def _reduce_of(domain):
    """(reduce function pointer, user) for a collective decomposition call, or (None, None)."""
    if domain is None:
        return None, None
    return ctypes.cast(_state()[1].sinter_mpi_reduce, _void), ctypes.cast(domain._ptr, _void)


class Domain:
    """A decomposed domain over a duplicate of an mpi4py communicator (sinter_mpi_domain).
    Creating and closing it are collective."""

    def __init__(self, comm: Any, lo: Sequence[float] = (0.0, 0.0, 0.0),
                 hi: Sequence[float] = (1.0, 1.0, 1.0),
                 decomposition: DecompKind = DecompKind.BRICK,
                 grid: Optional[Sequence[int]] = None,
                 balance_threshold: float = 1.1) -> None:
        """Decompose the global box [lo, hi] (m) into one part per rank of `comm`: a brick
        (grid: ranks per axis, zeros or None chosen) or a bisection made at the first
        balance; rebalance above `balance_threshold` (largest load over the mean, >= 1)."""
        _, mpi, _ = _state()
        options = MpiOptions()
        _check(mpi.sinter_mpi_options_init(ctypes.byref(options), ctypes.sizeof(MpiOptions)),
               "sinter_mpi_options_init")
        options.decomposition = int(DecompKind(decomposition))
        options.grid = (_int * 3)(*(grid if grid is not None else (0, 0, 0)))
        options.lo, options.hi = _triple(lo, "lo"), _triple(hi, "hi")
        options.balance_threshold = float(balance_threshold)
        self._handle = DomainPtr()
        self._attached: Optional[Tuple[Any, Any]] = None
        _check(mpi.sinter_mpi_domain_create(ctypes.byref(self._handle), comm_handle(comm),
                                            ctypes.byref(options)), "sinter_mpi_domain_create")

    @property
    def _ptr(self) -> Any:
        if not self._handle:
            raise ValueError("the mpi Domain is closed")
        return self._handle

    def close(self) -> None:
        """Destroy the domain (collective). Detach it first from a stepper that outlives it."""
        if self._handle:
            if self._attached is not None:
                stepper = self._attached[0]
                if not stepper.closed:
                    stepper._call(lib.sinter_stepper_set_domain_ops, stepper._ptr, None, None)
                self._attached = None
            _state()[1].sinter_mpi_domain_destroy(self._handle)
        self._handle = DomainPtr()

    def __enter__(self) -> "Domain":
        return self

    def __exit__(self, *exc_info: Any) -> None:
        self.close()

    @property
    def rank(self) -> int:
        """This rank in the domain's communicator."""
        return self._rank_size()[0]

    @property
    def size(self) -> int:
        """The number of ranks."""
        return self._rank_size()[1]

    def _rank_size(self):
        rank, size = _int(), _int()
        _check(_state()[1].sinter_mpi_domain_rank(self._ptr, ctypes.byref(rank),
                                                  ctypes.byref(size)), "sinter_mpi_domain_rank")
        return rank.value, size.value

    @property
    def comm(self) -> Any:
        """The domain's own (duplicated) communicator as an mpi4py Comm, borrowed: valid while
        the domain lives; do not Free it."""
        MPI, mpi, comm_type = _state()
        handle = comm_type()
        _check(mpi.sinter_mpi_domain_comm(self._ptr, ctypes.byref(handle)),
               "sinter_mpi_domain_comm")
        comm = MPI.Intracomm()
        comm_type.from_address(MPI._addressof(comm)).value = handle.value
        return comm

    @property
    def decomposition(self) -> Decomposition:
        """The current decomposition (a view valid until the next balance)."""
        out = DecompPtr()
        _check(_state()[1].sinter_mpi_domain_decomp(self._ptr, ctypes.byref(out)),
               "sinter_mpi_domain_decomp")
        return Decomposition(out, owner=self)

    def reduce(self, values: Sequence[float], type: ReduceType = ReduceType.F64,
               op: ReduceOp = ReduceOp.SUM) -> List[float]:
        """Collective: the element-wise reduction over the ranks (sinter_mpi_reduce; the same
        bits on every rank, whatever their number)."""
        c_type = {ReduceType.F64: _double, ReduceType.I64: ctypes.c_int64,
                  ReduceType.U64: _u64}[ReduceType(type)]
        convert = float if c_type is _double else int
        array = (c_type * max(1, len(values)))(*[convert(v) for v in values])
        _check(_state()[1].sinter_mpi_reduce(array, len(values), int(type), int(op), self._ptr),
               "sinter_mpi_reduce")
        return list(array)[:len(values)]

    def exscan(self, value: int) -> Tuple[int, int]:
        """Collective: (the sum of `value` over the ranks before this one, the total)."""
        before, total = _u64(), _u64()
        _check(_state()[1].sinter_mpi_exscan(int(value), ctypes.byref(before),
                                             ctypes.byref(total), self._ptr),
               "sinter_mpi_exscan")
        return before.value, total.value

    def sum(self, terms: Sequence[float]) -> float:
        """Collective: the sum of every rank's terms, the same bits for any number of ranks."""
        c_terms, n = _doubles(terms)
        out = _double()
        _check(_state()[1].sinter_mpi_sum(self._ptr, c_terms, n, ctypes.byref(out)),
               "sinter_mpi_sum")
        return out.value

    def balance(self, positions: Sequence[Sequence[float]],
                weights: Optional[Sequence[float]] = None) -> Tuple[float, bool]:
        """Collective: rebalance above the threshold from this rank's points; return
        (imbalance before, rebalanced)."""
        xyz, n = _doubles(positions, 3)
        w = _doubles(weights)[0] if weights is not None else None
        imbalance, rebalanced = _double(), _int()
        _check(_state()[1].sinter_mpi_balance(self._ptr, xyz, w, n, ctypes.byref(imbalance),
                                              ctypes.byref(rebalanced)), "sinter_mpi_balance")
        return imbalance.value, bool(rebalanced.value)

    def stats(self) -> MpiStats:
        """This rank's reduction counters."""
        stats = _CStats(struct_size=ctypes.sizeof(_CStats))
        _check(_state()[1].sinter_mpi_get_stats(self._ptr, ctypes.byref(stats)),
               "sinter_mpi_get_stats")
        return MpiStats(*(getattr(stats, f.name) for f in dataclasses.fields(MpiStats)))

    def attach(self, stepper: Any, particles: Any, balance: bool = False) -> None:
        """Collective: install the domain as this rank's explicit stepper's collective
        operations over `particles`, its set (migration, ghosts, halos and reductions through
        MPI). balance: rebalance at every neighbour-list rebuild. The domain is detached when
        closed; a stepper closed first is detached by its own destruction."""
        stepper._call(_state()[1].sinter_mpi_attach, self._ptr, stepper._ptr, particles._ptr,
                      ATTACH_BALANCE if balance else 0)
        self._attached = (stepper, particles)

    def distribute(self) -> None:
        """Collective: move every owned particle to the rank whose part holds its centre (the
        initial distribution of a set filled on one rank). After attach, before stepping."""
        function = _state()[1].sinter_mpi_distribute
        if self._attached is not None and not self._attached[0].closed:
            self._attached[0]._call(function, self._ptr)  # the stepper context's message
        else:
            _check(function(self._ptr), "sinter_mpi_distribute")

    def exchange_stats(self) -> ExchangeStats:
        """This rank's exchange counters of the attached stepper."""
        stats = _CExchangeStats(struct_size=ctypes.sizeof(_CExchangeStats))
        _check(_state()[1].sinter_mpi_get_exchange_stats(self._ptr, ctypes.byref(stats)),
               "sinter_mpi_get_exchange_stats")
        return ExchangeStats(*(getattr(stats, f.name)
                               for f in dataclasses.fields(ExchangeStats)))


def checkpoint_write(stepper: Any, particles: Any, comm: Any, path: str) -> None:
    """Collective over `comm`: a portable checkpoint of every rank's stepper in one file
    through MPI-IO (sinter_mpi_checkpoint_write); every rank passes the same path."""
    stepper._call(_state()[1].sinter_mpi_checkpoint_write, stepper._ptr, particles._ptr,
                  comm_handle(comm), os.fsencode(path))


def checkpoint_read(stepper: Any, particles: Any, comm: Any, path: str,
                    decomposition: Decomposition) -> int:
    """Collective over `comm`: read a checkpoint written on any number of ranks; each rank's
    stepper (set up alike over an empty set) receives the particles in its part of
    `decomposition` (part r for rank r). Returns this rank's particle count."""
    count = _size()
    stepper._call(_state()[1].sinter_mpi_checkpoint_read, stepper._ptr, particles._ptr,
                  comm_handle(comm), os.fsencode(path), decomposition._ptr, ctypes.byref(count))
    return count.value


__all__ = ["ATTACH_BALANCE", "DecompKind", "Decomposition", "Domain", "ExchangeStats",
           "MpiOptions", "MpiStats", "MpiUnavailable", "available", "checkpoint_read",
           "checkpoint_write", "comm_handle", "imbalance", "library_candidates"]
