"""Steppers: time integration over a particle set, walls and submodels; checkpoints."""

import ctypes
import dataclasses
import enum
import os
import sys
import time as _time
import weakref
from typing import (TYPE_CHECKING, Any, Callable, Dict, Iterable, List, Mapping, Optional,
                    Sequence, Tuple, Union)

from . import _callbacks
from ._errors import check, check_path
from ._lib import (InsertionOptions as _CInsertionOptions, NeckLawCallbacks, NeckLawFn,
                   ObserverFn, PackingOptions, SinteringStats as _CSinteringStats,
                   StepperPtr, StepperStats as _CStats, lib)
from .context import Context, _Handle

if TYPE_CHECKING:  # pragma: no cover
    from .models import ElectricModel, ForceModel, HeatModel
    from .packing import InsertionRegion
    from .particles import Particles
    from .walls import Walls

PathLike = Union[str, bytes, "os.PathLike[str]", "os.PathLike[bytes]"]
#: progress(time [s], t_end [s]) -> None, or True for a progress bar
Progress = Union[None, bool, Callable[[float, float], Any]]


class StepperKind(enum.IntEnum):
    """sinter_stepper_kind."""

    EXPLICIT = 0  #: velocity Verlet, fixed step (seed 003 sec. 4)
    STAGGERED = 1  #: implicit staggered, adaptive step (seed 000 sec. 3, 6); see set_option
    QUASISTATIC = 2  #: bonded links driven by 7DOF necks, K u = f each step (seed 001 sec. 3.3)


class ThermalScheme(enum.IntEnum):
    """sinter_thermal_scheme: thermal time integration of the explicit stepper."""

    EXPLICIT = 0  #: forward Euler, seed 003 eq. 46 (stable for dt < m C / sum G)
    IMPLICIT = 1  #: backward Euler for conduction (PCG solve), other powers explicit


#: The options of Stepper.set_option by stepper kind: key -> (unit, default, range/meaning).
#: Keys are checked by the library, whose message for an unknown key lists the valid ones.
OPTIONS: Dict[str, Dict[str, str]] = {
    "any": {
        "stream_stores": "[-] -1 (default): time both kinds of stores and keep the faster; "
                         "1 always streaming stores, 0 never (explicit stepper only)",
        "thread_choice": "[-] -1 (default): time steps on the context's threads and on one "
                         "and take the faster; 0 always the context's threads (explicit only)",
        "dt_check": "[-] 1 (default) refuses a fixed step above twice stable_step() "
                    "(explicit only); 0 runs it knowingly",
        "energy_check": "[steps] 1 (default): every step is checked for energy created in "
                        "contacts, stopped with the last accepted state kept (explicit only); "
                        "N: every N-th step; 0 off",
        "reproducible": "[-] 1: pairs sorted by id at every build, every particle's sums in "
                        "that order on one thread: the same bits for any memory order, thread "
                        "count and decomposition (explicit, staggered and quasi-static "
                        "steppers; global sums exact, the averaged electric model swept "
                        "Jacobi, the network's and implicit conduction's PCG with exact dot "
                        "products, the quasi-static solve block-Jacobi PCG with necks one by "
                        "one); 0 (default) off",
    },
    "explicit_staggered": {
        "sort_interval": "[steps] sort the particles spatially every so many steps; 0 "
                         "(default) never; whole number >= 0",
        "rotation": "[-] 1 (default) integrates the rotation vector, 0 leaves it",
    },
    "explicit": {
        "frozen_heat": "[-] 1: freeze the mechanics at rest and step the heat alone at its own "
                       "accuracy control (docs/steppers.md); 0 (default) off",
        "frozen_ke": "[J] at rest below this kinetic energy per particle; 1e-12; > 0",
        "frozen_settle": "[steps] explicit steps before the rest test; 1000; whole number >= 0",
        "frozen_rtol": "[-] relative temperature tolerance of a heat step; 1e-4; > 0",
        "frozen_atol": "[K] absolute temperature tolerance of a heat step; 0.01; > 0",
        "frozen_dt_max": "[s] largest heat step; 0 (default: none); >= 0",
        "frozen_travel": "[radii] a moving source's axis travels at most this many smallest "
                         "radii in a heat step; 0.05; >= 0 (0: no limit)",
        "frozen_wake": "[-] relative change of a softening factor that wakes the mechanics; "
                       "0.01; > 0",
        "heat_interval": "[steps] 1 (default) advances the temperatures every step; k: every "
                         "k-th step over k dt (conduction and convection only, explicit "
                         "thermal scheme, not with frozen_heat); whole number in [1, 1000]",
    },
    "staggered": {
        "phi": "[-] trapezoidal parameter; 0.5 (default, second order), 1 backward Euler; "
               "(0, 1]",
        "target_iterations": "[-] K_d of seed 000 eq. 49; 10; whole number in [2, 1000]",
        "tolerance": "[-] TOL_r = TOL_theta of eq. 48; 5e-4; (0, 1)",
        "exponent": "[-] p of eq. 49; 2; (0, 10]",
        "dt_max": "[s] largest step; +inf; > 0",
        "dt_min": "[s] smallest step before SINTER_ERR_NOT_CONVERGED; 1e-12; (0, dt_max]",
        "adaptive": "[-] 1 (default) adapts the step, 0 keeps it",
        "position_tolerance": "[m] absolute floor of the position test; 0; >= 0",
        "temperature_tolerance": "[K] absolute floor of the temperature test; 0; >= 0",
        "scheme": "[-] 0 the seed's Algorithm 1, 1 (default) Anderson acceleration with a "
                  "weighted RMS test, PI step control and a predictor",
        "anderson_depth": "[-] m of Anderson(m) in scheme 1; 3; whole number in [0, 10]",
    },
    "quasistatic": {
        "qs_strategy": "[-] 1 or 2 (seed 001 sec. 3.3, fig. 7), 3 (default; the library's own "
                       "addition, not in the seed): CVODE necks",
        "qs_dt_min": "[s] a global step below it fails; 1e-12",
        "qs_dt_max": "[s] largest global step; 10",
        "qs_alpha": "[-] step factor of seed 001 eq. 45, 47; 1.5",
        "qs_error_limit": "[-] eps_lim of eq. 46, weighted RK4 local error per step; 1",
        "qs_grow_fraction": "[-] strategy 2: grow when fewer pairs than this sub-stepped; 0.05",
        "qs_shrink_fraction": "[-] strategy 2: shrink when more than this did; 0.15",
        "qs_contact_tolerance": "[-] new contact if distance < (r_a + r_b)(1 + this); 1e-9",
        "qs_plane_tolerance": "[-] on a principal plane if x_d - r < this r; 1e-6",
        "qs_solve_rtol": "[-] K u = f solved to |f - K u| <= this |f|; 1e-10",
        "qs_rtol": "[-] relative accuracy of the necks; 1e-6",
        "qs_epsilon": "[-] seeded neck radius x0 / min(R_A, R_B); 0.01",
        "qs_h0_ratio": "[-] junction radius of the seeded neck h0 / x0; 1.5",
        "qs_max_strain": "[-] strategy 3: largest approach per step / L0; 7e-5",
        "qs_strain_fraction": "[-] strategy 3: fraction of links allowed to reach it; 0.01",
        "qs_grown_rk4": "[-] strategy 3: 1 (default) advances grown necks by RK4; 0: CVODE",
        "qs_young_pairs": "[-] strategy 3: 1 (default): each young neck on its own CVODE "
                          "steps; 0: one batch",
        "qs_new_contacts": "[-] 1 (default): contacts made during the run become links; 0: "
                           "only those of the first step",
        "qs_neck_law": "[-] 0 (default) the 7DOF model, 1 the grain-boundary diffusion law of "
                       "Bouvard and McMeeking, 2 a host law (set_neck_law)",
        "qs_cell_strain": "[-] periodic axes: 1 (default) the cell follows the links' mean "
                          "approach; 0: the cell keeps its size",
    },
}


