"""Packing helpers: random sequential addition, lattices, pouring and triaxial compaction."""

import ctypes
import enum

from ._errors import check
from ._integers import to_c
from ._lib import CompactionOptions, CompactionResult, PackingOptions, lib


class RadiusDistribution(enum.IntEnum):
    """sinter_radius_distribution."""

    MONODISPERSE = 0
    UNIFORM = 1
    NORMAL = 2


def packing_options(**options):
    """A sinter_packing_options filled with the library's defaults, then `options`.

    Keys: box_min, box_max (3 each) [m], distribution ("monodisperse",
    "uniform", "normal" or RadiusDistribution), radius (alias of radius_mean),
    radius_mean, radius_spread (alias spread), radius_min, radius_max, gap [m],
    seed, max_attempts, material (id), temperature [K].
    """
    c = PackingOptions()
    check(lib.sinter_packing_options_init(ctypes.byref(c), ctypes.sizeof(PackingOptions)), None,
          "sinter_packing_options_init")
    aliases = {"radius": "radius_mean", "spread": "radius_spread"}
    for key, value in options.items():
        key = aliases.get(key, key)
        if key in ("box_min", "box_max"):
            value = [float(v) for v in value]
            if len(value) != 3:
                raise ValueError("%s needs 3 coordinates" % key)
            setattr(c, key, (ctypes.c_double * 3)(*value))
        elif key == "distribution":
            if isinstance(value, str):
                value = RadiusDistribution[value.upper()]
            c.distribution = to_c(int(value), ctypes.c_int, "distribution")
        elif key in ("seed", "max_attempts", "material"):
            setattr(c, key, to_c(int(value), dict(PackingOptions._fields_)[key], key))
        elif key in {name for name, _ in PackingOptions._fields_} - {"struct_size"}:
            setattr(c, key, float(value))
        else:
            raise TypeError("unknown packing option %r" % key)
    return c


def pack_random(particles, n, box_min, box_max, **options):
    """Random sequential addition of up to n non-overlapping spheres inside the box
    (seed 000 sec. 7.1); returns the number placed (fewer if max_attempts fail in a row).

    Options: see packing_options (radius, distribution, spread, gap, seed, material, ...).
    """
    c = packing_options(box_min=box_min, box_max=box_max, **options)
    placed = ctypes.c_size_t()
    particles._check(lib.sinter_pack_random(particles._ptr, ctypes.byref(c), int(n),
                                            ctypes.byref(placed)),
                     "sinter_pack_random")
    return placed.value


def pack_lattice(particles, box_min, box_max, radius, spacing=None, material=0,
                 temperature=293.15):
    """Simple-cubic lattice of spheres of `radius` with centre `spacing` (default 2 r) filling
    the box from its lower corner; returns the number placed."""
    lo = (ctypes.c_double * 3)(*[float(v) for v in box_min])
    hi = (ctypes.c_double * 3)(*[float(v) for v in box_max])
    spacing = 2.0 * radius if spacing is None else spacing
    placed = ctypes.c_size_t()
    particles._check(lib.sinter_pack_lattice(particles._ptr, lo, hi, float(radius),
                                             float(spacing), int(material), float(temperature),
                                             ctypes.byref(placed)),
                     "sinter_pack_lattice")
    return placed.value


def pour(stepper, ke_per_particle, t_min=0.0, t_max=1.0):
    """Advance `stepper` (with gravity) until the kinetic energy per particle [J] falls below
    ke_per_particle after at least t_min [s]; a SinterError (ERR_NOT_CONVERGED) after t_max.
    Returns the time reached."""
    return stepper.pour(ke_per_particle, t_min, t_max)


def compaction_options(**options):
    """A sinter_compaction_options filled with the library's defaults, then `options`.

    Keys: box_min, box_max (3 each) [m], volume_fraction, friction, restitution,
    velocity [m/s], max_pressure [Pa], stop_at_jamming (bool), ke_per_particle [J],
    relax_time_max [s], dt [s].
    """
    c = CompactionOptions()
    check(lib.sinter_compaction_options_init(ctypes.byref(c), ctypes.sizeof(CompactionOptions)),
          None, "sinter_compaction_options_init")
    for key, value in options.items():
        if key in ("box_min", "box_max"):
            value = [float(v) for v in value]
            if len(value) != 3:
                raise ValueError("%s needs 3 coordinates" % key)
            setattr(c, key, (ctypes.c_double * 3)(*value))
        elif key == "stop_at_jamming":
            c.stop_at_jamming = 1 if value else 0
        elif key in {name for name, _ in CompactionOptions._fields_} - {"struct_size"}:
            setattr(c, key, float(value))
        else:
            raise TypeError("unknown compaction option %r" % key)
    return c


def pack_compact(particles, box_min, box_max, **options):
    """Triaxial compaction of `particles` (seed 001 sec. 3.2) onto the box box_min..box_max [m]
    (scaled to `volume_fraction` if given), or until the packing jams with
    stop_at_jamming=True; see sinter_pack_compact. Returns a dict of the result: box_min,
    box_max [m], volume_fraction, jammed, coordination, contacts, max_overlap [m],
    max_overlap_ratio, max_wall_overlap_ratio, pressure [Pa], kinetic_energy [J], time,
    relax_time, dt [s], steps. Errors raise SinterError subclasses; the set is then unchanged.
    """
    c = compaction_options(box_min=box_min, box_max=box_max, **options)
    r = CompactionResult()
    r.struct_size = ctypes.sizeof(CompactionResult)
    particles._check(lib.sinter_pack_compact(particles._ptr, ctypes.byref(c), ctypes.byref(r)),
                     "sinter_pack_compact")
    out = {}
    for name, _ in CompactionResult._fields_:
        if name == "struct_size":
            continue
        value = getattr(r, name)
        out[name] = list(value) if name in ("box_min", "box_max") else value
    out["jammed"] = bool(out["jammed"])
    return out
