"""Particle sets: adding and removing particles, and zero-copy field views.

Field views are NumPy arrays when NumPy imports and USE_NUMPY is true, and
memoryviews otherwise. Set the environment variable SINTER_NO_NUMPY=1 before
import, or sinter.particles.USE_NUMPY = False at run time, to get memoryviews.
"""

import collections
import ctypes
import enum
from typing import TYPE_CHECKING, Any, Callable, Iterable, Optional, Sequence, Union
import itertools
import numbers
import os

from ._errors import NotFound, SinterError, Status, check
from ._lib import MaterialPtr, ParticlesPtr, c_enum, lib, text
from .context import _Handle
from .material import Material

if TYPE_CHECKING:  # pragma: no cover
    from .context import Context


def _import_numpy():
    if os.environ.get("SINTER_NO_NUMPY", "") not in ("", "0"):
        return None
    try:
        import numpy
    except ImportError:
        return None
    return numpy


numpy = _import_numpy()

#: Module-level switch: field views are NumPy arrays when true, memoryviews when false.
USE_NUMPY = numpy is not None

#: One particle field: id (sinter_field), name, SI unit, struct format of an
#: element ('d', 'i', 'I', 'Q'), components per particle, and whether it may be written.
FieldInfo = collections.namedtuple("FieldInfo", "id name unit format components writable")

# sinter_dtype -> struct/NumPy format character.
_FORMATS = {0: "d", 1: "i", 2: "I", 3: "Q"}  # DOUBLE, INT32, UINT32, UINT64
_CTYPES = {"d": ctypes.c_double, "i": ctypes.c_int32, "I": ctypes.c_uint32, "Q": ctypes.c_uint64}
# sinter_field_info() does not say which fields are read-only; sinter.h documents these.
_READ_ONLY_FIELDS = {"id"}


def _load_fields():
    """{name: FieldInfo} for field ids 0, 1, ... until SINTER_ERR_RANGE."""
    fields = {}
    for field in itertools.count():
        name, unit = ctypes.c_char_p(), ctypes.c_char_p()
        dtype, components = c_enum(), ctypes.c_size_t()
        status = lib.sinter_field_info(field, ctypes.byref(name), ctypes.byref(unit),
                                       ctypes.byref(dtype), ctypes.byref(components))
        if status == Status.ERR_RANGE:
            return fields
        check(status, None, "sinter_field_info")
        fields[text(name.value)] = FieldInfo(
            field, text(name.value), text(unit.value), _FORMATS.get(dtype.value),
            components.value, text(name.value) not in _READ_ONLY_FIELDS)


#: Every particle field of the loaded library, by name.
FIELDS = _load_fields()


#: sinter_field as an IntEnum, read from the library: Field.POSITION, ... (Particles accepts
#: a Field or its name in lower case).
Field = enum.IntEnum("Field", [(name.upper(), info.id) for name, info in FIELDS.items()],
                     module=__name__)


class DType(enum.IntEnum):
    """sinter_dtype: element type of a field (FieldInfo.format is its struct character)."""

    DOUBLE = 0  #: "d"
    INT32 = 1  #: "i"
    UINT32 = 2  #: "I"
    UINT64 = 3  #: "Q"


class ParticleFlag(enum.IntFlag):
    """sinter_particle_flag: bits of the "flags" field."""

    FIXED = 1  #: position and velocity are prescribed (not integrated)
    NO_ROTATION = 2  #: spin is not integrated
    FIXED_TEMPERATURE = 4  #: temperature is not integrated
    ELECTRIFIED = 8  #: set by the electric submodel: touches an electrified wall
    LIT = 16  #: set by the beam heat submodels: the beam has given the particle power


class Property(enum.IntEnum):
    """sinter_property: a material property that may be tabulated against temperature."""

    THERMAL_CONDUCTIVITY = 0  #: k(theta) [W/(m K)]
    HEAT_CAPACITY = 1  #: C(theta) [J/(kg K)]
    ELECTRIC_CONDUCTIVITY = 2  #: sigma(theta) [S/m]


