"""Rigid walls (planes, rectangles, discs, cylinders) with prescribed motions, a spin, a force
servo, temperatures and electric data."""

import ctypes
import os
import enum
from typing import TYPE_CHECKING, Callable, Optional, Sequence, Tuple, Union

from . import _callbacks
from ._errors import check
from ._lib import WallMotionFn, WallsPtr, lib
from .context import _Handle

if TYPE_CHECKING:  # pragma: no cover
    from .context import Context
    from .material import Material

Vec3 = Sequence[float]


class WallMotion(enum.IntEnum):
    """sinter_wall_motion."""

    FIXED = 0
    VELOCITY = 1
    SCHEDULE = 2
    SINE = 3
    CALLBACK = 4


class WallKind(enum.IntEnum):
    """sinter_wall_kind."""

    PLANE = 0
    RECTANGLE = 1
    DISC = 2
    CYLINDER = 3
    MESH = 4


class WallThermal(enum.IntEnum):
    """sinter_wall_thermal_mode."""

    RESERVOIR = 0
    ADIABATIC = 1
    RESISTANCE = 2
    TRANSFER = 3
    IMPOSED = 4


class WallElectric(enum.IntEnum):
    """sinter_wall_electric_mode."""

    NEUTRAL = 0
    CURRENT = 1
    POTENTIAL = 2


def _vec3(values, what):
    values = [float(v) for v in values]
    if len(values) != 3:
        raise ValueError("%s needs 3 components, got %d" % (what, len(values)))
    return (ctypes.c_double * 3)(*values)


def _doubles(values):
    values = [float(v) for v in values]
    return (ctypes.c_double * max(len(values), 1))(*values), len(values)


