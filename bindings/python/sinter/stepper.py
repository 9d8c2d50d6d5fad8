"""Steppers: time integration over a particle set, walls and submodels; checkpoints."""

import ctypes
import dataclasses
import enum
import os
import weakref

from . import _callbacks
from ._errors import check
from ._lib import ObserverFn, SinteringStats as _CSintering, StepperPtr, StepperStats as _CStats, lib
from .context import _Handle


class StepperKind(enum.IntEnum):
    """sinter_stepper_kind."""

    EXPLICIT = 0  #: velocity Verlet, fixed step (seed 003 sec. 4)
    STAGGERED = 1  #: implicit staggered, adaptive step (seed 000 sec. 3, 6); see set_option
    QUASISTATIC = 2  #: bonded links driven by 7DOF necks (seed 001 sec. 3.3); sintering_stats


class ThermalScheme(enum.IntEnum):
    """sinter_thermal_scheme."""

    EXPLICIT = 0
    IMPLICIT = 1


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

    def as_dict(self):
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

    def __init__(self, context, particles, walls=None, kind="explicit", dt=None, skin=None,
                 domain=None, thermal=None, forces=(), heat=(), electric=None, observer=None,
                 options=None):
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
    def kind(self):
        """StepperKind of a stepper made here (None for a scene's)."""
        return self._state.kind

    @property
    def forces(self):
        """The ForceModels added from Python (a scene's own models are not listed)."""
        return list(self._state.forces)

    @property
    def heat_models(self):
        """The HeatModels added from Python, in order (the index of heat_energy)."""
        return list(self._state.heat_models)

    def _guarded(self, c_function, *args):
        return self._call(c_function, self._ptr, *args)

    # --- submodels ---------------------------------------------------------

    def add_force(self, model):
        """Add a ForceModel (the stepper keeps it alive; it may be shared)."""
        self._call(lib.sinter_stepper_add_force, self._ptr, model._ptr)
        self._keeper._borrow(model)
        self._state.forces.append(model)
        return model

    def add_heat(self, model):
        """Add a HeatModel; a stepper without one does no thermal work."""
        self._call(lib.sinter_stepper_add_heat, self._ptr, model._ptr)
        self._keeper._borrow(model)
        self._state.heat_models.append(model)
        return model

    @property
    def electric(self):
        """The ElectricModel solved on every evaluation (None: none)."""
        return self._state.electric

    @electric.setter
    def electric(self, model):
        self.set_electric(model)

    def set_electric(self, model):
        self._call(lib.sinter_stepper_set_electric, self._ptr,
                                                    model._ptr if model is not None else None)
        previous, self._state.electric = self._state.electric, model
        if model is not None:
            self._keeper._borrow(model)
        if previous is not None:
            self._keeper._unborrow(previous)

    # --- settings ----------------------------------------------------------

    @property
    def dt(self):
        """Time step [s]."""
        return self.stats.dt

    @dt.setter
    def dt(self, dt):
        self._call(lib.sinter_stepper_set_dt, self._ptr, float(dt))

    @property
    def skin(self):
        """Verlet skin [m] as last set here (None: the library's automatic choice, or the
        scene's)."""
        return self._state.skin

    @skin.setter
    def skin(self, skin):
        self._call(lib.sinter_stepper_set_skin, self._ptr, float(skin))
        self._state.skin = float(skin)

    @property
    def domain(self):
        """(lo, hi) corners [m] of the simulation domain as last set here (None: no domain)."""
        return self._state.domain

    @domain.setter
    def domain(self, corners):
        lo, hi = corners
        lo, hi = [float(x) for x in lo], [float(x) for x in hi]
        if len(lo) != 3 or len(hi) != 3:
            raise ValueError("a domain is two corners of 3 coordinates each")
        self._call(lib.sinter_stepper_set_domain, self._ptr, (ctypes.c_double * 3)(*lo),
                                                  (ctypes.c_double * 3)(*hi))
        self._state.domain = (tuple(lo), tuple(hi))

    @property
    def thermal_scheme(self):
        """ThermalScheme.EXPLICIT or IMPLICIT (set with the enum, its value or "implicit").

        None for a scene's stepper until set here."""
        return self._state.thermal

    @thermal_scheme.setter
    def thermal_scheme(self, scheme):
        scheme = _enum(ThermalScheme, scheme)
        self._call(lib.sinter_stepper_set_thermal_scheme, self._ptr, int(scheme))
        self._state.thermal = scheme

    def set_option(self, key, value):
        """Set an option of the staggered stepper ("phi", "tolerance", "dt_max", ...; sinter.h)."""
        self._call(lib.sinter_stepper_set_option, self._ptr, key.encode("utf-8"), float(value))

    def set_furnace(self, times, temperatures):
        """Every particle's temperature follows T(t) through the points (times [s], K).

        The quasi-static stepper integrates the necks along it; an empty schedule removes it.
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

    def get_option(self, key):
        value = ctypes.c_double()
        self._call(lib.sinter_stepper_get_option, self._ptr, key.encode("utf-8"),
                                                  ctypes.byref(value))
        return value.value

    @property
    def observer(self):
        """observer(stepper, time) after every accepted step; a true result stops advance."""
        return self._state.observer

    @observer.setter
    def observer(self, function):
        self.set_observer(function)

    def set_observer(self, function):
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

    def advance(self, t_end):
        """Advance to t_end [s] (the last step lands on it); return the time reached.

        An observer may stop earlier. On an error the particles hold the last
        accepted state.
        """
        self._guarded(lib.sinter_stepper_advance, float(t_end))
        return self.time

    def step(self, n=1):
        """Take exactly n steps (fewer if the observer stops); return the time reached."""
        if n < 0:
            raise ValueError("cannot take %d steps" % n)
        self._guarded(lib.sinter_stepper_step, int(n))
        return self.time

    def evaluate(self):
        """Evaluate forces (and heat) on the current state without stepping."""
        self._guarded(lib.sinter_stepper_evaluate)

    @property
    def time(self):
        """Current simulated time [s]."""
        time = ctypes.c_double()
        self._call(lib.sinter_stepper_time, self._ptr, ctypes.byref(time))
        return time.value

    @property
    def stats(self):
        """StepperStats (a frozen dataclass; .as_dict() for a dict)."""
        stats = _CStats()
        stats.struct_size = ctypes.sizeof(_CStats)
        self._call(lib.sinter_stepper_get_stats, self._ptr, ctypes.byref(stats))
        names = [field.name for field in dataclasses.fields(StepperStats)]
        return StepperStats(**{name: getattr(stats, name) for name in names
                               if hasattr(_CStats, name)})

    def sintering_stats(self):
        """The quasi-static stepper's statistics (sinter_stepper_sintering_stats) as a dict:
        links, neck_mean/min/max [m], neck_ratio_mean, shrinkage (3), relative_density,
        coordination, pcg_iterations."""
        stats = _CSintering()
        stats.struct_size = ctypes.sizeof(_CSintering)
        self._guarded(lib.sinter_stepper_sintering_stats, ctypes.byref(stats))
        out = {name: getattr(stats, name) for name, _ in _CSintering._fields_
               if name != "struct_size"}
        out["shrinkage"] = list(stats.shrinkage)
        return out

    def snapshot(self):
        """The contacts (and quasi-static links) of the current state with their forces, heat
        flows and currents: a sinter.snapshot.Snapshot of copied arrays. Valid after a step or
        an advance until the particles are written, added, removed or sorted; otherwise a
        SinterError with status ERR_STATE (step(0) evaluates the state again)."""
        from . import snapshot
        return snapshot.take(self)

    def stable_dt_thermal(self):
        """Largest stable explicit thermal step in the current contact state [s] (inf if none)."""
        dt = ctypes.c_double()
        self._guarded(lib.sinter_stepper_stable_dt_thermal, ctypes.byref(dt))
        return dt.value

    def stable_dt_hertz(self, v_rel=1.0):
        """Stable explicit step [s] for Hertz contacts at relative speed v_rel [m/s] (eq. 47)."""
        return stable_dt_hertz(self.particles, self.walls, v_rel)

    def heat_energy(self, index=None):
        """Energy [J] put in by heat model `index` so far; all of them as a list if None."""
        if index is None:
            return [self.heat_energy(k) for k in range(len(self.heat_models))]
        energy = ctypes.c_double()
        self._call(lib.sinter_stepper_heat_energy, self._ptr, int(index), ctypes.byref(energy))
        return energy.value

    @property
    def electric_iterations(self):
        """Total iterations of the electric solves so far."""
        iterations = ctypes.c_uint64()
        self._call(lib.sinter_stepper_electric_iterations, self._ptr, ctypes.byref(iterations))
        return iterations.value

    def pour(self, ke_per_particle, t_min=0.0, t_max=1.0):
        """Advance until the kinetic energy per particle [J] falls below the threshold
        (after t_min [s]); NotConverged-style SinterError after t_max [s]."""
        self._guarded(lib.sinter_pack_pour, float(ke_per_particle), float(t_min), float(t_max))
        return self.time

    # --- checkpoints -------------------------------------------------------

    def write_checkpoint(self, path):
        """Write the complete state to a versioned, checksummed binary file."""
        self._call(lib.sinter_checkpoint_write, self._ptr, _path(path))

    def read_checkpoint(self, path):
        """Restore the state from a checkpoint of a stepper with the same submodels and walls."""
        self._call(lib.sinter_checkpoint_read, self._ptr, _path(path))

    def __repr__(self):
        if self.closed:
            return "<sinter.Stepper closed>"
        return "<sinter.Stepper t=%g s, %d force, %d heat model(s)>" % (
            self.time, len(self.forces), len(self.heat_models))


def stable_dt_hertz(particles, walls=None, v_rel=1.0):
    """Stable explicit step [s] for Hertz contacts (seed 003 eq. 47) at relative speed v_rel."""
    dt = ctypes.c_double()
    particles._check(lib.sinter_stable_dt_hertz(particles._ptr,
                                                walls._ptr if walls is not None else None,
                                                float(v_rel), ctypes.byref(dt)),
                     "sinter_stable_dt_hertz")
    return dt.value


def damping_ratio_from_restitution(e):
    """Damping ratio xi of seed 003 eq. 6 giving restitution e (0 < e <= 1) in a Hertz collision."""
    xi = ctypes.c_double()
    check(lib.sinter_damping_ratio_from_restitution(float(e), ctypes.byref(xi)), None,
          "sinter_damping_ratio_from_restitution")
    return xi.value
