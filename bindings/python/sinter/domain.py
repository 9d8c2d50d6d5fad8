"""libsinter on one subdomain of a decomposition the host owns (sinter_domain.h, issue 43).

Every subdomain has its own Context, Particles (owned particles with global ids, from
Particles.add(..., ids=...)), Walls and Stepper. The host supplies ghosts of the other
subdomains' particles (set_ghosts) and the collective operations the stepper needs, as a
DomainHost (set_domain_ops). The explicit, staggered and quasi-static steppers, in this
version.

    class Host(sinter.domain.DomainHost):
        def reduce(self, values, type, op): ...       # the same result on every subdomain
        def exscan(self, value): ...                  # (before, total)
        def halo(self, direction, width, rows, ids, owned, ghosts): ...
        def redistribute(self, stepper): ...          # calls set_ghosts(...)

    sinter.domain.set_domain_ops(stepper, Host())
"""

import ctypes
import enum
from typing import List, Optional, Sequence, Tuple

from . import _callbacks
from ._lib import DomainOps, DestroyUserFn, ExscanFn, GhostFields, HaloFn, ReduceFn
from ._lib import RedistributeFn, lib

#: Doubles per particle of the explicit step's forward halo: x, v, spin, rotation (3 each), T.
HALO_STATE_WIDTH = 13


class ReduceOp(enum.IntEnum):
    """sinter_reduce_op."""

    SUM = 0
    MIN = 1
    MAX = 2


class ReduceType(enum.IntEnum):
    """sinter_reduce_type: the values' C type (double, int64, uint64)."""

    F64 = 0
    I64 = 1
    U64 = 2


class HaloDir(enum.IntEnum):
    """sinter_halo_dir."""

    FORWARD = 0  #: owners' rows copied into the ghost rows
    REVERSE = 1  #: ghost rows added into their owners' rows, then zeroed


_CTYPES = {ReduceType.F64: ctypes.c_double, ReduceType.I64: ctypes.c_int64,
           ReduceType.U64: ctypes.c_uint64}


class DomainHost:
    """The host's collective operations; every subdomain calls them in the same order.
    Override all four. An exception in one becomes SINTER_ERR_CALLBACK and is raised again
    from the stepper's call."""

    def reduce(self, values: List[float], type: ReduceType, op: ReduceOp) -> Sequence[float]:
        """The reduced values (identical bits on every subdomain)."""
        raise NotImplementedError

    def exscan(self, value: int) -> Tuple[int, int]:
        """(sum of `value` over the subdomains before this one, the total)."""
        raise NotImplementedError

    def halo(self, direction: HaloDir, width: int, rows: "ctypes.Array", ids: "ctypes.Array",
             owned: int, ghosts: int) -> None:
        """Exchange rows: (owned + ghosts) * width doubles in `rows`, written in place."""
        raise NotImplementedError

    def redistribute(self, stepper: "object") -> None:
        """Move particles that left the subdomain, then call set_ghosts."""
        raise NotImplementedError


def _guarded(function):
    """A callback body whose exception is kept for the C call's caller (returns -1)."""
    def run(*args):
        try:
            function(*args)
            return 0
        except BaseException as error:  # re-raised by _callbacks.call after the C call
            _callbacks.store(error)
            return -1
    return run


def set_domain_ops(stepper: "object", host: Optional[DomainHost]) -> None:
    """Install `host`'s operations on the stepper (None removes them)."""
    if host is None:
        stepper._call(lib.sinter_stepper_set_domain_ops, stepper._ptr, None, None)
        stepper._domain_ops = None
        return

    def reduce(values, count, type_, op):
        c_type = _CTYPES[ReduceType(type_)]
        array = (c_type * count).from_address(values)
        result = host.reduce(list(array), ReduceType(type_), ReduceOp(op))
        for k in range(count):
            array[k] = result[k]

    def exscan(value, before, total):
        b, t = host.exscan(int(value))
        before[0], total[0] = b, t

    def halo(h, user):
        h = h.contents
        rows = (ctypes.c_double * ((h.owned + h.ghosts) * h.width)).from_address(
            ctypes.addressof(h.data.contents))
        ids = (ctypes.c_uint64 * (h.owned + h.ghosts)).from_address(
            ctypes.addressof(h.id.contents))
        host.halo(HaloDir(h.direction), h.width, rows, ids, h.owned, h.ghosts)

    def redistribute(ptr, user):
        host.redistribute(stepper)

    c_reduce = ReduceFn(_guarded(lambda v, n, t, o, user: reduce(v, n, t, o)))
    c_exscan = ExscanFn(_guarded(lambda value, b, t, user: exscan(value, b, t)))
    c_halo = HaloFn(_guarded(halo))
    c_redistribute = RedistributeFn(_guarded(redistribute))
    ops = DomainOps(ctypes.sizeof(DomainOps), c_reduce, c_exscan, c_halo, c_redistribute,
                    DestroyUserFn())
    stepper._call(lib.sinter_stepper_set_domain_ops, stepper._ptr, ctypes.byref(ops), None)
    stepper._domain_ops = (ops, c_reduce, c_exscan, c_halo, c_redistribute, host)  # kept alive


