"""The 7DOF two-particle neck model (seed 001 sec. 2.2, docs/7dof.md)."""

import ctypes
import dataclasses
import itertools
import numbers
import os

from ._errors import SinterError, check
from ._lib import NeckModelPtr, NeckStats as _CNeckStats, lib
from .context import _Handle
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

    def as_dict(self):
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
    def neck_ratio(self):
        """x / min(R_A, R_B) [-]."""
        if hasattr(self.neck_radius, "dtype"):
            return self.neck_radius / self.radius
        return [x / self.radius for x in self.neck_radius]


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

    def __init__(self, context, **options):
        handle = NeckModelPtr()
        check(lib.sinter_neck_model_create(ctypes.byref(handle), context._ptr), context._handle,
              "sinter_neck_model_create")
        super().__init__(context, handle)
        try:
            self.update(options)
        except BaseException:
            self.close()
            raise

    def __getitem__(self, key):
        value = ctypes.c_double()
        self._check(lib.sinter_neck_model_get(self._ptr, key.encode("utf-8"),
                                              ctypes.byref(value)),
                    "sinter_neck_model_get")
        return value.value

    def __setitem__(self, key, value):
        self._check(lib.sinter_neck_model_set(self._ptr, key.encode("utf-8"), float(value)),
                    "sinter_neck_model_set")

    def update(self, options=(), **more):
        for key, value in itertools.chain(dict(options).items(), more.items()):
            self[key] = value

    def two_particles(self, material, radius_a, radius_b, times, temperatures, out_times,
                      state=False):
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

    @property
    def stats(self):
        """NeckStats of the last two_particles call."""
        stats = _CNeckStats()
        stats.struct_size = ctypes.sizeof(_CNeckStats)
        self._check(lib.sinter_neck_get_stats(self._ptr, ctypes.byref(stats)),
                    "sinter_neck_get_stats")
        return NeckStats(*(getattr(stats, name) for name, _ in _CNeckStats._fields_[1:]))

    def __repr__(self):
        return "<sinter.NeckModel%s>" % (" closed" if self.closed else "")


def run_pair(context, path, csv_path, svg_path=None):
    """Run a pair file (sinter_pair_run, `sinter pair`): the two-particle model along the
    schedule of its [pair] section, written to csv_path (neck ratio, shrinkage, past_limit)
    and, when given, the plot svg_path (read the CSV with the csv module)."""
    check(lib.sinter_pair_run(context._ptr, os.fsencode(path), os.fsencode(csv_path),
                              None if svg_path is None else os.fsencode(svg_path)),
          context._handle, "sinter_pair_run")
