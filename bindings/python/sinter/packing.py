"""Packing helpers: random sequential addition, lattices, pouring and triaxial compaction."""

import ctypes
import enum
from typing import TYPE_CHECKING, Any, Dict, Optional, Sequence, Union

if TYPE_CHECKING:  # pragma: no cover
    from .particles import Particles
    from .stepper import Stepper

Vec3 = Sequence[float]

from ._errors import check
from ._integers import to_c
from ._lib import CompactionOptions, CompactionResult, PackingOptions, lib


class RadiusDistribution(enum.IntEnum):
    """sinter_radius_distribution."""

    MONODISPERSE = 0
    UNIFORM = 1
    NORMAL = 2


def _given(arguments: Dict[str, Any], exclude: Sequence[str] = ()) -> Dict[str, Any]:
    """The keyword arguments of a call (its locals()) that were given (not None)."""
    return {key: value for key, value in arguments.items()
            if value is not None and key not in exclude}


def packing_options(*, box_min: Optional[Vec3] = None, box_max: Optional[Vec3] = None,
                    distribution: Union[RadiusDistribution, str, int, None] = None,
                    radius: Optional[float] = None, radius_mean: Optional[float] = None,
                    radius_spread: Optional[float] = None, spread: Optional[float] = None,
                    radius_min: Optional[float] = None, radius_max: Optional[float] = None,
                    gap: Optional[float] = None, seed: Optional[int] = None,
                    max_attempts: Optional[int] = None, material: Optional[int] = None,
                    temperature: Optional[float] = None) -> PackingOptions:
    """A sinter_packing_options filled with the library's defaults, then the keywords given
    (None: the default).

    box_min, box_max: corners of the box the spheres lie in [m] (default the unit box);
    distribution: "monodisperse" (default), "uniform" or "normal" (RadiusDistribution);
    radius (alias of radius_mean): mean radius [m] (0.05); radius_spread (alias spread):
    half-width (uniform) or standard deviation (normal) [m]; radius_min, radius_max:
    truncation of the normal distribution [m] (0: mean -/+ 3 spread); gap: smallest surface
    gap [m] (>= 0); seed: random seed (same seed, same packing); max_attempts: attempts per
    sphere before giving up (100000); material: material id (0..255); temperature [K] (> 0,
    293.15).
    """
    return _packing_options(_given(locals()))


def _packing_options(options: Dict[str, Any]) -> PackingOptions:
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


def pack_random(particles: "Particles", n: int, box_min: Vec3, box_max: Vec3, *,
                distribution: Union[RadiusDistribution, str, int, None] = None,
                radius: Optional[float] = None, radius_mean: Optional[float] = None,
                radius_spread: Optional[float] = None, spread: Optional[float] = None,
                radius_min: Optional[float] = None, radius_max: Optional[float] = None,
                gap: Optional[float] = None, seed: Optional[int] = None,
                max_attempts: Optional[int] = None, material: Optional[int] = None,
                temperature: Optional[float] = None) -> int:
    """Random sequential addition of up to n non-overlapping spheres inside the box
    box_min..box_max [m] (seed 000 sec. 7.1); returns the number placed (fewer if
    max_attempts fail in a row). The keywords are those of packing_options.
    """
    c = _packing_options(_given(locals(), exclude=("particles", "n")))
    placed = ctypes.c_size_t()
    particles._check(lib.sinter_pack_random(particles._ptr, ctypes.byref(c), int(n),
                                            ctypes.byref(placed)),
                     "sinter_pack_random")
    return placed.value


def pack_lattice(particles: "Particles", box_min: Vec3, box_max: Vec3, radius: float,
                 spacing: Optional[float] = None, material: int = 0,
                 temperature: float = 293.15) -> int:
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


def pour(stepper: "Stepper", ke_per_particle: float, t_min: float = 0.0,
         t_max: float = 1.0) -> float:
    """Advance `stepper` (with gravity) until the kinetic energy per particle [J] falls below
    ke_per_particle after at least t_min [s]; a SinterError (ERR_NOT_CONVERGED) after t_max.
    Returns the time reached."""
    return stepper.pour(ke_per_particle, t_min, t_max)


def compaction_options(*, box_min: Optional[Vec3] = None, box_max: Optional[Vec3] = None,
                       volume_fraction: Optional[float] = None,
                       friction: Optional[float] = None, restitution: Optional[float] = None,
                       velocity: Optional[float] = None, max_pressure: Optional[float] = None,
                       stop_at_jamming: Optional[bool] = None,
                       ke_per_particle: Optional[float] = None,
                       relax_time_max: Optional[float] = None,
                       dt: Optional[float] = None) -> CompactionOptions:
    """A sinter_compaction_options filled with the library's defaults, then the keywords
    given (None: the default).

    box_min, box_max: the final box [m] (default [0, 1]^3); volume_fraction: 0 (default) or
    in (0, 0.7405], the box scaled about box_min so that the spheres fill this fraction;
    friction: particle-particle friction during the compaction (0.1); restitution: (0, 1]
    (0.5); velocity: largest wall speed [m/s] (0.5); max_pressure: mean wall stress at which
    the walls stop [Pa] (0: automatic); stop_at_jamming: end at jamming instead of failing;
    ke_per_particle: rest threshold [J] (0: automatic); relax_time_max: longest relaxation
    [s] (0: automatic); dt: time step [s] (0: seed 003 eq. 47).
    """
    return _compaction_options(_given(locals()))


def _compaction_options(options: Dict[str, Any]) -> CompactionOptions:
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


def pack_compact(particles: "Particles", box_min: Vec3, box_max: Vec3, *,
                 volume_fraction: Optional[float] = None, friction: Optional[float] = None,
                 restitution: Optional[float] = None, velocity: Optional[float] = None,
                 max_pressure: Optional[float] = None, stop_at_jamming: Optional[bool] = None,
                 ke_per_particle: Optional[float] = None,
                 relax_time_max: Optional[float] = None,
                 dt: Optional[float] = None) -> Dict[str, Any]:
    """Triaxial compaction of `particles` (seed 001 sec. 3.2) onto the box box_min..box_max [m]
    (scaled to `volume_fraction` if given), or until the packing jams with
    stop_at_jamming=True; see sinter_pack_compact. Returns a dict of the result: box_min,
    box_max [m], volume_fraction, jammed, coordination, contacts, max_overlap [m],
    max_overlap_ratio, max_wall_overlap_ratio, pressure [Pa], kinetic_energy [J], time,
    relax_time, dt [s], steps. Errors raise SinterError subclasses; the set is then unchanged.
    """
    c = _compaction_options(_given(locals(), exclude=("particles",)))
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
