"""Coarse-grained fields on a grid and lamina profiles (sinter_coarse_grain, issue 37).

    phi = sinter.coarse_grain(ps, "solid_fraction", origin=(0, 0, 0), spacing=1e-4,
                              points=(20, 20, 20), width=1e-4)
    phi[k, j, i]                       # at origin + (i, j, k) * spacing
    sigma = sinter.coarse_grain(ps, "stress", ..., stepper=st)   # [Pa], shape (nz, ny, nx, 3, 3)
    fraction, temperature = sinter.lamina_profile(ps, "z", box_min, box_max, 20)

Over subdomains (sinter_domain.h, issue 44): each adds its share, the host sums them (any
order of ranks: the same terms) and forms the fields once:

    sums = sinter.fields.coarse_sums(ps, origin, spacing, points, width, stepper=st)
    sinter.fields.write_vti_sums(ctx, "fields.vti", origin, spacing, points, width, total)
    volumes = sinter.fields.lamina_sums(ps, "z", box_min, box_max, 20)

Each particle is smeared by a Gaussian of standard deviation `width` [m] cut at `cutoff`
widths (docs/models.md, "Coarse-grained fields"). The arrays are NumPy arrays, or flat
memoryviews where NumPy is absent or sinter.particles.USE_NUMPY is false. Units are SI.
"""

import ctypes
import enum
from typing import TYPE_CHECKING, Any, List, Optional, Sequence, Tuple, Union

from . import particles as _particles
from ._errors import check
from ._lib import CoarseOptions, SnapshotPtr, lib, text

if TYPE_CHECKING:
    from .context import Context
    from .stepper import Stepper

Vec3 = Sequence[float]


class CoarseQuantity(enum.IntEnum):
    """sinter_coarse_quantity: what sinter_coarse_grain computes."""
    SOLID_FRACTION = 0
    DENSITY = 1
    TEMPERATURE = 2
    VELOCITY = 3
    STRESS = 4


def quantity_info(quantity: Union[str, int, CoarseQuantity]) -> Tuple[str, str, int]:
    """(name, unit, components) of a quantity."""
    q = _quantity(quantity)
    name, unit, components = ctypes.c_char_p(), ctypes.c_char_p(), ctypes.c_size_t()
    status = lib.sinter_coarse_quantity_info(int(q), ctypes.byref(name), ctypes.byref(unit),
                                             ctypes.byref(components))
    if status != 0:
        raise ValueError("unknown coarse-grained quantity %r" % (quantity,))
    return text(name.value), text(unit.value), components.value


def _quantity(quantity):
    if isinstance(quantity, str):
        try:
            return CoarseQuantity[quantity.upper()]
        except KeyError:
            raise ValueError("unknown coarse-grained quantity %r; expected one of %s"
                             % (quantity, ", ".join(q.name.lower() for q in CoarseQuantity)))
    return CoarseQuantity(quantity)


def _triple(value, kind):
    if isinstance(value, (int, float)):
        return [kind(value)] * 3
    values = [kind(v) for v in value]
    if len(values) != 3:
        raise ValueError("expected one number or three, got %d" % len(values))
    return values


def _options(origin, spacing, points, width, cutoff):
    options = CoarseOptions()
    check(lib.sinter_coarse_options_init(ctypes.byref(options), ctypes.sizeof(options)),
          None, "sinter_coarse_options_init")
    options.origin[:] = _triple(origin, float)
    options.spacing[:] = _triple(spacing, float)
    options.points[:] = _triple(points, int)
    options.width = float(width)
    options.cutoff = float(cutoff)
    return options


#: Doubles per grid point of coarse_sums (SINTER_COARSE_SUMS): 15 particle sums, then the
#: contact stress's 9 in a second block.
COARSE_SUMS = 24


def coarse_sums(particles: "_particles.Particles", origin: Vec3, spacing: Union[float, Vec3],
                points: Union[int, Sequence[int]], width: float, cutoff: float = 3.0,
                stepper: Optional["Stepper"] = None) -> List[float]:
    """This subdomain's share of the fields (sinter_coarse_sums): its owned particles' sums
    and those of its contacts whose smaller id it owns, points * COARSE_SUMS floats."""
    options = _options(origin, spacing, points, width, cutoff)
    nx, ny, nz = options.points
    count = nx * ny * nz * COARSE_SUMS
    out = (ctypes.c_double * count)()
    snapshot = SnapshotPtr()
    if stepper is not None:
        stepper._call(lib.sinter_snapshot_create, ctypes.byref(snapshot), stepper._ptr)
    try:
        particles._check(lib.sinter_coarse_sums(particles._ptr, snapshot, ctypes.byref(options),
                                                out, count), "sinter_coarse_sums")
    finally:
        if snapshot:
            lib.sinter_snapshot_destroy(snapshot)
    return list(out)


