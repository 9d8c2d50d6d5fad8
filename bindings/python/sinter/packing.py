"""Packing helpers: random sequential addition, lattices, pouring and triaxial compaction."""

import ctypes
import enum
import os
from typing import TYPE_CHECKING, Any, Dict, List, Optional, Sequence, Tuple, Union

if TYPE_CHECKING:  # pragma: no cover
    from .context import Context
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
    LOGNORMAL = 3
    TABLE = 4


class InsertionRegion(enum.IntEnum):
    """sinter_insertion_region: where the continuous insertion places spheres."""

    BOX = 0       #: the powder's box
    CYLINDER = 1  #: the cylinder inscribed in the box along z


class SizeBasis(enum.IntEnum):
    """sinter_size_basis: what a cumulative size distribution counts."""

    NUMBER = 0
    VOLUME = 1


def _basis(value: Union[SizeBasis, str, int]) -> int:
    if isinstance(value, str):
        value = SizeBasis[value.upper()]
    return to_c(int(value), ctypes.c_int, "basis")


def _doubles(values: Sequence[float]) -> Any:
    """A ctypes array of the values (at least one element) and their count."""
    values = [float(v) for v in values]
    return (ctypes.c_double * max(1, len(values)))(*values), len(values)


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
                    temperature: Optional[float] = None,
                    radius_median: Optional[float] = None, radius_gsd: Optional[float] = None,
                    gsd: Optional[float] = None,
                    table_diameter: Optional[Sequence[float]] = None,
                    table_cumulative: Optional[Sequence[float]] = None,
                    table_basis: Union[SizeBasis, str, int, None] = None,
                    mixture_materials: Optional[Sequence[int]] = None,
                    mixture_mass_fractions: Optional[Sequence[float]] = None,
                    mixture_sizes: Optional[Sequence[PackingOptions]] = None
                    ) -> PackingOptions:
    """A sinter_packing_options filled with the library's defaults, then the keywords given
    (None: the default).

    box_min, box_max: corners of the box the spheres lie in [m] (default the unit box);
    distribution: "monodisperse" (default), "uniform" or "normal" (RadiusDistribution);
    radius (alias of radius_mean): mean radius [m] (0.05); radius_spread (alias spread):
    half-width (uniform) or standard deviation (normal) [m]; radius_min, radius_max:
    truncation of the normal distribution [m] (0: mean -/+ 3 spread); gap: smallest surface
    gap [m] (>= 0); seed: random seed (same seed, same packing); max_attempts: attempts per
    sphere before giving up (100000); material: material id (0..255); temperature [K] (> 0,
    293.15). Issue 38: distribution "lognormal" with radius_median (the number median [m])
    and radius_gsd (alias gsd, the geometric standard deviation, >= 1), radius_min and
    radius_max its truncation (0: median / gsd^3, median gsd^3); distribution "table" with
    table_diameter [m] and table_cumulative (sequences of one length, e.g. from
    read_psd_csv) and table_basis ("volume" (default) or "number", SizeBasis); a mixture by
    mass: mixture_materials (ids) and mixture_mass_fractions (one length, summing to 1), and
    optionally mixture_sizes, one packing_options(...) per material whose size keywords give
    that material its own distribution (the material is then chosen before the radius). The
    sequences are copied into arrays that the returned struct keeps alive.
    """
    return _packing_options(_given(locals()))


