"""Materials: named sets of parameters with SI units, defaults and valid ranges."""

import collections
import ctypes
import enum
import itertools
from typing import Any, Dict, List, Mapping, Optional, Union

from ._errors import NotFound, Status, check
from ._lib import MaterialPtr, c_enum, lib, text
from .context import Context, _Handle

#: What Material.describe() returns; values in the parameter's SI unit.
ParamInfo = collections.namedtuple("ParamInfo", "unit meaning default min max")


def _material_params() -> List[Any]:
    """[(KEY, id)] of every parameter of the library, in order."""
    members = []
    for param in itertools.count():
        info = _param_info(param)
        if info is None:
            return members
        members.append((info[0].upper(), param))


def _given(arguments: Dict[str, Any]) -> Dict[str, float]:
    """The parameter keywords of a call (its locals()) that were given (not None)."""
    return {key: arguments[key] for key in Material.KEYWORDS if arguments.get(key) is not None}


def _param_id(key):
    """The sinter_material_param of a key such as "youngs_modulus" (or a MaterialParam)."""
    if isinstance(key, MaterialParam):
        return int(key)
    param = c_enum()
    status = lib.sinter_material_param_find(key.encode("utf-8"), ctypes.byref(param))
    if status == Status.ERR_NOT_FOUND:
        raise NotFound(Status.ERR_NOT_FOUND,
                       "unknown material parameter %r; known keys: %s"
                       % (key, ", ".join(Material.keys())))
    check(status, None, "sinter_material_param_find")
    return param.value


def _param_info(param):
    """(key, ParamInfo) of a parameter id, or None past the last parameter."""
    key, unit, meaning = ctypes.c_char_p(), ctypes.c_char_p(), ctypes.c_char_p()
    default, low, high = ctypes.c_double(), ctypes.c_double(), ctypes.c_double()
    status = lib.sinter_material_param_info(
        param, ctypes.byref(key), ctypes.byref(unit), ctypes.byref(meaning),
        ctypes.byref(default), ctypes.byref(low), ctypes.byref(high))
    if status == Status.ERR_RANGE:
        return None
    check(status, None, "sinter_material_param_info")
    return text(key.value), ParamInfo(text(unit.value), text(meaning.value),
                                      default.value, low.value, high.value)


#: sinter_material_param as an IntEnum, read from the library: MaterialParam.DENSITY, ...
#: (a member's name is its key in upper case; Material accepts either).
MaterialParam = enum.IntEnum("MaterialParam", _material_params(), module=__name__)