def write_vti_sums(context: "Context", path: str, origin: Vec3, spacing: Union[float, Vec3],
                   points: Union[int, Sequence[int]], width: float, sums: Sequence[float],
                   cutoff: float = 3.0, binary: bool = True, single: bool = False) -> None:
    """Write the fields of coarse_sums summed over the subdomains as a .vti
    (sinter_write_vti_sums)."""
    options = _options(origin, spacing, points, width, cutoff)
    values = (ctypes.c_double * max(len(sums), 1))(*sums)
    flags = (1 if binary else 0) | (2 if single else 0)
    status = lib.sinter_write_vti_sums(context._ptr, path.encode(), ctypes.byref(options),
                                       values, len(sums), flags)
    check(status, context._handle, "sinter_write_vti_sums")


def lamina_sums(particles: "_particles.Particles", axis: Union[str, int], box_min: Vec3,
                box_max: Vec3, count: int) -> List[float]:
    """This subdomain's slice volumes per lamina [m^3], then those times the temperature
    [m^3 K] (sinter_lamina_sums): 2 count floats."""
    index = "xyz".index(axis) if isinstance(axis, str) else int(axis)
    lo = (ctypes.c_double * 3)(*_triple(box_min, float))
    hi = (ctypes.c_double * 3)(*_triple(box_max, float))
    n = int(count)
    out = (ctypes.c_double * max(2 * n, 1))()
    particles._check(lib.sinter_lamina_sums(particles._ptr, index, lo, hi, n, out),
                     "sinter_lamina_sums")
    return list(out)[:2 * n]


def coarse_grain(particles: "_particles.Particles", quantity: Union[str, int, CoarseQuantity],
                 origin: Vec3, spacing: Union[float, Vec3], points: Union[int, Sequence[int]],
                 width: float, cutoff: float = 3.0, stepper: Optional["Stepper"] = None) -> Any:
    """One coarse-grained quantity at every grid point origin + (i, j, k) * spacing [m].

    quantity: "solid_fraction" [1], "density" [kg/m^3], "temperature" [K],
    "velocity" [m/s] or "stress" [Pa] (Cauchy, tension positive). stepper: a Stepper of
    these particles whose contacts add to the stress (a snapshot of its state; None: the
    kinetic stress only). Returns an array of shape (nz, ny, nx) + (components,) for vectors,
    (3, 3) for the stress.
    """
    q = _quantity(quantity)
    options = CoarseOptions()
    check(lib.sinter_coarse_options_init(ctypes.byref(options), ctypes.sizeof(options)),
          None, "sinter_coarse_options_init")
    options.origin[:] = _triple(origin, float)
    options.spacing[:] = _triple(spacing, float)
    options.points[:] = _triple(points, int)
    options.width = float(width)
    options.cutoff = float(cutoff)
    _, _, components = quantity_info(q)
    nx, ny, nz = options.points
    count = nx * ny * nz * components
    out = (ctypes.c_double * max(count, 1))()
    snapshot = SnapshotPtr()
    if stepper is not None and q == CoarseQuantity.STRESS:
        stepper._call(lib.sinter_snapshot_create, ctypes.byref(snapshot), stepper._ptr)
    try:
        particles._check(lib.sinter_coarse_grain(particles._ptr, snapshot, ctypes.byref(options),
                                                 int(q), out, count),
                         "sinter_coarse_grain")
    finally:
        if snapshot:
            lib.sinter_snapshot_destroy(snapshot)
    shape = (nz, ny, nx) + ((3, 3) if components == 9 else (components,) if components > 1
                            else ())
    return _array(out, count, shape)


def _array(buffer, count, shape):
    raw = bytearray(memoryview(buffer).cast("B")[:count * 8])
    numpy = _particles.numpy
    if _particles.USE_NUMPY and numpy is not None:
        return numpy.frombuffer(raw, dtype="d").reshape(shape)
    return memoryview(raw).cast("d")


def lamina_profile(particles: "_particles.Particles", axis: Union[str, int], box_min: Vec3,
                   box_max: Vec3, count: int,
                   temperature: bool = True) -> Tuple[Any, Optional[Any]]:
    """Seed 001 eq. 48: the relative density of `count` equal laminae of the box along axis
    ("x", "y", "z" or 0-2), and their slice-volume-weighted temperature [K] (None when
    temperature is false). Returns (fraction, temperature) arrays of length count."""
    index = "xyz".index(axis) if isinstance(axis, str) else int(axis)
    lo = (ctypes.c_double * 3)(*_triple(box_min, float))
    hi = (ctypes.c_double * 3)(*_triple(box_max, float))
    n = int(count)
    fraction = (ctypes.c_double * max(n, 1))()
    temps = (ctypes.c_double * max(n, 1))() if temperature else None
    particles._check(lib.sinter_lamina_profile(particles._ptr, index, lo, hi, n, fraction, temps),
                     "sinter_lamina_profile")
    return (_array(fraction, n, (n,)), _array(temps, n, (n,)) if temps is not None else None)
