"""The 7DOF two-particle neck model (seed 001 sec. 2.2, docs/7dof.md)."""

import ctypes
import dataclasses
import numbers
import os
from typing import Any, Dict, Mapping, Optional, Sequence, Tuple, Union

from ._errors import SinterError, check
from ._lib import NeckModelPtr, NeckStats as _CNeckStats, lib
from .context import Context, _Handle
from .material import Material, MaterialParam, _param_id
from . import particles as _particles


@dataclasses.dataclass(frozen=True)
class NeckStats:
    """Work of the last two_particles call (sinter_neck_stats); seconds in s."""

    steps: int
    rhs_evaluations: int
    jacobian_evaluations: int
    error_test_failures: int
    nonlinear_iterations: int
    nonlinear_failures: int
    segments: int
    seconds: float

    def as_dict(self) -> Dict[str, Any]:
        return dataclasses.asdict(self)


@dataclasses.dataclass
class NeckResult:
    """Outputs of NeckModel.two_particles at the requested times (NumPy arrays, or lists).

    time [s]; neck_radius x [m]; shrinkage Delta L / L0 [-]; state (n, 7)
    lengths y1..y7 [m] or None; radius = min(R_A, R_B) [m]. NaN marks times a
    failed run did not reach.
    """

    time: object
    neck_radius: object
    shrinkage: object
    state: object
    radius: float

    @property
    def neck_ratio(self) -> Any:
        """x / min(R_A, R_B) [-]."""
        if hasattr(self.neck_radius, "dtype"):
            return self.neck_radius / self.radius
        return [x / self.radius for x in self.neck_radius]


@dataclasses.dataclass
class NeckSensitivities:
    """Outputs of NeckModel.sensitivities at the requested times (NumPy arrays, or lists).

    time [s]; neck_ratio x / min(R_A, R_B) [-]; shrinkage Delta L / L0 [-];
    d_neck_ratio and d_shrinkage (n_out, n_params): derivatives with respect to ln D0 [-] for a
    diffusion prefactor key, Q [J/mol] for an activation energy key, ln of the value [-] for a
    path constant (neck_*_path, lattice_mobile_fraction); params: the keys.
    """

    time: object
    neck_ratio: object
    shrinkage: object
    d_neck_ratio: object
    d_shrinkage: object
    params: Tuple[str, ...]


def _as_list(values):
    if isinstance(values, numbers.Real):
        return [float(values)]
    return [float(v) for v in values]


def _out(values, shape):
    numpy = _particles.numpy if _particles.USE_NUMPY else None
    if numpy is not None:
        return numpy.array(values[:], dtype=float).reshape(shape)
    flat = list(values)
    if len(shape) == 1:
        return flat
    return [flat[k * shape[1]:(k + 1) * shape[1]] for k in range(shape[0])]