def _array(c_type, values, per, name):
    flat = [float(x) if c_type is ctypes.c_double else int(x) for row in values
            for x in (row if per > 1 else (row,))]
    return (c_type * max(1, len(flat)))(*flat), len(flat) // per


def set_ghosts(particles: "object", ids: Sequence[int], positions: Sequence[Sequence[float]],
               velocities: Sequence[Sequence[float]], spins: Sequence[Sequence[float]],
               rotations: Sequence[Sequence[float]], radii: Sequence[float],
               masses: Sequence[float], inertias: Sequence[float],
               temperatures: Sequence[float], materials: Sequence[int],
               flags: Optional[Sequence[int]] = None,
               owners: Optional[Sequence[int]] = None) -> None:
    """Replace the ghost rows of `particles` (sinter_particles_set_ghosts; SI units)."""
    c_ids, n = _array(ctypes.c_uint64, ids, 1, "ids")
    fields = GhostFields()
    fields.struct_size = ctypes.sizeof(GhostFields)
    fields.count = n
    keep = [c_ids]
    fields.id = ctypes.cast(c_ids, type(fields.id))
    for name, values, per, c_type in (
            ("position", positions, 3, ctypes.c_double), ("velocity", velocities, 3, ctypes.c_double),
            ("spin", spins, 3, ctypes.c_double), ("rotation", rotations, 3, ctypes.c_double),
            ("radius", radii, 1, ctypes.c_double), ("mass", masses, 1, ctypes.c_double),
            ("inertia", inertias, 1, ctypes.c_double),
            ("temperature", temperatures, 1, ctypes.c_double),
            ("material", materials, 1, ctypes.c_int32), ("flags", flags, 1, ctypes.c_uint32),
            ("owner", owners, 1, ctypes.c_int32)):
        if values is None:
            continue
        array, count = _array(c_type, values, per, name)
        if count != n:
            raise ValueError("set_ghosts: %d %s for %d ids" % (count, name, n))
        keep.append(array)
        setattr(fields, name, ctypes.cast(array, type(getattr(fields, name))))
    particles._call(lib.sinter_particles_set_ghosts, particles._ptr, ctypes.byref(fields))


def ghost_cutoff(stepper: "object") -> float:
    """The distance [m] within which the host must supply ghosts of an owned particle."""
    cutoff = ctypes.c_double()
    stepper._call(lib.sinter_stepper_ghost_cutoff, stepper._ptr, ctypes.byref(cutoff))
    return cutoff.value


def wall_force_local(walls: "object", k: int) -> Tuple[float, float, float]:
    """This subdomain's share of wall k's reaction force [N] (Walls.force is the total)."""
    force = (ctypes.c_double * 3)()
    walls._call(lib.sinter_walls_get_force_local, walls._ptr, walls._index(k), force)
    return tuple(force)


def heat_energy_global(stepper: "object", index: int) -> float:
    """Collective: the energy heat model `index` put into the particles of every subdomain [J]."""
    energy = ctypes.c_double()
    stepper._call(lib.sinter_stepper_heat_energy_global, stepper._ptr, int(index),
                  ctypes.byref(energy))
    return energy.value


def stats_global(stepper: "object") -> "object":
    """Collective: the statistics over every subdomain (a sinter.StepperStats)."""
    from ._lib import StepperStats as CStats
    from .stepper import StepperStats
    import dataclasses

    stats = CStats()
    stats.struct_size = ctypes.sizeof(CStats)
    stepper._call(lib.sinter_stepper_get_stats_global, stepper._ptr, ctypes.byref(stats))
    names = [field.name for field in dataclasses.fields(StepperStats)]
    return StepperStats(**{name: getattr(stats, name) for name in names
                           if hasattr(CStats, name)})