def _enum(enum_type, value):
    if isinstance(value, str):
        try:
            return enum_type[value.upper()]
        except KeyError:
            raise ValueError("unknown %s %r; known: %s" % (
                enum_type.__name__, value, ", ".join(m.name.lower() for m in enum_type))) from None
    return enum_type(value)


@dataclasses.dataclass(frozen=True)
class StepperStats:
    """What a stepper did (sinter_stepper_stats); times in s."""

    steps: int
    rejected: int
    neighbor_builds: int
    contacts: int
    wall_contacts: int
    time: float
    dt: float
    seconds_neighbor: float
    seconds_force: float
    seconds_integrate: float
    seconds_total: float
    iterations: int = 0  #: fixed-point iterations (staggered stepper)
    evaluations: int = 0  #: evaluations of the force/electric/heat pipeline
    contraction: float = 0.0  #: staggered scheme 1: contraction of the last step (0: none)
    bonds_broken: int = 0  #: bonds that held in tension and broke (power law bond_strength)

    def as_dict(self) -> Dict[str, Any]:
        return dataclasses.asdict(self)


@dataclasses.dataclass(frozen=True)
class SinteringStats:
    """What a quasi-static stepper reports (sinter_sintering_stats).

    links: bonded links (necks); neck_mean, neck_min, neck_max: neck radii [m];
    neck_ratio_mean: mean neck radius / smaller particle radius [-]; shrinkage: homogeneous
    strain along x, y, z (positive: shrinking) [-]; relative_density: green density over
    (1 - s_x)(1 - s_y)(1 - s_z) [-]; coordination: 2 links / particles [-]; pcg_iterations:
    linear-solver iterations so far.
    """

    links: int
    neck_mean: float
    neck_min: float
    neck_max: float
    neck_ratio_mean: float
    shrinkage: Tuple[float, float, float]
    relative_density: float
    coordination: float
    pcg_iterations: int

    @property
    def linear_shrinkage(self) -> float:
        """Mean of the three shrinkage components [-]."""
        return sum(self.shrinkage) / 3.0

    def as_dict(self) -> Dict[str, Any]:
        return dataclasses.asdict(self)