class NeckModel(_Handle):
    """Options of the 7DOF neck model by key: NeckModel(ctx, rtol=1e-8)["epsilon"].

    Keys (sinter.h): epsilon, h0_ratio, rtol, atol, initial_step, max_steps,
    integrator (0 CVODE, 1 RK4), rk4_steps, rk4_time_scale, ...
    """

    _destroy_function = "sinter_neck_model_destroy"

    #: The options of the neck model (sinter_neck_model_set), in the library's order.
    OPTIONS = ("epsilon", "h0_ratio", "rtol", "atol", "initial_step", "max_steps", "integrator",
               "rk4_steps", "rk4_time_scale", "error_scale")

    def __init__(self, context: Context, options: Optional[Mapping[str, float]] = None, *,
                 epsilon: Optional[float] = None,
                 h0_ratio: Optional[float] = None,
                 rtol: Optional[float] = None,
                 atol: Optional[float] = None,
                 initial_step: Optional[float] = None,
                 max_steps: Optional[float] = None,
                 integrator: Optional[float] = None,
                 rk4_steps: Optional[float] = None,
                 rk4_time_scale: Optional[float] = None,
                 error_scale: Optional[float] = None) -> None:
        """A neck model with the library's default options, then `options` (a mapping) and
        the keywords given (None: the default):

        epsilon: seeded neck radius x0 / min(R_A, R_B) [-]; 0.01, (0, 0.1]
        h0_ratio: junction radius of the seeded neck h0 / x0 [-]; 1.5, (1, 2)
        rtol: relative tolerance of every state component [-]; 1e-8, [1e-14, 1e-2]
        atol: absolute tolerance of the state lengths [m]; 0 = 1e-14 min(R_A, R_B); [0, 1]
        initial_step: first step [s]; 1e-12, 0 lets CVODE estimate; [0, 1e6]
        max_steps: most accepted steps of one run; 1e6, [1, 1e12], whole number
        integrator: 0 = CVODE BDF (default); 1 = the seed's classical RK4 on a fixed grid
        rk4_steps: number of RK4 steps of a run; 20000, [1, 1e10], whole number
        rk4_time_scale: tau [s] of the RK4 grid, uniform in ln(1 + (t - t0)/tau); 1e-6, (0, 1e6]
        error_scale: what rtol is relative to: 1 (default) the geometry, 0 each component
        """
        handle = NeckModelPtr()
        check(lib.sinter_neck_model_create(ctypes.byref(handle), context._ptr), context._handle,
              "sinter_neck_model_create")
        super().__init__(context, handle)
        given = {key: value for key, value in locals().items()
                 if key in NeckModel.OPTIONS and value is not None}
        try:
            self.update(options)
            self.update(given)
        except BaseException:
            self.close()
            raise

    def __getitem__(self, key: str) -> float:
        value = ctypes.c_double()
        self._check(lib.sinter_neck_model_get(self._ptr, key.encode("utf-8"),
                                              ctypes.byref(value)),
                    "sinter_neck_model_get")
        return value.value

    def __setitem__(self, key: str, value: float) -> None:
        self._check(lib.sinter_neck_model_set(self._ptr, key.encode("utf-8"), float(value)),
                    "sinter_neck_model_set")

    def update(self, options: Optional[Mapping[str, float]] = None) -> None:
        """Set several options from a mapping {key: value} (keys: NeckModel.OPTIONS)."""
        for key, value in dict(options or {}).items():
            self[key] = value

    def two_particles(self, material: Material, radius_a: float, radius_b: float,
                      times: Union[float, Sequence[float]],
                      temperatures: Union[float, Sequence[float]],
                      out_times: Union[float, Sequence[float]],
                      state: bool = False) -> NeckResult:
        """Sinter two spheres of radii radius_a, radius_b [m] touching at times[0].

        The temperature follows the piecewise-linear schedule (times [s],
        temperatures [K]; numbers for an isothermal run), held constant
        outside it. Returns a NeckResult at out_times [s] (each >= times[0]).
        On a failure the SinterError carries the partial NeckResult as .result.
        """
        times, temperatures = _as_list(times), _as_list(temperatures)
        if len(times) != len(temperatures):
            raise ValueError("%d schedule times but %d temperatures"
                             % (len(times), len(temperatures)))
        out_times = _as_list(out_times)
        n, n_out = len(times), len(out_times)
        doubles = ctypes.c_double
        c_times, c_temps = (doubles * max(n, 1))(*times), (doubles * max(n, 1))(*temperatures)
        c_out = (doubles * max(n_out, 1))(*out_times)
        x, shrinkage = (doubles * max(n_out, 1))(), (doubles * max(n_out, 1))()
        c_state = (doubles * max(7 * n_out, 1))() if state else None
        status = lib.sinter_neck_two_particles(self._ptr, material._ptr, float(radius_a),
                                               float(radius_b), n, c_times, c_temps, n_out,
                                               c_out, x, shrinkage, c_state)
        result = NeckResult(_out(c_out[:n_out], (n_out,)), _out(x[:n_out], (n_out,)),
                            _out(shrinkage[:n_out], (n_out,)),
                            _out(c_state[:7 * n_out], (n_out, 7)) if state else None,
                            min(float(radius_a), float(radius_b)))
        try:
            self._check(status, "sinter_neck_two_particles")
        except SinterError as error:
            error.result = result
            raise
        return result

    def sensitivities(self, material: Material, radius_a: float, radius_b: float,
                      times: Union[float, Sequence[float]],
                      temperatures: Union[float, Sequence[float]],
                      params: Sequence[Union[str, MaterialParam]],
                      out_times: Union[float, Sequence[float]]) -> NeckSensitivities:
        """Neck ratio and shrinkage along the schedule, as two_particles, with their forward
        sensitivities (sinter_neck_sensitivities; docs/calibration.md) with respect to the
        parameters `params` (material keys: a *_diffusion_prefactor[_hot] key means ln D0, an
        *_activation_energy[_hot] key Q [J/mol], neck_boundary_path, neck_cone_path,
        neck_cap_path or lattice_mobile_fraction ln of the value). Needs integrator 0 (CVODE).
        On a failure the SinterError carries the partial NeckSensitivities as .result.
        """
        times, temperatures = _as_list(times), _as_list(temperatures)
        if len(times) != len(temperatures):
            raise ValueError("%d schedule times but %d temperatures"
                             % (len(times), len(temperatures)))
        out_times = _as_list(out_times)
        ids = [_param_id(p) for p in params]
        keys = tuple(MaterialParam(i).name.lower() for i in ids)
        n, n_out, n_par = len(times), len(out_times), len(ids)
        doubles = ctypes.c_double
        c_times, c_temps = (doubles * max(n, 1))(*times), (doubles * max(n, 1))(*temperatures)
        c_params = (ctypes.c_int * max(n_par, 1))(*ids)
        c_out = (doubles * max(n_out, 1))(*out_times)
        ratio, shrinkage = (doubles * max(n_out, 1))(), (doubles * max(n_out, 1))()
        d_ratio = (doubles * max(n_out * n_par, 1))()
        d_shrinkage = (doubles * max(n_out * n_par, 1))()
        status = lib.sinter_neck_sensitivities(
            self._context._ptr, self._ptr, material._ptr, float(radius_a), float(radius_b), n,
            c_times, c_temps, n_par, c_params, n_out, c_out, ratio, shrinkage, d_ratio,
            d_shrinkage)
        result = NeckSensitivities(_out(c_out[:n_out], (n_out,)), _out(ratio[:n_out], (n_out,)),
                                   _out(shrinkage[:n_out], (n_out,)),
                                   _out(d_ratio[:n_out * n_par], (n_out, n_par)),
                                   _out(d_shrinkage[:n_out * n_par], (n_out, n_par)), keys)
        try:
            self._check(status, "sinter_neck_sensitivities")
        except SinterError as error:
            error.result = result
            raise
        return result

    @property
    def stats(self) -> NeckStats:
        """NeckStats of the last two_particles call."""
        stats = _CNeckStats()
        stats.struct_size = ctypes.sizeof(_CNeckStats)
        self._check(lib.sinter_neck_get_stats(self._ptr, ctypes.byref(stats)),
                    "sinter_neck_get_stats")
        return NeckStats(*(getattr(stats, name) for name, _ in _CNeckStats._fields_[1:]))

    def __repr__(self) -> str:
        return "<sinter.NeckModel%s>" % (" closed" if self.closed else "")


def run_pair(context: Context, path: "os.PathLike[str] | str", csv_path: "os.PathLike[str] | str",
             svg_path: "Optional[os.PathLike[str] | str]" = None) -> None:
    """Run a pair file (sinter_pair_run, `sinter pair`): the two-particle model along the
    schedule of its [pair] section, written to csv_path (neck ratio, shrinkage, past_limit)
    and, when given, the plot svg_path (read the CSV with the csv module)."""
    check(lib.sinter_pair_run(context._ptr, os.fsencode(path), os.fsencode(csv_path),
                              None if svg_path is None else os.fsencode(svg_path)),
          context._handle, "sinter_pair_run")
