"""Submodels: force, heat and electric models, built in (by name) or from Python callbacks.

Built-in models take their parameters as keyword arguments and by item access:

    gravity = sinter.ForceModel(ctx, "gravity", gz=-9.81)
    gravity["gx"] = 1.0
    conduction = sinter.HeatModel(ctx, "conduction", area=0)
    laser = sinter.HeatModel(ctx, "laser", intensity=1e9)
    laser.set_schedule("x", [0.0, 1.0], [0.0, 0.01])

Host models run Python functions once per evaluation over whole batches
(see ForceModel.from_callbacks and HeatModel.from_callback).
"""

import ctypes
import itertools
from typing import Any, Callable, Dict, Mapping, Optional, Sequence, Tuple

from . import _callbacks
from ._callbacks import ContactBatch, StateView
from ._errors import NotFound, check
from ._integers import to_c
from ._lib import (BodyFn, ConductanceFn, ContactsFn, ElectricCallbacks, ElectricModelPtr,
                   ForceCallbacks, ForceModelPtr, HeatCallbacks, HeatModelPtr, JouleSplitFn,
                   PowerFn, lib, text)
from .context import Context, _Handle


def _doubles(values):
    """A ctypes double array of a sequence (or NumPy array) of numbers."""
    values = [float(v) for v in values]
    return (ctypes.c_double * max(len(values), 1))(*values), len(values)


class _KeyedModel(_Handle):
    """A submodel with a name and parameters by key (model-level, SI units)."""

    _ptr_type = None
    # The C functions of the kind, by role: {"create": "sinter_force_model_create", ...}
    _functions: Dict[str, str] = {}

    def __init__(self, context: Context, name: str, **params: float) -> None:
        """Create the built-in model `name` (NotFound lists the known ones) and set its
        parameters, SI units (an unknown key raises NotFound listing the model's keys).

        The parameters are keywords of the model, not of this class: which keys exist depends
        on `name` (sinter.h lists them), hence **params here."""
        handle = self._ptr_type()
        create = getattr(lib, self._functions["create"])
        check(create(ctypes.byref(handle), context._ptr, name.encode("utf-8")),
              context._handle, create.__name__)
        super().__init__(context, handle)
        try:
            self.update(params)
        except BaseException:
            self.close()
            raise

    @property
    def _destroy_function(self):
        return self._functions["destroy"]

    @property
    def name(self) -> str:
        """The model's name ("gravity", or a host model's)."""
        return text(getattr(lib, self._functions["name"])(self._ptr))

    def __getitem__(self, key: str) -> float:
        value = ctypes.c_double()
        function = getattr(lib, self._functions["get"])
        self._check(function(self._ptr, key.encode("utf-8"), ctypes.byref(value)),
                    function.__name__)
        return value.value

    def __setitem__(self, key: str, value: float) -> None:
        function = getattr(lib, self._functions["set"])
        self._check(function(self._ptr, key.encode("utf-8"), float(value)), function.__name__)

    def get(self, key: str, default: Optional[float] = None) -> Optional[float]:
        """The parameter's value, or `default` for a key the model does not have."""
        try:
            return self[key]
        except NotFound:
            return default

    def update(self, params: Optional[Mapping[str, float]] = None, **more: float) -> None:
        """Set several parameters from a mapping {key: value} and/or keywords."""
        for key, value in itertools.chain(dict(params or {}).items(), more.items()):
            self[key] = value

    def __repr__(self) -> str:
        return "<sinter.%s %s>" % (type(self).__name__,
                                   "closed" if self.closed else repr(self.name))