class _StepperState:
    """Python objects a C stepper uses or was given (kept by its owner)."""

    def __init__(self, thermal):
        self.forces, self.heat_models, self.electric = [], [], None
        self.observer = self.observer_function = None
        self.skin = self.domain = self.kind = None
        self.thermal = thermal


def _path(path):
    return os.fsencode(path)


class Stepper(_Handle):
    """A time integrator (sinter_stepper) over `particles`, `walls` and submodels.

        with sinter.Stepper(ctx, ps, walls, dt=1e-5, forces=[hertz, gravity]) as st:
            st.advance(0.1)
            print(st.time, st.stats.steps)

    The stepper keeps its Particles, Walls and submodels alive (and their C
    objects undestroyed) until it is closed. An exception raised by a Python
    callback (host submodel, observer, wall motion) stops the run at the last
    accepted state and is raised again by advance/step/evaluate.
    """

    _destroy_function = "sinter_stepper_destroy"

    def __init__(self, context: Context, particles: "Particles",
                 walls: Optional["Walls"] = None,
                 kind: Union[StepperKind, str, int] = StepperKind.EXPLICIT,
                 dt: Optional[float] = None, skin: Optional[float] = None,
                 domain: Optional[Tuple[Sequence[float], Sequence[float]]] = None,
                 thermal: Union[ThermalScheme, str, int, None] = None,
                 forces: Iterable["ForceModel"] = (), heat: Iterable["HeatModel"] = (),
                 electric: Optional["ElectricModel"] = None,
                 observer: Optional[Callable[["Stepper", float], Any]] = None,
                 options: Optional[Mapping[str, float]] = None,
                 furnace: Optional[Tuple[Sequence[float], Sequence[float]]] = None) -> None:
        """Create a stepper of `kind` ("explicit", "staggered" or "quasistatic", or a
        StepperKind) over `particles` and `walls` (may be None).

        dt: time step [s] (> 0; the first step of the adaptive kinds); skin: Verlet skin [m]
        (>= 0); domain: (lo, hi) corners [m]; thermal: ThermalScheme of the explicit kind;
        forces, heat: submodels added in order; electric: an ElectricModel; observer:
        observer(stepper, time) after every accepted step; options: {key: value} of
        set_option (OPTIONS lists the keys by kind: "qs_*" for the quasi-static stepper);
        furnace: (times [s], temperatures [K]) of set_furnace.
        """
        handle = StepperPtr()
        check(lib.sinter_stepper_create(ctypes.byref(handle), context._ptr,
                                        int(_enum(StepperKind, kind)), particles._ptr,
                                        walls._ptr if walls is not None else None),
              context._handle, "sinter_stepper_create")
        super().__init__(context, handle)
        self._setup(particles, walls)
        self._state.kind = _enum(StepperKind, kind)
        try:
            if dt is not None:
                self.dt = dt
            if skin is not None:
                self.skin = skin
            if domain is not None:
                self.domain = domain
            if thermal is not None:
                self.thermal_scheme = thermal
            for key, value in dict(options or {}).items():
                self.set_option(key, value)
            if furnace is not None:
                self.set_furnace(*furnace)
            for model in forces:
                self.add_force(model)
            for model in heat:
                self.add_heat(model)
            if electric is not None:
                self.electric = electric
            if observer is not None:
                self.observer = observer
        except BaseException:
            self.close()
            raise

    def _setup(self, particles, walls, keeper=None, state=None):
        self.particles = particles
        self.walls = walls
        self._borrow(particles)
        if walls is not None:
            self._borrow(walls)
        # What the C stepper uses lives as long as the C stepper: on this object for a
        # stepper of its own, on the scene for a scene's (whose views come and go).
        self._owner = keeper  # None: this object itself (no self-reference: no cycle)
        self._state = _StepperState(ThermalScheme.EXPLICIT) if state is None else state

    @classmethod
    def _borrowed_from(cls, owner, handle, particles, walls):
        """The stepper of a scene: closing it destroys nothing; what is added to it is
        kept alive by the scene."""
        stepper = cls.__new__(cls)
        _Handle.__init__(stepper, owner.context, handle, owned=False)
        stepper._borrow(owner)
        if getattr(owner, "_stepper_state", None) is None:
            owner._stepper_state = _StepperState(None)
        stepper._setup(particles, walls, keeper=owner, state=owner._stepper_state)
        return stepper

    @property
    def _keeper(self):
        return self if self._owner is None else self._owner

    def _forget(self):
        if self._owner is None:
            self._state.observer_function = None

    @property
    def kind(self) -> Optional[StepperKind]:
        """StepperKind of a stepper made here (None for a scene's)."""
        return self._state.kind

    @property
    def forces(self) -> List["ForceModel"]:
        """The ForceModels added from Python (a scene's own models are not listed)."""
        return list(self._state.forces)

    @property
    def heat_models(self) -> List["HeatModel"]:
        """The HeatModels added from Python, in order (the index of heat_energy)."""
        return list(self._state.heat_models)

    def _guarded(self, c_function, *args):
        return self._call(c_function, self._ptr, *args)

    # --- submodels ---------------------------------------------------------

    def add_force(self, model: "ForceModel") -> "ForceModel":
        """Add a ForceModel (the stepper keeps it alive; it may be shared)."""
        self._call(lib.sinter_stepper_add_force, self._ptr, model._ptr)
        self._keeper._borrow(model)
        self._state.forces.append(model)
        return model

    def add_heat(self, model: "HeatModel") -> "HeatModel":
        """Add a HeatModel; a stepper without one does no thermal work."""
        self._call(lib.sinter_stepper_add_heat, self._ptr, model._ptr)
        self._keeper._borrow(model)
        self._state.heat_models.append(model)
        return model

    @property
    def electric(self) -> Optional["ElectricModel"]:
        """The ElectricModel solved on every evaluation (None: none)."""
        return self._state.electric

    @electric.setter
    def electric(self, model: Optional["ElectricModel"]) -> None:
        self.set_electric(model)

    def set_electric(self, model: Optional["ElectricModel"]) -> None:
        """Give the stepper an ElectricModel, solved on every evaluation (None removes it)."""
        self._call(lib.sinter_stepper_set_electric, self._ptr,
                                                    model._ptr if model is not None else None)
        previous, self._state.electric = self._state.electric, model
        if model is not None:
            self._keeper._borrow(model)
        if previous is not None:
            self._keeper._unborrow(previous)

    # --- settings ----------------------------------------------------------

    @property
    def dt(self) -> float:
        """Time step [s]."""
        return self.stats.dt

    @dt.setter
    def dt(self, dt: float) -> None:
        self._call(lib.sinter_stepper_set_dt, self._ptr, float(dt))

    @property
    def skin(self) -> Optional[float]:
        """Verlet skin [m] as last set here (None: the library's automatic choice, or the
        scene's)."""
        return self._state.skin

    @skin.setter
    def skin(self, skin: float) -> None:
        self._call(lib.sinter_stepper_set_skin, self._ptr, float(skin))
        self._state.skin = float(skin)

    @property
    def domain(self) -> Optional[Tuple[Tuple[float, ...], Tuple[float, ...]]]:
        """(lo, hi) corners [m] of the simulation domain as last set here (None: no domain)."""
        return self._state.domain

    @domain.setter
    def domain(self, corners: Tuple[Sequence[float], Sequence[float]]) -> None:
        lo, hi = corners
        lo, hi = [float(x) for x in lo], [float(x) for x in hi]
        if len(lo) != 3 or len(hi) != 3:
            raise ValueError("a domain is two corners of 3 coordinates each")
        self._call(lib.sinter_stepper_set_domain, self._ptr, (ctypes.c_double * 3)(*lo),
                                                  (ctypes.c_double * 3)(*hi))
        self._state.domain = (tuple(lo), tuple(hi))

    def set_periodic(self, axis: int, lo: float = 0.0, hi: float = 0.0) -> None:
        """Make `axis` (0 x, 1 y, 2 z) periodic with the cell lo..hi [m]; lo = hi = 0 makes it
        non-periodic again. Explicit and staggered steppers: particles wrap into the cell and their
        images within 2 r_max + skin of a face are ghost particles after the owned ones."""
        self._call(lib.sinter_stepper_set_periodic, self._ptr, int(axis), float(lo), float(hi))

    def periodic(self, axis: int) -> Optional[Tuple[float, float]]:
        """The periodic cell (lo, hi) [m] along `axis`, or None when it is not periodic."""
        on, lo, hi = ctypes.c_int(), ctypes.c_double(), ctypes.c_double()
        self._call(lib.sinter_stepper_get_periodic, self._ptr, int(axis), ctypes.byref(on),
                   ctypes.byref(lo), ctypes.byref(hi))
        return (lo.value, hi.value) if on.value else None

    @property
    def thermal_scheme(self) -> Optional[ThermalScheme]:
        """ThermalScheme.EXPLICIT or IMPLICIT (set with the enum, its value or "implicit").

        None for a scene's stepper until set here."""
        return self._state.thermal

    @thermal_scheme.setter
    def thermal_scheme(self, scheme: Union[ThermalScheme, str, int]) -> None:
        scheme = _enum(ThermalScheme, scheme)
        self._call(lib.sinter_stepper_set_thermal_scheme, self._ptr, int(scheme))
        self._state.thermal = scheme

    def set_option(self, key: str, value: float) -> None:
        """Set an option by key (sinter_stepper_set_option); see OPTIONS for the keys of each
        kind with their units, defaults and ranges ("phi", "dt_max", ... of the staggered
        stepper; "qs_strategy", "qs_rtol", ... of the quasi-static one, which take effect when
        set before its first step). An unknown key raises NotFound listing the valid keys, a
        value out of range InvalidArgument."""
        self._call(lib.sinter_stepper_set_option, self._ptr, key.encode("utf-8"), float(value))

    def set_furnace(self, times: Sequence[float], temperatures: Sequence[float]) -> None:
        """Furnace: every particle's temperature follows the piecewise-linear T(t) through
        the points (times [s] strictly increasing, on the stepper's clock; temperatures [K]
        finite and > 0), held constant outside them.

        The quasi-static stepper integrates the necks along T(t); every kind sets the
        particle temperatures to T(t) before its first step and after each accepted step.
        Empty sequences remove the furnace. A stepper with heat models refuses a furnace
        (SinterError ERR_STATE).
        """
        times = [float(t) for t in times]
        temperatures = [float(v) for v in temperatures]
        if len(times) != len(temperatures):
            raise ValueError("set_furnace: %d times but %d temperatures"
                             % (len(times), len(temperatures)))
        n = len(times)
        array = ctypes.c_double * max(n, 1)
        self._call(lib.sinter_stepper_set_furnace, self._ptr, n, array(*times),
                   array(*temperatures))

    def set_neck_law(self,
                     advance: Optional[Callable[[_callbacks.NeckLawBatch], Any]]) -> None:
        """A host neck law for the quasi-static stepper (sinter_stepper_set_neck_law): it
        selects "qs_neck_law" 2; None removes it and selects the 7DOF model (0).

        advance(batch) is called once per global step with every link (a
        sinter.NeckLawBatch) and writes batch.state (count, 7) at batch.time + batch.dt:
        column 0 the neck radius [m], columns 3 and 6 the centre-to-neck-plane distances
        L_A, L_B [m], whose decrease is the pair's free approach. Return None or a
        CallbackResult, as ForceModel.from_callbacks; an exception is raised again from the
        stepper call."""
        table = None
        function = None
        if advance is not None:
            def trampoline(batch_pointer, user):
                try:
                    batch = _callbacks.NeckLawBatch(batch_pointer.contents)
                    try:
                        return _callbacks.result_code(advance(batch))
                    finally:
                        batch.invalidate()
                except BaseException as exception:  # never unwind through C
                    _callbacks.store(exception)
                    return -1

            function = NeckLawFn(trampoline)
            table = NeckLawCallbacks()
            table.struct_size = ctypes.sizeof(NeckLawCallbacks)
            table.advance = function
        self._call(lib.sinter_stepper_set_neck_law, self._ptr,
                   ctypes.byref(table) if table is not None else None, None)
        self._neck_law = function  # the C function must outlive the stepper's use of it

    def set_insertion(self, powder: Optional[PackingOptions], *,
                      region: Union["InsertionRegion", str, int] = 0,
                      mass_rate: float = 1e-3, start: float = 0.0, end: float = float("inf"),
                      interval: float = 1e-3,
                      velocity: Sequence[float] = (0.0, 0.0, 0.0)) -> None:
        """Continuous insertion (sinter_stepper_set_insertion), a stage of each explicit step:
        at start + k interval [s] before end [s], spheres of the powder (packing_options:
        size distribution, material, temperature, seed, gap; its box is the region) are
        inserted at random places free of particles and walls until the mass inserted since
        start is within one sphere's mass of mass_rate [kg/s] times (k + 1) interval; they move
        at velocity [m/s]. region: "box" or "cylinder" (inscribed in the box along z,
        InsertionRegion). powder=None removes the insertion."""
        from .packing import InsertionRegion
        if powder is None:
            self._call(lib.sinter_stepper_set_insertion, self._ptr, None, None)
            return
        options = _CInsertionOptions()
        check(lib.sinter_insertion_options_init(ctypes.byref(options),
                                                ctypes.sizeof(_CInsertionOptions)),
              None, "sinter_insertion_options_init")
        if isinstance(region, str):
            region = InsertionRegion[region.upper()]
        options.region = int(region)
        options.mass_rate = float(mass_rate)
        options.start = float(start)
        options.end = float(end)
        options.interval = float(interval)
        v = [float(x) for x in velocity]
        if len(v) != 3:
            raise ValueError("set_insertion: velocity needs 3 components")
        options.velocity = (ctypes.c_double * 3)(*v)
        self._call(lib.sinter_stepper_set_insertion, self._ptr, ctypes.byref(powder),
                   ctypes.byref(options))

    def insertion(self) -> Tuple[float, float, int, int]:
        """What the insertion did so far (sinter_stepper_get_insertion): the mass inserted
        [kg], the target mass of the insertions made so far [kg], the spheres inserted, and
        the insertions that ended with a sphere finding no room."""
        done, target = ctypes.c_double(), ctypes.c_double()
        count, crowded = ctypes.c_uint64(), ctypes.c_uint64()
        self._call(lib.sinter_stepper_get_insertion, self._ptr, ctypes.byref(done),
                   ctypes.byref(target), ctypes.byref(count), ctypes.byref(crowded))
        return done.value, target.value, count.value, crowded.value

    def insertion_mixture(self) -> List[float]:
        """The mass inserted so far of each material of the insertion's mixture [kg], in the
        order of the powder's mixture_materials (sinter_stepper_get_insertion_mixture); empty
        without a mixture."""
        count = ctypes.c_size_t()
        self._call(lib.sinter_stepper_get_insertion_mixture, self._ptr, None, 0,
                   ctypes.byref(count))
        mass = (ctypes.c_double * max(1, count.value))()
        self._call(lib.sinter_stepper_get_insertion_mixture, self._ptr, mass, count.value, None)
        return [mass[k] for k in range(count.value)]

    def get_option(self, key: str) -> float:
        """Read an option of set_option."""
        value = ctypes.c_double()
        self._call(lib.sinter_stepper_get_option, self._ptr, key.encode("utf-8"),
                                                  ctypes.byref(value))
        return value.value

    @property
    def observer(self) -> Optional[Callable[["Stepper", float], Any]]:
        """observer(stepper, time) after every accepted step; a true result stops advance."""
        return self._state.observer

    @observer.setter
    def observer(self, function: Optional[Callable[["Stepper", float], Any]]) -> None:
        self.set_observer(function)

    def set_observer(self, function: Optional[Callable[["Stepper", float], Any]]) -> None:
        """observer(stepper, time [s]) after every accepted step; a true result stops the run
        (None removes it)."""
        if function is None:
            c_function = ObserverFn()
        else:
            this, keeper = weakref.ref(self), weakref.ref(self._keeper)

            def trampoline(handle, time, user):
                try:
                    stepper = this()
                    if stepper is None:  # a scene's stepper view was dropped: a new one
                        stepper = keeper().stepper
                    return 1 if function(stepper, time) else 0
                except BaseException as exception:
                    _callbacks.store(exception)
                    return 1  # stop; advance raises the exception

            c_function = ObserverFn(trampoline)
        self._call(lib.sinter_stepper_set_observer, self._ptr, c_function, None)
        self._state.observer, self._state.observer_function = function, c_function

    # --- running -----------------------------------------------------------

    def advance(self, t_end: float, progress: Progress = None) -> float:
        """Advance to t_end [s] (>= the current time; the last step lands on it); return
        the time reached.

        progress: a callable progress(time, t_end) [s] called as the run goes (at most ten
        times a second, and at the end), or True for a progress bar (tqdm when it is
        installed, else a line on stderr). An observer may stop earlier.

        Ctrl-C stops the run after its current step and raises KeyboardInterrupt within a
        fraction of a second; the particles then hold the last accepted state (readable,
        checkpointable, and a later advance continues from it). On an error they hold the
        last accepted state too. An exception raised by a Python callback (observer,
        progress, host submodel, wall motion) is raised here.
        """
        t_end = float(t_end)
        if progress is None or progress is False:
            self._guarded_run(lib.sinter_stepper_advance, t_end)
            return self.time
        report = _progress_function(progress, self.time, t_end)
        with self._reporting(report, t_end):
            self._guarded_run(lib.sinter_stepper_advance, t_end)
        report(self.time, t_end, final=True)
        return self.time

    def step(self, n: int = 1) -> float:
        """Take exactly n steps (fewer if the observer stops); return the time reached.

        Ctrl-C raises KeyboardInterrupt as in advance()."""
        if n < 0:
            raise ValueError("cannot take %d steps" % n)
        self._guarded_run(lib.sinter_stepper_step, int(n))
        return self.time

    def _guarded_run(self, c_function, *args):
        self._context._sync_log_level()
        return self._call(c_function, self._ptr, *args, interruptible=True)

    def _reporting(self, report, t_end):
        """A context manager: the C observer also calls report(time, t_end) during a run,
        then the stepper's own observer is put back."""
        stepper = self

        class _Reporting:
            def __enter__(self):
                user = stepper._state.observer
                this = weakref.ref(stepper)

                def trampoline(handle, time, _):
                    try:
                        report(time, t_end)
                        if user is not None:
                            return 1 if user(this(), time) else 0
                        return 0
                    except BaseException as exception:
                        _callbacks.store(exception)
                        return 1

                self.function = ObserverFn(trampoline)
                stepper._call(lib.sinter_stepper_set_observer, stepper._ptr, self.function,
                              None)
                return self

            def __exit__(self, *exc_info):
                previous = stepper._state.observer_function
                stepper._call(lib.sinter_stepper_set_observer, stepper._ptr,
                              previous if previous is not None else ObserverFn(), None)
                self.function = None

        return _Reporting()

    def evaluate(self) -> None:
        """Evaluate forces (and heat) on the current state without stepping."""
        self._guarded(lib.sinter_stepper_evaluate)

    @property
    def time(self) -> float:
        """Current simulated time [s]."""
        time = ctypes.c_double()
        self._call(lib.sinter_stepper_time, self._ptr, ctypes.byref(time))
        return time.value

    def sintering_stats(self) -> SinteringStats:
        """SinteringStats of a quasi-static stepper that has taken a step (links, necks [m],
        neck ratio, shrinkage along x, y, z, relative density, coordination).

        SinterError ERR_STATE for another kind or before the first step."""
        stats = _CSinteringStats()
        stats.struct_size = ctypes.sizeof(_CSinteringStats)
        self._call(lib.sinter_stepper_sintering_stats, self._ptr, ctypes.byref(stats))
        return SinteringStats(
            links=stats.links, neck_mean=stats.neck_mean, neck_min=stats.neck_min,
            neck_max=stats.neck_max, neck_ratio_mean=stats.neck_ratio_mean,
            shrinkage=tuple(stats.shrinkage), relative_density=stats.relative_density,
            coordination=stats.coordination, pcg_iterations=stats.pcg_iterations)

    @property
    def stats(self) -> StepperStats:
        """StepperStats (a frozen dataclass; .as_dict() for a dict)."""
        stats = _CStats()
        stats.struct_size = ctypes.sizeof(_CStats)
        self._call(lib.sinter_stepper_get_stats, self._ptr, ctypes.byref(stats))
        names = [field.name for field in dataclasses.fields(StepperStats)]
        return StepperStats(**{name: getattr(stats, name) for name in names
                               if hasattr(_CStats, name)})

    def snapshot(self) -> "Any":
        """The contacts (and quasi-static links) of the current state with their forces, heat
        flows and currents: a sinter.snapshot.Snapshot of copied arrays. Valid after a step or
        an advance until the particles are written, added, removed or sorted; otherwise a
        SinterError with status ERR_STATE (step(0) evaluates the state again)."""
        from . import snapshot
        return snapshot.take(self)

    def stable_dt_thermal(self) -> float:
        """Largest stable explicit thermal step in the current contact state [s] (inf if none)."""
        dt = ctypes.c_double()
        self._guarded(lib.sinter_stepper_stable_dt_thermal, ctypes.byref(dt))
        return dt.value

    def stable_step(self) -> float:
        """Stable step estimate of the explicit stepper [s] (issue 35; inf without a contact
        model): a fixed step above twice it is refused unless option "dt_check" is 0."""
        dt = ctypes.c_double()
        self._guarded(lib.sinter_stepper_stable_step, ctypes.byref(dt))
        return dt.value

    def stable_dt_hertz(self, v_rel: float = 1.0) -> float:
        """Stable explicit step [s] for Hertz contacts at relative speed v_rel [m/s] (eq. 47)."""
        return stable_dt_hertz(self.particles, self.walls, v_rel)

    def heat_energy(self, index: Optional[int] = None) -> Union[float, List[float]]:
        """Energy [J] put in by heat model `index` so far; all of them as a list if None."""
        if index is None:
            return [self.heat_energy(k) for k in range(len(self.heat_models))]
        energy = ctypes.c_double()
        self._call(lib.sinter_stepper_heat_energy, self._ptr, int(index), ctypes.byref(energy))
        return energy.value

    @property
    def electric_iterations(self) -> int:
        """Total iterations of the electric solves so far."""
        iterations = ctypes.c_uint64()
        self._call(lib.sinter_stepper_electric_iterations, self._ptr, ctypes.byref(iterations))
        return iterations.value

    def pour(self, ke_per_particle: float, t_min: float = 0.0, t_max: float = 1.0) -> float:
        """Advance until the kinetic energy per particle [J] falls below the threshold
        (after t_min [s]); NotConverged-style SinterError after t_max [s]."""
        self._guarded_run(lib.sinter_pack_pour, float(ke_per_particle), float(t_min),
                          float(t_max))
        return self.time

    # --- checkpoints -------------------------------------------------------

    def write_checkpoint(self, path: PathLike) -> None:
        """Write the complete state to a versioned, checksummed binary file (written to a
        temporary name and renamed: an existing checkpoint is never left half-written)."""
        self._call(lib.sinter_checkpoint_write, self._ptr, _path(path))

    def read_checkpoint(self, path: PathLike) -> None:
        """Restore the state from a checkpoint of a stepper with the same submodels and walls
        (FileNotFoundError when `path` does not exist; nothing changes on any error)."""
        status = lib.sinter_checkpoint_read(self._ptr, _path(path))
        check_path(status, self._context._handle, "sinter_checkpoint_read", path)

    # --- migration between steppers (subdomains) ---------------------------

    def export_particles(self, indices: Sequence[int], remove: bool = False) -> bytes:
        """The particles of the indices listed as a record stream, with everything the stepper
        keeps for them (fields, contact histories, quasi-static links, electric warm start);
        remove=True also takes them out of this stepper's set. See sinter_stepper_export."""
        index_list = [int(i) for i in indices]
        array = (ctypes.c_size_t * max(len(index_list), 1))(*index_list)
        size = ctypes.c_size_t(0)
        self._call(lib.sinter_stepper_export_size, self._ptr, len(index_list), array,
                   ctypes.byref(size))
        buffer = ctypes.create_string_buffer(max(size.value, 1))
        written = ctypes.c_size_t(0)
        self._call(lib.sinter_stepper_export, self._ptr, len(index_list), array, buffer,
                   size.value, ctypes.byref(written), 1 if remove else 0)
        return buffer.raw[:written.value]

    def remove_particles(self, indices: Sequence[int]) -> None:
        """Take the particles of the indices listed out of this stepper's set, as
        export_particles(indices, remove=True) does, without writing their records (for a
        host that exported them already, one stream per destination). See
        sinter_stepper_remove."""
        index_list = [int(i) for i in indices]
        array = (ctypes.c_size_t * max(len(index_list), 1))(*index_list)
        self._call(lib.sinter_stepper_remove, self._ptr, len(index_list), array)

    def import_particles(self, records: bytes) -> int:
        """Append the particles of a record stream of export_particles as owned particles;
        returns how many. A damaged or foreign stream is refused and nothing changes."""
        data = bytes(records)
        buffer = ctypes.create_string_buffer(data, max(len(data), 1))
        count = ctypes.c_size_t(0)
        self._call(lib.sinter_stepper_import, self._ptr, buffer, len(data), ctypes.byref(count))
        return count.value

    def save_global(self) -> bytes:
        """The stepper's global part (time, step, counters, walls, step control): with the
        records of every particle (export_particles), a portable checkpoint."""
        size = ctypes.c_size_t(0)
        self._call(lib.sinter_stepper_save_global, self._ptr, None, 0, ctypes.byref(size))
        buffer = ctypes.create_string_buffer(max(size.value, 1))
        self._call(lib.sinter_stepper_save_global, self._ptr, buffer, size.value,
                   ctypes.byref(size))
        return buffer.raw[:size.value]

    def load_global(self, part: bytes) -> None:
        """Load a global part of save_global into this stepper, set up alike and without
        particles; then import the particles' records (import_particles)."""
        data = bytes(part)
        buffer = ctypes.create_string_buffer(data, max(len(data), 1))
        self._call(lib.sinter_stepper_load_global, self._ptr, buffer, len(data))

    def __repr__(self) -> str:
        if self.closed:
            return "<sinter.Stepper closed>"
        return "<sinter.Stepper t=%g s, %d force, %d heat model(s)>" % (
            self.time, len(self.forces), len(self.heat_models))