def _field(name):
    if isinstance(name, Field):
        name = name.name.lower()
    try:
        return FIELDS[name]
    except KeyError:
        raise NotFound(Status.ERR_NOT_FOUND, "unknown particle field %r; fields: %s"
                       % (name, ", ".join(FIELDS))) from None


class _SetKeeper:
    """Held by the memory under a field array: while an array over a set's memory lives (a
    NumPy array kept after its ``with`` block), closing the set (or its context) only marks
    it closed, and its C object is destroyed when the last such array goes, so a write
    through the array never lands in freed memory."""

    def __init__(self, particles):
        self._particles = particles
        particles._users += 1

    def __del__(self):
        try:
            self._particles._users -= 1
            self._particles._destroy_if_unused()
        except Exception:  # interpreter shutdown: modules may be gone
            pass


def _wrap(address, count, components, fmt, writable, owner=None):
    """A NumPy array or memoryview over count*components elements at `address` (no copy).

    owner: the Particles whose memory it is, kept undestroyed while the array (whose base
    holds the memory object) lives.
    """
    size = count * components
    if size == 0:
        buffer = memoryview(bytearray() if writable else b"")
    else:
        memory = (_CTYPES[fmt] * size).from_address(address)
        if owner is not None:
            memory._sinter_keeper = _SetKeeper(owner)
        buffer = memoryview(memory).cast("B")
        if not writable:
            buffer = buffer.toreadonly()
    shape = (count, components) if components > 1 else (count,)
    if USE_NUMPY and numpy is not None:
        return numpy.frombuffer(buffer, dtype=fmt).reshape(shape)
    return buffer.cast(fmt, shape) if size > 0 else buffer.cast(fmt)


class FieldView:
    """Borrows one field of a Particles while inside ``with``; see Particles.view."""

    def __init__(self, particles: "Particles", field: FieldInfo, writable: bool) -> None:
        self.particles = particles
        self.field = field
        self.writable = writable
        self._array = None
        self._borrowed = False

    def __enter__(self):
        if self._borrowed:
            raise RuntimeError("this field view is already open")
        c_function = lib.sinter_particles_view if self.writable else lib.sinter_particles_view_read
        if self.field.format is None:
            raise NotImplementedError("field %r has an element type this binding does not know"
                                      % self.field.name)
        data, count, components = ctypes.c_void_p(), ctypes.c_size_t(), ctypes.c_size_t()
        self.particles._check(
            c_function(self.particles._ptr, self.field.id, ctypes.byref(data),
                       ctypes.byref(count), ctypes.byref(components)),
            c_function.__name__)
        self._borrowed = True
        try:
            self._array = _wrap(data.value, count.value, components.value,
                                self.field.format, self.writable, owner=self.particles)
        except BaseException:
            self.release()
            raise
        return self._array

    def __exit__(self, *exc_info):
        self.release()

    def release(self) -> None:
        """Give the field back to the library; the array must not be used afterwards."""
        if not self._borrowed:
            return
        self._borrowed = False
        array, self._array = self._array, None
        if isinstance(array, memoryview):
            try:
                array.release()  # later use raises ValueError instead of touching freed memory
            except BufferError:  # something still exports it
                pass
        handle = self.particles._handle
        if handle is not None:  # a destroyed set has no views to release
            self.particles._check(lib.sinter_particles_release(handle, self.field.id),
                                  "sinter_particles_release")


def _flatten_positions(positions):
    """Positions as a flat list of 3n floats, from [(x, y, z), ...] or [x0, y0, z0, ...]."""
    positions = list(positions)
    if positions and not isinstance(positions[0], numbers.Real):
        flat = []
        for point in positions:
            point = list(point)
            if len(point) != 3:
                raise ValueError("each position needs 3 coordinates, got %r" % (point,))
            flat.extend(float(x) for x in point)
        return flat
    if len(positions) % 3:
        raise ValueError("positions need 3 coordinates per particle, got %d values"
                         % len(positions))
    return [float(x) for x in positions]