class ForceModel(_KeyedModel):
    """A force/moment submodel (sinter_force_model).

    Built in, by name: "hertz_mindlin", "power_law", "linear_spring" (kn,
    cn), "drag", "gravity" (gx, gy, gz), "body_force" (fx, fy, fz); see sinter.h.
    """

    _ptr_type = ForceModelPtr
    _functions = {"create": "sinter_force_model_create", "destroy": "sinter_force_model_destroy",
                  "name": "sinter_force_model_name", "get": "sinter_force_model_get",
                  "set": "sinter_force_model_set"}

    @classmethod
    def from_callbacks(cls, context: Context, name: str,
                       contacts: Optional[Callable[[StateView, ContactBatch], Any]] = None,
                       particles: Optional[Callable[[StateView, Any, Any], Any]] = None,
                       history_size: int = 0) -> "ForceModel":
        """A host force model running Python functions on whole batches.

        contacts(state, batch) is called once per evaluation for the
        particle-particle batch and once for the particle-wall batch (only
        when it has contacts); it writes batch.force (force on i; j receives
        the opposite), batch.torque_i, batch.torque_j and batch.history_trial
        in place. particles(state, force, torque) adds body forces: force and
        torque are (count, 3) arrays, zeroed before the call.

        `state` is a StateView, `batch` a ContactBatch: NumPy arrays over the
        library's memory (memoryviews without NumPy), valid during the call
        only. Return None or 0 for success, a positive number to ask for a
        retry, a negative one to fail; an exception stops the stepper at its
        last accepted state and is raised again by Stepper.advance/step.
        history_size: doubles of per-contact history (batch.history).
        """
        if contacts is None and particles is None:
            raise ValueError("give a contacts and/or a particles function")
        functions = []
        table = ForceCallbacks()
        table.struct_size = ctypes.sizeof(ForceCallbacks)
        table.history_size = to_c(int(history_size), ctypes.c_size_t, "history_size")
        if contacts is not None:
            functions.append(_contacts_trampoline(contacts))
            table.contacts = functions[-1]
        if particles is not None:
            functions.append(_body_trampoline(particles))
            table.particles = functions[-1]
        handle = ForceModelPtr()
        check(lib.sinter_force_model_create_host(ctypes.byref(handle), context._ptr,
                                                 name.encode("utf-8"), ctypes.byref(table), None),
              context._handle, "sinter_force_model_create_host")
        model = cls.__new__(cls)
        _Handle.__init__(model, context, handle)
        model._c_functions = functions  # the library holds these pointers until destroy
        model.callbacks = {"contacts": contacts, "particles": particles}
        return model

    def _forget(self):
        self.__dict__.pop("_c_functions", None)