class Walls(_Handle):
    """A set of walls (sinter_walls). Wall k: point p_k(t), fixed unit normal (a cylinder: axis)
    n_k; particles on the side the normal points to (a cylinder: inside or outside). Lengths
    in m, velocities in m/s, temperatures in K.

        walls = sinter.Walls(ctx)
        floor = walls.add_plane((0, 0, 0), (0, 0, 1), steel, temperature=700.0)
        walls.set_velocity(floor, (0, 0, 1e-3))
        walls.force(floor)     # reaction of the last accepted step [N]
    """

    _destroy_function = "sinter_walls_destroy"

    def __init__(self, context: "Context") -> None:
        handle = WallsPtr()
        check(lib.sinter_walls_create(ctypes.byref(handle), context._ptr), context._handle,
              "sinter_walls_create")
        super().__init__(context, handle)

    @classmethod
    def _borrowed_from(cls, owner, handle):
        walls = cls.__new__(cls)
        _Handle.__init__(walls, owner.context, handle, owned=False)
        walls._borrow(owner)
        return walls

    @property
    def count(self) -> int:
        count = ctypes.c_size_t()
        self._call(lib.sinter_walls_count, self._ptr, ctypes.byref(count))
        return count.value

    def __len__(self) -> int:
        return self.count

    def _index(self, k):
        k = int(k)
        if k < 0:
            k += self.count
        if k < 0:
            raise IndexError("wall index out of range")
        return k

    def add_plane(self, point: Vec3, normal: Vec3, material: "Material",
                  temperature: Optional[float] = None) -> int:
        """Add a fixed plane through `point` with `normal` (normalised; into the particle region).

        The material is copied. Returns the wall's index.
        """
        index = ctypes.c_size_t()
        self._call(lib.sinter_walls_add_plane, self._ptr, _vec3(point, "point"),
                                               _vec3(normal, "normal"), material._ptr,
                                               ctypes.byref(index))
        if temperature is not None:
            self.set_temperature(index.value, temperature)
        return index.value

    def add_rectangle(self, center: Vec3, normal: Vec3, edge: Vec3, half_1: float,
                      half_2: float, material: "Material") -> int:
        """Add a fixed rectangle centred at `center`, normal into the particle region, first
        edge along `edge` (half length half_1), second along normal x edge (half_2) [m]."""
        index = ctypes.c_size_t()
        self._call(lib.sinter_walls_add_rectangle, self._ptr, _vec3(center, "center"),
                   _vec3(normal, "normal"), _vec3(edge, "edge"), float(half_1), float(half_2),
                   material._ptr, ctypes.byref(index))
        return index.value

    def add_disc(self, center: Vec3, normal: Vec3, radius: float,
                 material: "Material") -> int:
        """Add a fixed disc of `radius` [m] centred at `center`, normal into the particles."""
        index = ctypes.c_size_t()
        self._call(lib.sinter_walls_add_disc, self._ptr, _vec3(center, "center"),
                   _vec3(normal, "normal"), float(radius), material._ptr, ctypes.byref(index))
        return index.value

    def add_cylinder(self, point: Vec3, axis: Vec3, radius: float, material: "Material",
                     half_length: float = float("inf"), inside: bool = True) -> int:
        """Add a fixed cylinder (axis through `point` along `axis`, `radius` [m]), touching
        where the axial offset from `point` is at most half_length [m]; particles inside (a
        die) or outside (a pin)."""
        index = ctypes.c_size_t()
        self._call(lib.sinter_walls_add_cylinder, self._ptr, _vec3(point, "point"),
                   _vec3(axis, "axis"), float(radius), float(half_length), int(bool(inside)),
                   material._ptr, ctypes.byref(index))
        return index.value

    def add_mesh(self, path: str, material: "Material", scale: float = 1.0,
                 rotate: Vec3 = (0.0, 0.0, 0.0), translate: Vec3 = (0.0, 0.0, 0.0),
                 flip: bool = False, reach: float = 0.0) -> int:
        """Add a fixed triangle mesh from the STL file `path` (ASCII or binary), each point
        placed at translate + R (scale x), R turning by rotate [rad] about x, then y, then z;
        particles on the side of the facets' normals (their winding), reversed by flip; beyond
        `reach` [m] (0: nowhere) a distance may be a lower bound."""
        index = ctypes.c_size_t()
        self._call(lib.sinter_walls_add_mesh, self._ptr, os.fsencode(path), float(scale),
                   _vec3(rotate, "rotate"), _vec3(translate, "translate"), int(bool(flip)),
                   float(reach), material._ptr, ctypes.byref(index))
        return index.value

    def kind(self, k: int) -> WallKind:
        """Kind of wall k."""
        kind = ctypes.c_int()
        self._call(lib.sinter_walls_get_kind, self._ptr, self._index(k), ctypes.byref(kind))
        return WallKind(kind.value)

    def shape(self, k: int) -> Tuple[Tuple[float, ...], Tuple[float, ...], Tuple[float, ...]]:
        """(axis, edge, size) of wall k: size is (half_1, half_2, 0) for a rectangle, (radius,
        0, 0) for a disc, (radius, half_length, inside) for a cylinder."""
        axis, edge = (ctypes.c_double * 3)(), (ctypes.c_double * 3)()
        size = (ctypes.c_double * 3)()
        self._call(lib.sinter_walls_get_shape, self._ptr, self._index(k), axis, edge, size)
        return tuple(axis), tuple(edge), tuple(size)

    def set_spin(self, k: int, omega: float) -> None:
        """Spin of wall k about its axis through its point [rad/s]: the surface velocity at a
        contact, u + omega a x (c - p), enters the friction laws."""
        self._call(lib.sinter_walls_set_spin, self._ptr, self._index(k), float(omega))

    def set_rotation(self, k: int, point: Vec3, axis: Vec3, omega: float) -> None:
        """Turn mesh wall k rigidly about the axis through point [m] along axis at omega
        [rad/s] from its motion's start on (its triangles turn; the surface velocity u + omega
        a x (c - p) enters the contact laws). The wall's point becomes point."""
        self._call(lib.sinter_walls_set_rotation, self._ptr, self._index(k),
                   _vec3(point, "point"), _vec3(axis, "axis"), float(omega))

    def set_servo(self, k: int, times: Sequence[float], forces: Sequence[float], kp: float,
                  ki: float, vmax: float) -> None:
        """Drive wall k along its normal to a target force schedule (times [s], forces [N]) by a
        PI controller: v = clamp(kp e + ki int e, +-vmax), e = target - pushing force; gains kp
        [m/(s N)], ki [m/(s^2 N)], vmax [m/s]. A pressure P on area A is the force P A."""
        c_times, n = _doubles(times)
        c_forces, n_forces = _doubles(forces)
        if n != n_forces:
            raise ValueError("%d times but %d forces" % (n, n_forces))
        self._call(lib.sinter_walls_set_servo, self._ptr, self._index(k), n, c_times, c_forces,
                   float(kp), float(ki), float(vmax))

    def servo(self, k: int) -> Tuple[float, float, float]:
        """(target force [N], the particles' pushing force [N], velocity along the normal
        [m/s]) of wall k's servo."""
        target, pushed, velocity = ctypes.c_double(), ctypes.c_double(), ctypes.c_double()
        self._call(lib.sinter_walls_get_servo, self._ptr, self._index(k), ctypes.byref(target),
                   ctypes.byref(pushed), ctypes.byref(velocity))
        return target.value, pushed.value, velocity.value

    def set_moment(self, k: int, on: bool) -> None:
        """Whether wall k's reaction moment is summed (default: yes for rectangles, discs,
        cylinders, spinning and servo walls; no for other planes)."""
        self._call(lib.sinter_walls_set_moment, self._ptr, self._index(k), int(bool(on)))

    def moment(self, k: int) -> Tuple[float, float, float]:
        """Reaction moment on wall k about its point in the last accepted step [N m] (0 when
        not summed: set_moment)."""
        moment = (ctypes.c_double * 3)()
        self._call(lib.sinter_walls_get_moment, self._ptr, self._index(k), moment)
        return tuple(moment)

    def set_material(self, k: int, material: "Material") -> None:
        """Replace wall k's material with a copy of `material`."""
        self._call(lib.sinter_walls_set_material, self._ptr, self._index(k), material._ptr)

    def set_velocity(self, k: int, velocity: Vec3) -> None:
        """Constant velocity u [m/s]: p(t) = p0 + u t."""
        self._call(lib.sinter_walls_set_velocity, self._ptr, self._index(k),
                                                  _vec3(velocity, "velocity"))

    def set_schedule(self, k: int, times: Sequence[float],
                     displacements: Sequence[Vec3]) -> None:
        """Piecewise-linear displacement through (times[i] [s], displacements[i] (3,) [m])."""
        flat = []
        for d in displacements:
            flat.extend(_vec3(d, "displacement"))
        c_times, n = _doubles(times)
        if 3 * n != len(flat):
            raise ValueError("%d times but %d displacements" % (n, len(flat) // 3))
        c_disp, _ = _doubles(flat)
        self._call(lib.sinter_walls_set_schedule, self._ptr, self._index(k), n, c_times, c_disp)

    def set_sine(self, k: int, amplitude: Vec3, omega: float) -> None:
        """p0 + amplitude sin(omega t): amplitude vector [m], omega [rad/s]."""
        self._call(lib.sinter_walls_set_sine, self._ptr, self._index(k),
                                              _vec3(amplitude, "amplitude"), float(omega))

    def set_callback(self, k: int,
                     motion: Callable[[float], Tuple[Vec3, Vec3]]) -> None:
        """Host motion: motion(t) returns (displacement (3,) [m], velocity (3,) [m/s]).

        An exception stops the stepper (last accepted state kept) and is raised
        again by the Stepper call that ran it.
        """
        k = self._index(k)

        def trampoline(t, displacement, velocity, user):
            try:
                d, v = motion(t)
                d, v = list(d), list(v)
                if len(d) != 3 or len(v) != 3:
                    raise ValueError("a wall motion returns two 3-vectors, got %r" % ((d, v),))
                for axis in range(3):
                    displacement[axis] = float(d[axis])
                    velocity[axis] = float(v[axis])
                return 0
            except BaseException as exception:
                _callbacks.store(exception)
                return -1

        function = WallMotionFn(trampoline)
        # Kept first: the library stores the pointer even when its first call fails.
        self._keep(("wall motion", k), function)
        self._call(lib.sinter_walls_set_callback, self._ptr, k, function, None)

    def set_motion_start(self, k: int, start: float) -> None:
        """Time [s] at which wall k's motion starts (float('inf') holds it)."""
        self._call(lib.sinter_walls_set_motion_start, self._ptr, self._index(k), float(start))

    def set_temperature(self, k: int, temperature: float) -> None:
        """Wall temperature [K] (> 0), used by heat submodels."""
        self._call(lib.sinter_walls_set_temperature, self._ptr, self._index(k),
                                                     float(temperature))

    def set_temperature_schedule(self, k: int, times: Sequence[float],
                                 temperatures: Sequence[float]) -> None:
        """Wall temperature following a piecewise-linear schedule (times [s] strictly
        increasing, temperatures [K]), held constant outside."""
        c_times, n = _doubles(times)
        c_temps, n_temps = _doubles(temperatures)
        if n != n_temps:
            raise ValueError("%d times but %d temperatures" % (n, n_temps))
        self._call(lib.sinter_walls_set_temperature_schedule, self._ptr, self._index(k), n,
                                                              c_times, c_temps)

    def set_electric(self, k: int, mode: Union["WallElectric", str, int],
                     value: float = 0.0) -> None:
        """Electric boundary: mode "neutral", "current" (J_ext [A]) or "potential" ([V])."""
        if isinstance(mode, str):
            mode = WallElectric[mode.upper()]
        self._call(lib.sinter_walls_set_electric, self._ptr, self._index(k), int(mode),
                                                  float(value))

    def set_electric_schedule(self, k: int, times: Sequence[float],
                              values: Sequence[float]) -> None:
        """The electric value of wall k follows (times [s], values [A or V]) piecewise linearly;
        empty lists remove the schedule."""
        times, values = [float(t) for t in times], [float(v) for v in values]
        if len(times) != len(values):
            raise ValueError("times and values differ in length")
        n = len(times)
        self._call(lib.sinter_walls_set_electric_schedule, self._ptr, self._index(k), n,
                   (ctypes.c_double * max(n, 1))(*times), (ctypes.c_double * max(n, 1))(*values))

    def set_electric_pulse(self, k: int, on: float, off: float) -> None:
        """Pulse wall k's drive: on for `on` s, off for `off` s, from t = 0 (off = 0: continuous)."""
        self._call(lib.sinter_walls_set_electric_pulse, self._ptr, self._index(k), float(on),
                   float(off))

    def set_electric_limit(self, k: int, limit: float) -> None:
        """Compliance limit of wall k's supply: |V| of a current electrode, |I| of a potential
        one (network model); 0: none."""
        self._call(lib.sinter_walls_set_electric_limit, self._ptr, self._index(k), float(limit))

    def set_thermal(self, k: int, mode: Union[str, int], value: float = 0.0) -> None:
        """Thermal boundary: mode "reservoir", "adiabatic", "resistance" (R'' [m^2 K/W]),
        "transfer" (h [W/(m^2 K)]) or "imposed" (touching particles take the wall's
        temperature)."""
        if isinstance(mode, str):
            mode = WallThermal[mode.upper()]
        self._call(lib.sinter_walls_set_thermal, self._ptr, self._index(k), int(mode),
                   float(value))

    def state(self, k: int) -> Tuple[Tuple[float, float, float], Tuple[float, float, float]]:
        """(point, velocity) of wall k at the stepper's current time, as tuples."""
        point, velocity = (ctypes.c_double * 3)(), (ctypes.c_double * 3)()
        self._call(lib.sinter_walls_get_state, self._ptr, self._index(k), point, velocity)
        return tuple(point), tuple(velocity)

    def normal(self, k: int) -> Tuple[float, float, float]:
        """Unit normal of wall k (into the particle region)."""
        normal = (ctypes.c_double * 3)()
        self._call(lib.sinter_walls_get_normal, self._ptr, self._index(k), normal)
        return tuple(normal)

    def force(self, k: int) -> Tuple[float, float, float]:
        """Force the particles exerted on wall k in the last accepted step [N]."""
        force = (ctypes.c_double * 3)()
        self._call(lib.sinter_walls_get_force, self._ptr, self._index(k), force)
        return tuple(force)

    def __repr__(self) -> str:
        return "<sinter.Walls %s>" % ("closed" if self.closed else "n=%d" % self.count)