def _double_arrays(positions, radii):
    """(n, positions pointer, radii pointer, keep-alive) for sinter_particles_add."""
    double_p = ctypes.POINTER(ctypes.c_double)
    if numpy is not None and USE_NUMPY:
        xyz = numpy.ascontiguousarray(positions, dtype=numpy.float64)
        if xyz.size % 3 or xyz.ndim > 2 or (xyz.ndim == 2 and xyz.shape[1] != 3):
            raise ValueError("positions must have shape (n, 3) or (3n,), got %s" % (xyz.shape,))
        n = xyz.size // 3
        r = numpy.asarray(radii, dtype=numpy.float64)
        r = numpy.full(n, r) if r.ndim == 0 else numpy.ascontiguousarray(r.reshape(-1))
        if r.size != n:
            raise ValueError("%d positions but %d radii" % (n, r.size))
        return n, xyz.ctypes.data_as(double_p), r.ctypes.data_as(double_p), (xyz, r)
    flat = _flatten_positions(positions)
    n = len(flat) // 3
    r = [float(radii)] * n if isinstance(radii, numbers.Real) else [float(x) for x in radii]
    if len(r) != n:
        raise ValueError("%d positions but %d radii" % (n, len(r)))
    xyz_c, r_c = (ctypes.c_double * len(flat))(*flat), (ctypes.c_double * n)(*r)
    return n, xyz_c, r_c, (xyz_c, r_c)