def _packing_options(options: Dict[str, Any]) -> PackingOptions:
    c = PackingOptions()
    check(lib.sinter_packing_options_init(ctypes.byref(c), ctypes.sizeof(PackingOptions)), None,
          "sinter_packing_options_init")
    aliases = {"radius": "radius_mean", "spread": "radius_spread", "gsd": "radius_gsd"}
    if "mixture_sizes" in options and len(options["mixture_sizes"]) != len(
            options.get("mixture_materials", ())):
        raise ValueError("mixture_sizes needs one packing_options per material of "
                         "mixture_materials")
    for a, b in (("table_diameter", "table_cumulative"),
                 ("mixture_materials", "mixture_mass_fractions")):
        if (a in options) != (b in options) or (a in options and
                                                len(options[a]) != len(options[b])):
            raise ValueError("%s and %s must be given together, of the same length" % (a, b))
    for key, value in options.items():
        key = aliases.get(key, key)
        if key in ("table_diameter", "table_cumulative", "mixture_mass_fractions"):
            array, count = _doubles(value)
            setattr(c, key, array)
            if key == "mixture_mass_fractions":
                c.mixture_count = count
            elif key == "table_diameter":
                c.table_points = count
        elif key == "mixture_materials":
            ids = [to_c(int(v), ctypes.c_int32, key) for v in value]
            c.mixture_materials = (ctypes.c_int32 * max(1, len(ids)))(*ids)
            c.mixture_count = len(ids)
        elif key == "mixture_sizes":
            sizes = list(value)
            array = (PackingOptions * max(1, len(sizes)))(*sizes)
            c.mixture_sizes = ctypes.cast(array, ctypes.c_void_p).value
            # the copies borrow the originals' tables: keep both alive with the struct
            setattr(c, "_sizes_alive", (array, sizes))
        elif key == "table_basis":
            c.table_basis = _basis(value)
        elif key in ("box_min", "box_max"):
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
        elif key in {"radius_mean", "radius_spread", "radius_min", "radius_max", "gap",
                     "temperature", "radius_median", "radius_gsd"}:
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
                temperature: Optional[float] = None,
                radius_median: Optional[float] = None, radius_gsd: Optional[float] = None,
                gsd: Optional[float] = None,
                table_diameter: Optional[Sequence[float]] = None,
                table_cumulative: Optional[Sequence[float]] = None,
                table_basis: Union[SizeBasis, str, int, None] = None,
                mixture_materials: Optional[Sequence[int]] = None,
                mixture_mass_fractions: Optional[Sequence[float]] = None,
                mixture_sizes: Optional[Sequence[PackingOptions]] = None) -> int:
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


def read_psd_csv(context: "Context", path: Union[str, "os.PathLike[str]"], unit: float = 1.0,
                 percent: bool = False) -> Tuple[List[float], List[float]]:
    """A cumulative size distribution from a CSV file (sinter_psd_read_csv): rows
    "diameter, cumulative"; diameters times `unit` give metres (1e-6 for micrometres); the
    cumulative values are fractions, or percent with percent=True. Returns (diameters [m],
    cumulative fractions ending at 1); a bad row raises with "path:line:".
    """
    encoded = os.fsencode(path)
    count = ctypes.c_size_t()
    context._check(lib.sinter_psd_read_csv(context._ptr, encoded, float(unit), int(bool(percent)),
                                           None, None, 0, ctypes.byref(count)),
                   "sinter_psd_read_csv")
    n = count.value
    d = (ctypes.c_double * n)()
    q = (ctypes.c_double * n)()
    context._check(lib.sinter_psd_read_csv(context._ptr, encoded, float(unit), int(bool(percent)),
                                           d, q, n, ctypes.byref(count)),
                   "sinter_psd_read_csv")
    return list(d), list(q)


def size_quantiles(particles: "Particles", fractions: Sequence[float] = (0.1, 0.5, 0.9),
                   basis: Union[SizeBasis, str, int] = "volume", first: int = 0,
                   count: Optional[int] = None) -> List[float]:
    """Diameters [m] at which the cumulative fraction by `basis` ("number" or "volume") of
    particles first .. first + count - 1 (default: to the end) reaches each of `fractions`:
    D10, D50, D90 by default (sinter_particles_size_quantiles)."""
    if count is None:
        count = particles.count - int(first)
    wanted, n = _doubles(fractions)
    out = (ctypes.c_double * max(1, n))()
    particles._check(lib.sinter_particles_size_quantiles(particles._ptr, int(first), int(count),
                                                         _basis(basis), n, wanted, out),
                     "sinter_particles_size_quantiles")
    return list(out)[:n]


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