class HeatModel(_KeyedModel):
    """A heat-power submodel (sinter_heat_model).

    Built in, by name: "conduction", "convection", "radiation", "nozzle",
    "laser", "joule", "beam"; see sinter.h for their parameters.
    """

    _ptr_type = HeatModelPtr
    _functions = {"create": "sinter_heat_model_create", "destroy": "sinter_heat_model_destroy",
                  "name": "sinter_heat_model_name", "get": "sinter_heat_model_get",
                  "set": "sinter_heat_model_set"}

    def set_schedule(self, key: str, times: Sequence[float], values: Sequence[float]) -> None:
        """Make parameter `key` follow a piecewise-linear schedule (times [s], increasing)."""
        c_times, n = _doubles(times)
        c_values, n_values = _doubles(values)
        if n != n_values:
            raise ValueError("%d times but %d values" % (n, n_values))
        self._check(lib.sinter_heat_model_set_schedule(self._ptr, key.encode("utf-8"), n,
                                                       c_times, c_values),
                    "sinter_heat_model_set_schedule")

    def set_scan_path(self, vertices: Sequence[Sequence[float]], start_time: float = 0.0) -> None:
        """Move the beam along a scan path (sinter_heat_model_set_scan_path).

        vertices: (x [m], y [m], speed [m/s], level [0..1]) each; the first is the start point,
        each later one a straight segment from the previous at its speed, the power times its
        level (0: off, a jump). An empty sequence removes the path.
        """
        flat = [float(value) for vertex in vertices for value in vertex]
        if len(flat) % 4:
            raise ValueError("scan path vertices need 4 values each (x, y, speed, level)")
        c_points, n = _doubles(flat)
        self._check(lib.sinter_heat_model_set_scan_path(self._ptr, n // 4, c_points,
                                                        float(start_time)),
                    "sinter_heat_model_set_scan_path")

    def scan_end(self) -> float:
        """The time [s] at which the scan path ends (NotFound without one)."""
        value = ctypes.c_double()
        self._check(lib.sinter_heat_model_scan_end(self._ptr, ctypes.byref(value)),
                    "sinter_heat_model_scan_end")
        return value.value

    @staticmethod
    def hatch(context: Context, lo: Sequence[float], hi: Sequence[float], spacing: float,
              speed: float, angle: float = 0.0, jump_speed: Optional[float] = None,
              serpentine: bool = True) -> list:
        """The vertices of a hatch filling the rectangle lo..hi (x, y [m]) for set_scan_path:
        lines `spacing` [m] apart along `angle` [rad] at `speed` [m/s], jumps at `jump_speed`
        (default: speed) with the power off (sinter_scan_hatch)."""
        c_lo, _ = _doubles([float(lo[0]), float(lo[1])])
        c_hi, _ = _doubles([float(hi[0]), float(hi[1])])
        jump = float(speed if jump_speed is None else jump_speed)
        count = ctypes.c_size_t()
        args = (float(spacing), float(angle), float(speed), jump, 1 if serpentine else 0)
        check(lib.sinter_scan_hatch(context._ptr, c_lo, c_hi, *args, None, 0,
                                    ctypes.byref(count)),
              context._handle, "sinter_scan_hatch")
        points = (ctypes.c_double * (4 * max(count.value, 1)))()
        check(lib.sinter_scan_hatch(context._ptr, c_lo, c_hi, *args, points, count.value,
                                    ctypes.byref(count)),
              context._handle, "sinter_scan_hatch")
        return [tuple(points[4 * k:4 * k + 4]) for k in range(count.value)]

    def output(self, name: str) -> float:
        """An output of the last evaluation ("beam": "absorbed", "transmitted" [W], "lit",
        "lit_temperature" [K])."""
        value = ctypes.c_double()
        self._check(lib.sinter_heat_model_output(self._ptr, name.encode("utf-8"),
                                                 ctypes.byref(value)),
                    "sinter_heat_model_output")
        return value.value

    @classmethod
    def from_callback(cls, context: Context, name: str,
                      power: Callable[[StateView, ContactBatch, ContactBatch, Any], Any]
                      ) -> "HeatModel":
        """A host heat model: power(state, particle_contacts, wall_contacts, heat).

        heat is a (count,) array [W], zeroed before the call, that the
        function fills in place; the two ContactBatch arguments give the
        contact geometry (their force/torque/history attributes are None).
        Same conventions as ForceModel.from_callbacks.
        """
        table = HeatCallbacks()
        table.struct_size = ctypes.sizeof(HeatCallbacks)
        function = _power_trampoline(power)
        table.power = function
        handle = HeatModelPtr()
        check(lib.sinter_heat_model_create_host(ctypes.byref(handle), context._ptr,
                                                name.encode("utf-8"), ctypes.byref(table), None),
              context._handle, "sinter_heat_model_create_host")
        model = cls.__new__(cls)
        _Handle.__init__(model, context, handle)
        model._c_functions = [function]
        model.callbacks = {"power": power}
        return model

    def _forget(self):
        self.__dict__.pop("_c_functions", None)


class ElectricModel(_KeyedModel):
    """An electric submodel (sinter_electric_model): "averaged" or "network".

    Parameters: "tolerance", "max_iterations"; the network model also "sigmoid",
    "theta_ref", "k1", "gamma1" (its conductances follow seed 000 eq. 50's temperature
    term). Wall boundary data are set with Walls.set_electric.
    """

    _ptr_type = ElectricModelPtr
    _functions = {"create": "sinter_electric_model_create",
                  "destroy": "sinter_electric_model_destroy",
                  "name": "sinter_electric_model_name", "get": "sinter_electric_model_get",
                  "set": "sinter_electric_model_set"}

    def power(self) -> Tuple[float, float]:
        """(supplied, dissipated) [W] of the network model's last solve: the walls' electrical
        power and the contacts' Joule power, equal to the solve's accuracy."""
        supplied, dissipated = ctypes.c_double(), ctypes.c_double()
        self._check(lib.sinter_electric_model_power(self._ptr, ctypes.byref(supplied),
                                                    ctypes.byref(dissipated)),
                    "sinter_electric_model_power")
        return supplied.value, dissipated.value

    def electrode_heat(self) -> float:
        """The Joule heat [W] of the network model's last solve that a host split gave to the
        electrodes (0 with the built-in split): the particles receive the dissipated power
        less this."""
        heat = ctypes.c_double()
        self._check(lib.sinter_electric_model_electrode_heat(self._ptr, ctypes.byref(heat)),
                    "sinter_electric_model_electrode_heat")
        return heat.value

    def set_host(self,
                 conductance: Optional[Callable[[StateView, ContactBatch, Any, Any], Any]] = None,
                 joule_split: Optional[Callable[[StateView, ContactBatch, Any, Any], Any]] = None
                 ) -> None:
        """Give the network model a host conductance law and/or Joule split (both None: back
        to the built-in ones).

        conductance(state, batch, sigma, g): fill g (count,) [S], zeroed, one per contact of
        the batch (particle pairs, then wall contacts in a second call); sigma (state.count,)
        holds the particles' conductivities [S/m] after eq. 50's term. 0 insulates.
        joule_split(state, batch, power, share): fill share (count,), in [0, 1] and preset to
        the built-in 1/2 (pairs) or 1 (walls), the fraction of each contact's Joule power
        power [W] that heats particle i; the rest heats j or the electrode.
        Same conventions as ForceModel.from_callbacks (return None or a CallbackResult).
        """
        functions = []
        table = None
        if conductance is not None or joule_split is not None:
            table = ElectricCallbacks()
            table.struct_size = ctypes.sizeof(ElectricCallbacks)
            if conductance is not None:
                table.conductance = _electric_trampoline(conductance, ConductanceFn, True)
                functions.append(table.conductance)
            if joule_split is not None:
                table.joule_split = _electric_trampoline(joule_split, JouleSplitFn, False)
                functions.append(table.joule_split)
        self._check(lib.sinter_electric_model_set_host(
            self._ptr, ctypes.byref(table) if table is not None else None, None),
            "sinter_electric_model_set_host")
        self._c_functions = functions
        self.callbacks = {"conductance": conductance, "joule_split": joule_split}

    def _forget(self):
        self.__dict__.pop("_c_functions", None)