class Material(_Handle):
    """A sinter_material: Material(ctx, "steel", density=7800.0, youngs_modulus=2e11).

    Parameters are read and written by key, m["density"] (SI units, see
    Material.describe). Values outside a parameter's range raise
    InvalidArgument with the library's message naming the key.
    """

    _destroy_function = "sinter_material_destroy"

    #: The keyword parameters of __init__ and update: every key of the library (checked by
    #: the tests against Material.keys()).
    KEYWORDS = (
        "density", "youngs_modulus", "poisson_ratio", "damping_ratio", "friction_static",
        "friction_dynamic", "friction_damping_ratio", "rolling_friction",
        "rolling_damping_ratio", "contact_stiffness", "contact_exponent", "wall_stiffness",
        "wall_exponent", "bond_stiffness", "bond_exponent", "bond_critical_strain",
        "drag_coefficient", "thermal_conductivity", "heat_capacity", "emissivity",
        "absorptance", "softening_law", "softening_temperature", "softening_rate",
        "softening_floor", "electric_conductivity", "atomic_volume", "surface_energy",
        "grain_boundary_energy", "surface_thickness", "grain_boundary_thickness",
        "lattice_diffusion_prefactor", "lattice_activation_energy",
        "surface_diffusion_prefactor", "surface_activation_energy",
        "grain_boundary_diffusion_prefactor", "grain_boundary_activation_energy",
        "surface_mobile_fraction", "grain_boundary_mobile_fraction", "atomic_volume_hot",
        "surface_energy_hot", "grain_boundary_energy_hot", "surface_thickness_hot",
        "grain_boundary_thickness_hot", "lattice_diffusion_prefactor_hot",
        "lattice_activation_energy_hot", "surface_diffusion_prefactor_hot",
        "surface_activation_energy_hot", "grain_boundary_diffusion_prefactor_hot",
        "grain_boundary_activation_energy_hot", "surface_mobile_fraction_hot",
        "grain_boundary_mobile_fraction_hot", "phase_transition_temperature",
        "melting_temperature", "latent_heat", "melting_range", "melting_stop",
        "neck_boundary_path", "neck_cone_path", "neck_cap_path", "lattice_mobile_fraction"
    )

    def __init__(self, context: Context, name: Optional[str] = None,
                 params: Optional[Mapping[str, float]] = None, *,
                 density: Optional[float] = None,
                 youngs_modulus: Optional[float] = None,
                 poisson_ratio: Optional[float] = None,
                 damping_ratio: Optional[float] = None,
                 friction_static: Optional[float] = None,
                 friction_dynamic: Optional[float] = None,
                 friction_damping_ratio: Optional[float] = None,
                 rolling_friction: Optional[float] = None,
                 rolling_damping_ratio: Optional[float] = None,
                 contact_stiffness: Optional[float] = None,
                 contact_exponent: Optional[float] = None,
                 wall_stiffness: Optional[float] = None,
                 wall_exponent: Optional[float] = None,
                 bond_stiffness: Optional[float] = None,
                 bond_exponent: Optional[float] = None,
                 bond_critical_strain: Optional[float] = None,
                 drag_coefficient: Optional[float] = None,
                 thermal_conductivity: Optional[float] = None,
                 heat_capacity: Optional[float] = None,
                 emissivity: Optional[float] = None,
                 absorptance: Optional[float] = None,
                 softening_law: Optional[float] = None,
                 softening_temperature: Optional[float] = None,
                 softening_rate: Optional[float] = None,
                 softening_floor: Optional[float] = None,
                 electric_conductivity: Optional[float] = None,
                 atomic_volume: Optional[float] = None,
                 surface_energy: Optional[float] = None,
                 grain_boundary_energy: Optional[float] = None,
                 surface_thickness: Optional[float] = None,
                 grain_boundary_thickness: Optional[float] = None,
                 lattice_diffusion_prefactor: Optional[float] = None,
                 lattice_activation_energy: Optional[float] = None,
                 surface_diffusion_prefactor: Optional[float] = None,
                 surface_activation_energy: Optional[float] = None,
                 grain_boundary_diffusion_prefactor: Optional[float] = None,
                 grain_boundary_activation_energy: Optional[float] = None,
                 surface_mobile_fraction: Optional[float] = None,
                 grain_boundary_mobile_fraction: Optional[float] = None,
                 atomic_volume_hot: Optional[float] = None,
                 surface_energy_hot: Optional[float] = None,
                 grain_boundary_energy_hot: Optional[float] = None,
                 surface_thickness_hot: Optional[float] = None,
                 grain_boundary_thickness_hot: Optional[float] = None,
                 lattice_diffusion_prefactor_hot: Optional[float] = None,
                 lattice_activation_energy_hot: Optional[float] = None,
                 surface_diffusion_prefactor_hot: Optional[float] = None,
                 surface_activation_energy_hot: Optional[float] = None,
                 grain_boundary_diffusion_prefactor_hot: Optional[float] = None,
                 grain_boundary_activation_energy_hot: Optional[float] = None,
                 surface_mobile_fraction_hot: Optional[float] = None,
                 grain_boundary_mobile_fraction_hot: Optional[float] = None,
                 phase_transition_temperature: Optional[float] = None,
                 melting_temperature: Optional[float] = None,
                 latent_heat: Optional[float] = None,
                 melting_range: Optional[float] = None,
                 melting_stop: Optional[float] = None,
                 neck_boundary_path: Optional[float] = None,
                 neck_cone_path: Optional[float] = None,
                 neck_cap_path: Optional[float] = None,
                 lattice_mobile_fraction: Optional[float] = None) -> None:
        """Create a material with every parameter at its default, then set `params` (a
        mapping {key: value}) and the keywords given (None: left at the default).

        Parameters by key, SI units, the library's defaults and valid closed ranges
        (Material.describe(key) gives them with their meaning; the neck model's *_hot set
        is used at and above phase_transition_temperature):

        density [kg/m^3]: default 2500, range [0, 1e+06]
        youngs_modulus [Pa]: default 1e+07, range [0, 1e+13]
        poisson_ratio [1]: default 0.3, range [-0.999, 0.4999]
        damping_ratio [1]: default 0, range [0, 10]
        friction_static [1]: default 0.3, range [0, 100]
        friction_dynamic [1]: default 0.3, range [0, 100]
        friction_damping_ratio [1]: default 0, range [0, 10]
        rolling_friction [1]: default 0, range [0, 100]
        rolling_damping_ratio [1]: default 0, range [0, 10]
        contact_stiffness [Pa]: default 1e+07, range [0, 1e+15]
        contact_exponent [1]: default 1, range [0, 20]
        wall_stiffness [Pa]: default 1e+07, range [0, 1e+15]
        wall_exponent [1]: default 1, range [0, 20]
        bond_stiffness [Pa]: default 0, range [0, 1e+15]
        bond_exponent [1]: default 1, range [0, 20]
        bond_critical_strain [1]: default 0.1, range [0, 1]
        drag_coefficient [kg/s]: default 0, range [0, 1e+12]
        thermal_conductivity [W/(m K)]: default 1, range [0, 100000]
        heat_capacity [J/(kg K)]: default 1000, range [0, 1e+07]
        emissivity [1]: default 0, range [0, 1]
        absorptance [1]: default 1, range [0, 1]
        softening_law [1]: default 0, range [0, 4]
        softening_temperature [K]: default 400, range [0, 100000]
        softening_rate [1/K or 1]: default 1, range [0, 1e+06]
        softening_floor [1]: default 0, range [0, 1]
        electric_conductivity [S/m]: default 0, range [0, 1e+12]
        atomic_volume [m^3]: default 1.18e-29, range [0, 1e-26]
        surface_energy [J/m^2]: default 1.78, range [0, 100]
        grain_boundary_energy [J/m^2]: default 0.55, range [0, 100]
        surface_thickness [m]: default 2.3e-10, range [0, 1e-06]
        grain_boundary_thickness [m]: default 6.9e-10, range [0, 1e-06]
        lattice_diffusion_prefactor [m^2/s]: default 6.2e-05, range [0, 1e+30]
        lattice_activation_energy [J/mol]: default 207000, range [0, 1e+07]
        surface_diffusion_prefactor [m^2/s]: default 7e+06, range [0, 1e+30]
        surface_activation_energy [J/mol]: default 370000, range [0, 1e+07]
        grain_boundary_diffusion_prefactor [m^2/s]: default 2.7e+11, range [0, 1e+30]
        grain_boundary_activation_energy [J/mol]: default 500000, range [0, 1e+07]
        surface_mobile_fraction [1]: default 0.2, range [0, 1]
        grain_boundary_mobile_fraction [1]: default 0.1, range [0, 1]
        atomic_volume_hot [m^3]: default 1.18e-29, range [0, 1e-26]
        surface_energy_hot [J/m^2]: default 1.78, range [0, 100]
        grain_boundary_energy_hot [J/m^2]: default 0.55, range [0, 100]
        surface_thickness_hot [m]: default 2.3e-10, range [0, 1e-06]
        grain_boundary_thickness_hot [m]: default 6.9e-10, range [0, 1e-06]
        lattice_diffusion_prefactor_hot [m^2/s]: default 6.2e-05, range [0, 1e+30]
        lattice_activation_energy_hot [J/mol]: default 207000, range [0, 1e+07]
        surface_diffusion_prefactor_hot [m^2/s]: default 7e+06, range [0, 1e+30]
        surface_activation_energy_hot [J/mol]: default 370000, range [0, 1e+07]
        grain_boundary_diffusion_prefactor_hot [m^2/s]: default 2.7e+11, range [0, 1e+30]
        grain_boundary_activation_energy_hot [J/mol]: default 500000, range [0, 1e+07]
        surface_mobile_fraction_hot [1]: default 0.2, range [0, 1]
        grain_boundary_mobile_fraction_hot [1]: default 0.1, range [0, 1]
        phase_transition_temperature [K]: default 0, range [0, 100000]
        melting_temperature [K]: default 0 (no check), range [0, 100000]; without latent heat
            and with melting_stop 1 a step that takes a particle past it stops with
            SINTER_ERR_DOMAIN
        latent_heat [J/kg]: default 0, range [0, 1e8]; absorbed over [melting_temperature,
            melting_temperature + melting_range] as an apparent heat capacity (enthalpy method)
        melting_range [K]: default 1, range (0, 10000]
        melting_stop [1]: default 1 (stop without latent heat), 0 heats on; whole number
        neck_boundary_path, neck_cone_path, neck_cap_path [1]: defaults 0.25, 0.5, 1, range
            (0, 100]: the 7DOF neck's diffusion paths (grain boundary: this times the neck
            radius; cone and cap: this times the cone's slant; docs/7dof.md sec. 3)
        lattice_mobile_fraction [1]: default 1, range [0, 1]: n_v of lattice diffusion
        """
        handle = MaterialPtr()
        encoded = None if name is None else name.encode("utf-8")
        check(lib.sinter_material_create(ctypes.byref(handle), context._ptr, encoded),
              context._handle, "sinter_material_create")
        super().__init__(context, handle)
        values = _given(locals())
        try:
            self.update(params)
            self.update(values)
        except Exception:
            self.close()
            raise

    @classmethod
    def _from_handle(cls, context, handle):
        material = cls.__new__(cls)
        _Handle.__init__(material, context, handle)
        return material

    @staticmethod
    def keys() -> List[str]:
        """Every parameter key, in the library's order."""
        keys = []
        for param in itertools.count():
            info = _param_info(param)
            if info is None:
                return keys
            keys.append(info[0])

    @staticmethod
    def describe(key: Union[str, "MaterialParam"]) -> ParamInfo:
        """ParamInfo(unit, meaning, default, min, max) of a parameter key."""
        return _param_info(_param_id(key))[1]

    @property
    def name(self) -> str:
        """The material's name (\"\" if none)."""
        return text(lib.sinter_material_name(self._ptr))

    def __getitem__(self, key: Union[str, "MaterialParam"]) -> float:
        value = ctypes.c_double()
        self._check(lib.sinter_material_get(self._ptr, _param_id(key), ctypes.byref(value)),
                    "sinter_material_get")
        return value.value

    def __setitem__(self, key: Union[str, "MaterialParam"], value: float) -> None:
        self._check(lib.sinter_material_set(self._ptr, _param_id(key), float(value)),
                    "sinter_material_set")

    def update(self, params: Optional[Mapping[str, float]] = None, *,
               density: Optional[float] = None,
               youngs_modulus: Optional[float] = None,
               poisson_ratio: Optional[float] = None,
               damping_ratio: Optional[float] = None,
               friction_static: Optional[float] = None,
               friction_dynamic: Optional[float] = None,
               friction_damping_ratio: Optional[float] = None,
               rolling_friction: Optional[float] = None,
               rolling_damping_ratio: Optional[float] = None,
               contact_stiffness: Optional[float] = None,
               contact_exponent: Optional[float] = None,
               wall_stiffness: Optional[float] = None,
               wall_exponent: Optional[float] = None,
               bond_stiffness: Optional[float] = None,
               bond_exponent: Optional[float] = None,
               bond_critical_strain: Optional[float] = None,
               drag_coefficient: Optional[float] = None,
               thermal_conductivity: Optional[float] = None,
               heat_capacity: Optional[float] = None,
               emissivity: Optional[float] = None,
               absorptance: Optional[float] = None,
               softening_law: Optional[float] = None,
               softening_temperature: Optional[float] = None,
               softening_rate: Optional[float] = None,
               softening_floor: Optional[float] = None,
               electric_conductivity: Optional[float] = None,
               atomic_volume: Optional[float] = None,
               surface_energy: Optional[float] = None,
               grain_boundary_energy: Optional[float] = None,
               surface_thickness: Optional[float] = None,
               grain_boundary_thickness: Optional[float] = None,
               lattice_diffusion_prefactor: Optional[float] = None,
               lattice_activation_energy: Optional[float] = None,
               surface_diffusion_prefactor: Optional[float] = None,
               surface_activation_energy: Optional[float] = None,
               grain_boundary_diffusion_prefactor: Optional[float] = None,
               grain_boundary_activation_energy: Optional[float] = None,
               surface_mobile_fraction: Optional[float] = None,
               grain_boundary_mobile_fraction: Optional[float] = None,
               atomic_volume_hot: Optional[float] = None,
               surface_energy_hot: Optional[float] = None,
               grain_boundary_energy_hot: Optional[float] = None,
               surface_thickness_hot: Optional[float] = None,
               grain_boundary_thickness_hot: Optional[float] = None,
               lattice_diffusion_prefactor_hot: Optional[float] = None,
               lattice_activation_energy_hot: Optional[float] = None,
               surface_diffusion_prefactor_hot: Optional[float] = None,
               surface_activation_energy_hot: Optional[float] = None,
               grain_boundary_diffusion_prefactor_hot: Optional[float] = None,
               grain_boundary_activation_energy_hot: Optional[float] = None,
               surface_mobile_fraction_hot: Optional[float] = None,
               grain_boundary_mobile_fraction_hot: Optional[float] = None,
               phase_transition_temperature: Optional[float] = None,
               melting_temperature: Optional[float] = None,
               latent_heat: Optional[float] = None,
               melting_range: Optional[float] = None,
               melting_stop: Optional[float] = None,
               neck_boundary_path: Optional[float] = None,
               neck_cone_path: Optional[float] = None,
               neck_cap_path: Optional[float] = None,
               lattice_mobile_fraction: Optional[float] = None) -> None:
        """Set several parameters from a mapping {key: value} and/or the keywords (None:
        unchanged); see __init__ for the keys, units and ranges. An unknown key of the
        mapping raises NotFound listing the known ones."""
        for key, value in dict(params or {}).items():
            self[key] = value
        for key, value in _given(locals()).items():
            self[key] = value

    def params(self) -> Dict[str, float]:
        """{key: value} of every parameter."""
        return {key: self[key] for key in self.keys()}

    def clone(self) -> "Material":
        """An independent copy (name and every parameter)."""
        handle = MaterialPtr()
        self._check(lib.sinter_material_clone(ctypes.byref(handle), self._ptr),
                    "sinter_material_clone")
        return Material._from_handle(self._context, handle)

    def __repr__(self) -> str:
        return "<sinter.Material %s>" % ("closed" if self.closed else repr(self.name))