class Particles(_Handle):
    """A sinter_particles set of spheres. Lengths in m, temperatures in K.

    Materials are registered by id (0..255) with set_material before add().
    Fields ("position", "velocity", "radius", "mass", ... see FIELDS) are read
    and written in place through view(), or copied with get() and set().
    """

    _destroy_function = "sinter_particles_destroy"

    def __init__(self, context: "Context") -> None:
        handle = ParticlesPtr()
        check(lib.sinter_particles_create(ctypes.byref(handle), context._ptr),
              context._handle, "sinter_particles_create")
        super().__init__(context, handle)

    @classmethod
    def _borrowed_from(cls, owner, handle):
        """A Particles over a set another object owns (a scene's): closing it destroys nothing."""
        particles = cls.__new__(cls)
        _Handle.__init__(particles, owner.context, handle, owned=False)
        particles._borrow(owner)
        return particles

    def _size(self, c_function):
        value = ctypes.c_size_t()
        self._check(c_function(self._ptr, ctypes.byref(value)), c_function.__name__)
        return value.value

    @property
    def count(self) -> int:
        """Number of particles."""
        return self._size(lib.sinter_particles_count)

    def __len__(self) -> int:
        return self.count

    @property
    def owned_count(self) -> int:
        """Owned particles: the first owned_count; the rest are ghost particles, the images a
        periodic stepper made of them (Stepper.set_periodic)."""
        return self._size(lib.sinter_particles_owned_count)

    @property
    def capacity(self) -> int:
        """Particles that fit without reallocation."""
        return self._size(lib.sinter_particles_capacity)

    @property
    def views_out(self) -> int:
        """Number of field views currently borrowed."""
        return self._size(lib.sinter_particles_views_out)

    def reserve(self, capacity: int) -> None:
        """Reserve room for `capacity` particles (BusyError while a view is out)."""
        self._check(lib.sinter_particles_reserve(self._ptr, capacity), "sinter_particles_reserve")

    def set_material(self, material_id: int, material: Material) -> None:
        """Register (or replace) material `material_id` (0..255) with a copy of `material`.

        Replacing a material recomputes mass and inertia of its particles.
        """
        self._check(lib.sinter_particles_set_material(self._ptr, material_id, material._ptr),
                    "sinter_particles_set_material")

    def set_softening_curve(self, material_id: int, temperatures: Sequence[float],
                            factors: Sequence[float]) -> None:
        """Tabulated softening of material `material_id`: E(theta)/E_0 through the points
        (temperatures [K], increasing; factors > 0), held constant outside (softening_law 3)."""
        temperatures = [float(t) for t in temperatures]
        factors = [float(f) for f in factors]
        if len(temperatures) != len(factors):
            raise ValueError("%d temperatures but %d factors" % (len(temperatures), len(factors)))
        n = len(temperatures)
        self._check(lib.sinter_particles_set_softening_curve(
            self._ptr, material_id, n, (ctypes.c_double * max(n, 1))(*temperatures),
            (ctypes.c_double * max(n, 1))(*factors)), "sinter_particles_set_softening_curve")

    def set_property_table(self, material_id: int, prop: Property,
                           temperatures: Sequence[float], values: Sequence[float]) -> None:
        """Tabulate `prop` of material `material_id` against temperature: values (> 0, the
        property's SI unit) at temperatures [K] (> 0, strictly increasing), linear between
        points and clamped outside; replaces the material's constant. Empty lists remove it."""
        temperatures = [float(t) for t in temperatures]
        values = [float(v) for v in values]
        if len(temperatures) != len(values):
            raise ValueError("%d temperatures but %d values" % (len(temperatures), len(values)))
        n = len(temperatures)
        self._check(lib.sinter_particles_set_property_table(
            self._ptr, material_id, int(Property(prop)), n,
            (ctypes.c_double * max(n, 1))(*temperatures), (ctypes.c_double * max(n, 1))(*values)),
            "sinter_particles_set_property_table")

    def property_at(self, material_id: int, prop: Property, temperature: float) -> float:
        """Value of `prop` of material `material_id` at `temperature` [K] (its table's or its
        constant)."""
        value = ctypes.c_double()
        self._check(lib.sinter_particles_property(self._ptr, material_id, int(Property(prop)),
                                                  float(temperature), ctypes.byref(value)),
                    "sinter_particles_property")
        return value.value

    def specific_enthalpy(self, material_id: int, temperature: float) -> float:
        """Specific enthalpy [J/kg] of material `material_id` at `temperature` [K]: the
        integral of C from 0 K plus the latent heat absorbed below it."""
        value = ctypes.c_double()
        self._check(lib.sinter_particles_specific_enthalpy(self._ptr, material_id,
                                                           float(temperature),
                                                           ctypes.byref(value)),
                    "sinter_particles_specific_enthalpy")
        return value.value

    def set_softening_callback(self, material_id: int,
                               function: Callable[[float], float]) -> None:
        """Host softening law of material `material_id`: function(theta [K]) -> E/E_0 (> 0).

        Called for every particle of the material at each force evaluation. An
        exception stops the stepper at its last accepted state and is raised
        again by the Stepper call.
        """
        from . import _callbacks
        from ._lib import SofteningFn

        def trampoline(theta, user):
            try:
                return float(function(theta))
            except BaseException as exception:
                _callbacks.store(exception)
                return float("nan")  # the library stops with SINTER_ERR_CALLBACK

        c_function = SofteningFn(trampoline)
        self._keep(("softening", int(material_id)), c_function)  # before: the library keeps it
        self._call(lib.sinter_particles_set_softening_callback, self._ptr, material_id,
                   c_function, None)

    def get_material(self, material_id: int) -> Material:
        """A copy (new Material) of the set's material `material_id`."""
        borrowed = MaterialPtr()
        self._check(lib.sinter_particles_get_material(self._ptr, material_id,
                                                      ctypes.byref(borrowed)),
                    "sinter_particles_get_material")
        copy = MaterialPtr()
        self._check(lib.sinter_material_clone(ctypes.byref(copy), borrowed),
                    "sinter_material_clone")
        return Material._from_handle(self._context, copy)

    def add(self, positions: Any, radii: Any, material_id: int = 0,
            temperature: float = 293.15, ids: Optional[Iterable[int]] = None) -> range:
        """Append particles; return the range of their indices.

        positions: n points (x, y, z) [m], as an (n, 3) or flat sequence/array.
        radii: n radii [m] (or one for all), each > 0.
        temperature: initial temperature of every new particle [K].
        ids: n persistent ids chosen by the caller (sinter_particles_add_with_ids:
        unique in the set, not 2**64 - 1); None numbers them from the set's counter.
        Mass = density * 4/3 pi r^3 and inertia = 2/5 m r^2 follow from the
        material. On error nothing is added.
        """
        n, xyz, r, _keep_alive = _double_arrays(positions, radii)
        first = ctypes.c_size_t()
        if ids is None:
            self._check(lib.sinter_particles_add(self._ptr, n, xyz, r, material_id,
                                                 float(temperature), ctypes.byref(first)),
                        "sinter_particles_add")
            return range(first.value, first.value + n)
        id_list = [int(i) for i in ids]
        if len(id_list) != n:
            raise ValueError("%d positions but %d ids" % (n, len(id_list)))
        if any(i < 0 or i >= 1 << 64 for i in id_list):
            raise ValueError("particle ids must lie in [0, 2**64): %r" % (id_list,))
        id_array = (ctypes.c_uint64 * max(n, 1))(*id_list)
        self._check(lib.sinter_particles_add_with_ids(self._ptr, n, id_array, xyz, r,
                                                      material_id, float(temperature),
                                                      ctypes.byref(first)),
                    "sinter_particles_add_with_ids")
        return range(first.value, first.value + n)

    def remove(self, indices: Iterable[int]) -> None:
        """Remove the particles at `indices` (an int or an iterable); the rest keep their order."""
        indices = [indices] if isinstance(indices, numbers.Integral) else [int(i) for i in indices]
        if any(i < 0 for i in indices):
            raise IndexError("particle indices must not be negative: %r" % (indices,))
        array = (ctypes.c_size_t * len(indices))(*indices)
        self._check(lib.sinter_particles_remove(self._ptr, len(indices), array),
                    "sinter_particles_remove")

    def validate(self) -> None:
        """Check every value; raise InvalidArgument naming the first bad particle and field.

        The error's .index attribute is the bad particle's index.
        """
        bad_index = ctypes.c_size_t()
        try:
            self._check(lib.sinter_particles_validate(self._ptr, ctypes.byref(bad_index)),
                        "sinter_particles_validate")
        except SinterError as error:
            error.index = bad_index.value
            raise

    def find_id(self, particle_id: int) -> int:
        """Index of the particle with persistent id `particle_id` (NotFound if none)."""
        index = ctypes.c_size_t()
        self._check(lib.sinter_particles_find_id(self._ptr, particle_id, ctypes.byref(index)),
                    "sinter_particles_find_id")
        return index.value

    def sort_spatial(self) -> None:
        """Reorder the particles in memory by position (cells of the largest diameter, x
        fastest); ids move with them, indices change (sinter_particles_sort_spatial)."""
        self._check(lib.sinter_particles_sort_spatial(self._ptr), "sinter_particles_sort_spatial")

    def view(self, field: Union[str, "Field"], writable: Optional[bool] = None) -> "FieldView":
        """Zero-copy access to a field: ``with ps.view("position") as x: x[0, 2] = 1e-3``.

        Inside the block x is an array of shape (count, components) or (count,)
        over the library's memory: NumPy when available, else a memoryview.
        writable defaults to True except for read-only fields (id). While a
        view is out, add/remove/reserve raise BusyError. Do not keep x after
        the block: it points at memory the library may move (add, remove, reserve). A NumPy
        array kept anyway keeps the set's memory allocated: closing the set then destroys it
        only once the array is gone.
        """
        info = _field(field)
        return FieldView(self, info, info.writable if writable is None else writable)

    def get(self, field: Union[str, "Field"]) -> Any:
        """A copy of a field: a NumPy array, or a list (of lists) without NumPy."""
        with self.view(field, writable=False) as array:
            return array.tolist() if isinstance(array, memoryview) else array.copy()

    def set(self, field: Union[str, "Field"], values: Any) -> None:
        """Overwrite a field with `values` (same shape as get(), or one value for all)."""
        with self.view(field) as array:
            if not isinstance(array, memoryview):
                array[...] = values
                return
            flat = array.cast("B").cast(array.format)
            convert = float if array.format == "d" else int
            if isinstance(values, numbers.Number):
                items = [values] * len(flat)
            elif array.ndim == 2:
                items = [x for row in values for x in row]
            else:
                items = list(values)
            if len(items) != len(flat):
                raise ValueError("%s needs %d values, got %d" % (field, len(flat), len(items)))
            for i, value in enumerate(items):
                flat[i] = convert(value)

    def __repr__(self) -> str:
        return "<sinter.Particles %s>" % ("closed" if self.closed else "n=%d" % self.count)