# --- trampolines -----------------------------------------------------------

def _contacts_trampoline(function):
    def trampoline(state_pointer, batch_pointer, user):
        try:
            state = StateView(state_pointer.contents)
            batch = ContactBatch(batch_pointer.contents)
            try:
                return _callbacks.result_code(function(state, batch))
            finally:
                state.invalidate()
                batch.invalidate()
        except BaseException as exception:  # never unwind through C
            _callbacks.store(exception)
            return -1

    return ContactsFn(trampoline)


def _body_trampoline(function):
    def trampoline(state_pointer, force, torque, user):
        try:
            state = StateView(state_pointer.contents)
            n = state_pointer.contents.count
            force_array = _callbacks.array(force, (n, 3), "d", True)
            torque_array = _callbacks.array(torque, (n, 3), "d", True)
            try:
                return _callbacks.result_code(function(state, force_array, torque_array))
            finally:
                state.invalidate()
                _release(force_array, torque_array)
        except BaseException as exception:
            _callbacks.store(exception)
            return -1

    return BodyFn(trampoline)


def _power_trampoline(function):
    def trampoline(state_pointer, pp_pointer, pw_pointer, heat, user):
        try:
            state = StateView(state_pointer.contents)
            pp = ContactBatch(pp_pointer.contents)
            pw = ContactBatch(pw_pointer.contents)
            heat_array = _callbacks.array(heat, (state_pointer.contents.count,), "d", True)
            try:
                return _callbacks.result_code(function(state, pp, pw, heat_array))
            finally:
                state.invalidate()
                pp.invalidate()
                pw.invalidate()
                _release(heat_array)
        except BaseException as exception:
            _callbacks.store(exception)
            return -1

    return PowerFn(trampoline)


def _electric_trampoline(function, c_type, per_particle_input):
    # the input array is per particle (conductivities) or per contact (powers); the output is
    # per contact
    def trampoline(state_pointer, batch_pointer, values, out, user):
        try:
            state = StateView(state_pointer.contents)
            batch = ContactBatch(batch_pointer.contents)
            count = batch_pointer.contents.count
            rows = state_pointer.contents.count if per_particle_input else count
            input_array = _callbacks.array(values, (rows,), "d", False)
            output_array = _callbacks.array(out, (count,), "d", True)
            try:
                return _callbacks.result_code(function(state, batch, input_array, output_array))
            finally:
                state.invalidate()
                batch.invalidate()
                _release(input_array, output_array)
        except BaseException as exception:
            _callbacks.store(exception)
            return -1

    return c_type(trampoline)


def _release(*arrays):
    for array in arrays:
        if isinstance(array, memoryview):
            try:
                array.release()
            except BufferError:
                pass


__all__ = ["ContactBatch", "ElectricModel", "ForceModel", "HeatModel", "StateView"]