def stable_dt_hertz(particles: "Particles", walls: Optional["Walls"] = None,
                    v_rel: float = 1.0) -> float:
    """Stable explicit step [s] for Hertz contacts (seed 003 eq. 47) at relative speed v_rel."""
    dt = ctypes.c_double()
    particles._check(lib.sinter_stable_dt_hertz(particles._ptr,
                                                walls._ptr if walls is not None else None,
                                                float(v_rel), ctypes.byref(dt)),
                     "sinter_stable_dt_hertz")
    return dt.value


def damping_ratio_from_restitution(e: float) -> float:
    """Damping ratio xi of seed 003 eq. 6 giving restitution e (0 < e <= 1) in a Hertz collision."""
    xi = ctypes.c_double()
    check(lib.sinter_damping_ratio_from_restitution(float(e), ctypes.byref(xi)), None,
          "sinter_damping_ratio_from_restitution")
    return xi.value


# --- progress reports ---------------------------------------------------------------------

#: Least wall-clock time [s] between two progress reports.
PROGRESS_INTERVAL = 0.1


def _progress_function(progress, t_start, t_end):
    """report(time, t_end, final=False): `progress` (a callable, or True for a bar)
    throttled to one call per PROGRESS_INTERVAL, the final one always made."""
    if progress is True:
        show = _progress_bar(t_start, t_end)
    elif callable(progress):
        show = progress
    else:
        raise TypeError("progress must be None, True or a callable(time, t_end), not %r"
                        % (progress,))
    last = [float("-inf")]

    def report(time, t_end, final=False):
        now = _time.monotonic()
        if final or now - last[0] >= PROGRESS_INTERVAL:
            last[0] = now
            show(time, t_end)

    return report


def _progress_bar(t_start, t_end):
    """show(time, t_end): a tqdm bar when tqdm is importable, else a line on stderr."""
    span = max(t_end - t_start, 0.0)
    try:
        import tqdm  # type: ignore[import-not-found]
    except ImportError:
        tqdm = None
    if tqdm is not None:
        bar = tqdm.tqdm(total=span, unit="s", desc="sinter", leave=True)
        done = [0.0]

        def show(time, t_end):
            position = min(max(time - t_start, 0.0), span)
            bar.update(position - done[0])
            done[0] = position
            if time >= t_end:
                bar.close()

        return show

    def line(time, t_end):
        fraction = 1.0 if span <= 0.0 else min(max((time - t_start) / span, 0.0), 1.0)
        sys.stderr.write("\rsinter: t = %.6g s of %.6g s (%3.0f %%)" % (time, t_end,
                                                                        100.0 * fraction))
        if time >= t_end:
            sys.stderr.write("\n")
        sys.stderr.flush()

    return line
