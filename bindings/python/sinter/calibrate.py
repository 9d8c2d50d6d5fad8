"""Calibration of the 7DOF two-particle model against dilatometry (docs/calibration.md).

Two parts:

- Dilatometry import (read_dilatometry): a CSV of time [s], temperature [K] and the measured
  length change dL/L0 [-] (positive for expansion), corrected for thermal expansion with a
  constant linear expansion coefficient alpha [1/K] or a table alpha(T). The sintering strain is
  the measured strain less the thermal strain, the integral of alpha dT from the reference
  temperature; the model's shrinkage Delta L / L0 (positive when the sample shrinks) is its
  negative. Pure Python: works without NumPy.
- A least-squares driver (fit) over several profiles at once for the Arrhenius data
  D = D0 exp(-Q / (R T)) of the material (any *_diffusion_prefactor[_hot] and
  *_activation_energy[_hot] key), the path constants of the reconstruction (neck_boundary_path,
  neck_cone_path, neck_cap_path, lattice_mobile_fraction: docs/7dof.md sec. 3, fitted in ln of
  the value) and other material keys fitted linearly, with confidence intervals from the
  Jacobian at the optimum: covariance = s^2 (J^T J)^-1, s^2 the residual variance. A set of keys
  the data cannot tell apart (a path constant and its mechanism's D0 scale the same flux) is
  reported as not identifiable, with infinite intervals, or refused (NotIdentifiable). It needs
  NumPy and SciPy (scipy.optimize.least_squares); without them fit raises
  CalibrationUnavailable saying so.

Only the Python standard library is imported at module level (NumPy and SciPy when fit runs).
"""

import csv
import dataclasses
import math
import os
from typing import Any, Dict, List, Optional, Sequence, Tuple, Union

from .context import Context
from .material import Material
from .neck import NeckModel

#: Gas constant R [J/(mol K)], as the library's Arrhenius law (docs/7dof.md sec. 3).
GAS_CONSTANT = 8.314462618

PathLike = Union[str, "os.PathLike[str]"]


class DilatometryError(ValueError):
    """A dilatometry or expansion-table file the reader refuses; .path and .line (1-based, 0 when
    the problem is not on one line) say where."""

    def __init__(self, path: str, line: int, message: str) -> None:
        self.path, self.line = path, line
        super().__init__("%s:%d: %s" % (path, line, message) if line else "%s: %s" % (path, message))


class CalibrationUnavailable(ImportError):
    """fit needs NumPy and SciPy (scipy.optimize.least_squares); raised when they are missing."""


class NotIdentifiable(ValueError):
    """fit(..., refuse_unidentifiable=True) found that the data cannot tell some fitted keys
    apart; .combinations lists the undetermined directions ({key: coefficient} in the reported
    variables) and .result the FitResult."""

    def __init__(self, message: str, combinations: List[Dict[str, float]],
                 result: "FitResult") -> None:
        super().__init__(message)
        self.combinations, self.result = combinations, result


#: The path constants of the reconstruction (docs/7dof.md sec. 3), fitted in ln of the value.
PATH_KEYS = ("neck_boundary_path", "neck_cone_path", "neck_cap_path", "lattice_mobile_fraction")


# ---------------------------------------------------------------------------------------------
# Thermal expansion


@dataclasses.dataclass(frozen=True)
class ExpansionTable:
    """Linear thermal expansion coefficient alpha(T) [1/K], piecewise linear in T [K] between the
    nodes and constant beyond the first and last (one node: a constant)."""

    temperature: Tuple[float, ...]
    alpha: Tuple[float, ...]

    def __post_init__(self) -> None:
        if len(self.temperature) != len(self.alpha) or not self.temperature:
            raise ValueError("an expansion table needs as many temperatures as coefficients, "
                             "at least one")
        for k, (t, a) in enumerate(zip(self.temperature, self.alpha)):
            if not (math.isfinite(t) and t > 0.0 and math.isfinite(a)):
                raise ValueError("expansion table node %d: T = %r K, alpha = %r 1/K (T must be "
                                 "positive, both finite)" % (k, t, a))
            if k and t <= self.temperature[k - 1]:
                raise ValueError("expansion table temperatures must increase (node %d: %r K)"
                                 % (k, t))

    def alpha_at(self, temperature: float) -> float:
        """alpha(T) [1/K]."""
        ts, al = self.temperature, self.alpha
        if temperature <= ts[0]:
            return al[0]
        if temperature >= ts[-1]:
            return al[-1]
        k = _interval(ts, temperature)
        w = (temperature - ts[k]) / (ts[k + 1] - ts[k])
        return al[k] + w * (al[k + 1] - al[k])

    def _primitive(self, temperature: float) -> float:
        """F(T) = integral of alpha from the first node to T (exact for the piecewise-linear
        alpha: the trapezoid rule on each whole interval, then the partial one)."""
        ts, al = self.temperature, self.alpha
        if temperature <= ts[0]:
            return al[0] * (temperature - ts[0])
        total = 0.0
        for k in range(len(ts) - 1):
            if temperature <= ts[k + 1]:
                a_t = self.alpha_at(temperature)
                return total + 0.5 * (al[k] + a_t) * (temperature - ts[k])
            total += 0.5 * (al[k] + al[k + 1]) * (ts[k + 1] - ts[k])
        return total + al[-1] * (temperature - ts[-1])

    def strain(self, temperature: float, reference_temperature: float) -> float:
        """Thermal strain [-]: the integral of alpha dT from reference_temperature to temperature
        (small-strain reading of alpha = (1/L0) dL/dT)."""
        return self._primitive(temperature) - self._primitive(reference_temperature)


def _interval(nodes: Sequence[float], value: float) -> int:
    """k with nodes[k] <= value < nodes[k + 1] (nodes increasing, value inside)."""
    lo, hi = 0, len(nodes) - 1
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if nodes[mid] <= value:
            lo = mid
        else:
            hi = mid
    return lo


def _numbers(path: str, columns: int, names: str) -> List[Tuple[int, List[float]]]:
    """(line number, values) of the data lines of a CSV file: blank lines and lines starting
    with '#' are skipped; one header line (the first non-comment line, when its first field is
    not a number) is allowed. Refuses anything else with the line number."""
    rows: List[Tuple[int, List[float]]] = []
    try:
        handle = open(path, newline="", encoding="utf-8")
    except FileNotFoundError:
        raise
    except OSError as error:
        raise DilatometryError(path, 0, "cannot be read (%s)" % error) from error
    with handle:
        seen_first = False
        try:
            lines = list(csv.reader(handle))
        except (csv.Error, UnicodeDecodeError) as error:
            raise DilatometryError(path, 0, "not a readable CSV file (%s)" % error) from error
        for number, fields in enumerate(lines, start=1):
            if not fields or not "".join(fields).strip() or fields[0].lstrip().startswith("#"):
                continue
            first = not seen_first
            seen_first = True
            if first:
                try:
                    float(fields[0])
                except ValueError:
                    continue  # the header line
            fields = [f.strip() for f in fields]
            if len(fields) != columns:
                raise DilatometryError(path, number, "%d fields, expected %d (%s)"
                                       % (len(fields), columns, names))
            values = []
            for column, field in enumerate(fields, start=1):
                try:
                    value = float(field)
                except ValueError:
                    raise DilatometryError(path, number, "field %d is not a number: %r"
                                           % (column, field)) from None
                if not math.isfinite(value):
                    raise DilatometryError(path, number, "field %d is not finite: %r"
                                           % (column, field))
                values.append(value)
            rows.append((number, values))
    if not rows:
        raise DilatometryError(path, 0, "no data lines (%s)" % names)
    return rows


def read_expansion_table(path: PathLike) -> ExpansionTable:
    """An alpha(T) table from a CSV file of temperature [K], alpha [1/K] (header and '#' comments
    allowed; temperatures strictly increasing and positive). Errors name the line."""
    name = os.fspath(path)
    rows = _numbers(name, 2, "temperature [K], alpha [1/K]")
    for k, (number, (t, _)) in enumerate(rows):
        if t <= 0.0:
            raise DilatometryError(name, number, "temperature %r K is not positive" % t)
        if k and t <= rows[k - 1][1][0]:
            raise DilatometryError(name, number, "temperature %r K does not increase" % t)
    return ExpansionTable(tuple(r[1][0] for r in rows), tuple(r[1][1] for r in rows))


@dataclasses.dataclass
class Dilatometry:
    """A dilatometry curve after the thermal-expansion correction.

    time [s], temperature [K], measured_strain dL/L0 [-] (as recorded, expansion positive),
    thermal_strain [-] (integral of alpha dT from reference_temperature [K]); lists of floats.
    """

    name: str
    time: List[float]
    temperature: List[float]
    measured_strain: List[float]
    thermal_strain: List[float]
    reference_temperature: float

    @property
    def sintering_strain(self) -> List[float]:
        """measured_strain - thermal_strain [-] (negative while the sample shrinks)."""
        return [m - t for m, t in zip(self.measured_strain, self.thermal_strain)]

    @property
    def shrinkage(self) -> List[float]:
        """The sintering shrinkage in the model's convention, Delta L / L0 = -(sintering strain)
        [-], positive while the sample shrinks (docs/7dof.md sec. 5)."""
        return [-s for s in self.sintering_strain]


def thermal_strain(temperatures: Sequence[float], reference_temperature: float,
                   cte: Optional[float] = None,
                   cte_table: Optional[ExpansionTable] = None) -> List[float]:
    """The thermal strain [-] at each temperature [K]: the integral of alpha dT from
    reference_temperature [K], alpha [1/K] the constant cte or the table (exactly one given)."""
    if (cte is None) == (cte_table is None):
        raise ValueError("give exactly one of cte (a constant alpha [1/K]) and cte_table")
    if cte is not None:
        if not math.isfinite(cte):
            raise ValueError("cte must be finite, got %r" % cte)
        cte_table = ExpansionTable((reference_temperature,), (float(cte),))
    assert cte_table is not None
    return [cte_table.strain(t, reference_temperature) for t in temperatures]


def read_dilatometry(path: PathLike, *, cte: Optional[float] = None,
                     cte_table: Optional[Union[ExpansionTable, PathLike]] = None,
                     reference_temperature: Optional[float] = None,
                     name: Optional[str] = None) -> Dilatometry:
    """Read a dilatometry CSV file: time [s], temperature [K], dL/L0 [-] per line (an optional
    header line, blank lines and '#' comments allowed).

    The thermal strain is the integral of alpha dT from reference_temperature (default: the first
    line's temperature, where a dilatometer is zeroed) with alpha [1/K] the constant cte or the
    table cte_table (an ExpansionTable or the path of a read_expansion_table file); give neither
    for a curve already corrected (thermal strain 0). Refuses, with DilatometryError naming the
    line: a wrong number of fields, a field that is not a finite number, a time that does not
    increase, a temperature that is not positive; FileNotFoundError for a missing file.
    """
    file_name = os.fspath(path)
    rows = _numbers(file_name, 3, "time [s], temperature [K], dL/L0 [-]")
    for k, (number, (t, temp, _)) in enumerate(rows):
        if k and t <= rows[k - 1][1][0]:
            raise DilatometryError(file_name, number, "time %r s does not increase (previous "
                                   "line: %r s)" % (t, rows[k - 1][1][0]))
        if temp <= 0.0:
            raise DilatometryError(file_name, number, "temperature %r K is not positive" % temp)
    times = [r[1][0] for r in rows]
    temps = [r[1][1] for r in rows]
    strains = [r[1][2] for r in rows]
    t_ref = temps[0] if reference_temperature is None else float(reference_temperature)
    if not (math.isfinite(t_ref) and t_ref > 0.0):
        raise ValueError("reference_temperature must be positive and finite, got %r" % t_ref)
    if cte_table is not None and not isinstance(cte_table, ExpansionTable):
        cte_table = read_expansion_table(cte_table)
    if cte is None and cte_table is None:
        thermal = [0.0] * len(temps)
    else:
        thermal = thermal_strain(temps, t_ref, cte=cte, cte_table=cte_table)
    if name is None:
        name = os.path.splitext(os.path.basename(file_name))[0]
    return Dilatometry(name, times, temps, strains, thermal, t_ref)


def write_dilatometry(path: PathLike, time: Sequence[float], temperature: Sequence[float],
                      strain: Sequence[float]) -> None:
    """Write a CSV that read_dilatometry reads back: time [s], temperature [K], dL/L0 [-]
    (repr of each float: exact round trip)."""
    if not len(time) == len(temperature) == len(strain):
        raise ValueError("time, temperature and strain must have one length")
    with open(os.fspath(path), "w", newline="", encoding="utf-8") as handle:
        handle.write("time [s],temperature [K],dL/L0 [-]\n")
        for row in zip(time, temperature, strain):
            handle.write(",".join(repr(float(v)) for v in row) + "\n")


# ---------------------------------------------------------------------------------------------
# Fitting


@dataclasses.dataclass
class Profile:
    """One experiment: two equal spheres of radius [m] heated along the piecewise-linear schedule
    (schedule_time [s], schedule_temperature [K]), observed as shrinkage Delta L / L0 [-] at
    time [s] with standard deviation shrinkage_sigma [-] (a number or one per point), and
    optionally as neck ratios x/R [-] at neck_time [s] with neck_sigma [-]."""

    name: str
    radius: float
    schedule_time: Sequence[float]
    schedule_temperature: Sequence[float]
    time: Sequence[float] = ()
    shrinkage: Sequence[float] = ()
    shrinkage_sigma: Union[float, Sequence[float]] = 1.0
    neck_time: Sequence[float] = ()
    neck_ratio: Sequence[float] = ()
    neck_sigma: Union[float, Sequence[float]] = 1.0

    @classmethod
    def from_dilatometry(cls, data: Dilatometry, radius: float, sigma: float,
                         schedule: Optional[Tuple[Sequence[float], Sequence[float]]] = None,
                         start_time: Optional[float] = None) -> "Profile":
        """A profile from a corrected dilatometry curve: its shrinkage with standard deviation
        sigma [-]; the schedule (times [s], temperatures [K]) given, or else the recorded
        temperatures themselves. Points before start_time [s] (default: the first) are
        dropped; the model starts at the schedule's first time."""
        t0 = data.time[0] if start_time is None else float(start_time)
        keep = [k for k, t in enumerate(data.time) if t >= t0]
        times = [data.time[k] for k in keep]
        if schedule is None:
            schedule = (times, [data.temperature[k] for k in keep])
        shrink = data.shrinkage
        return cls(data.name, float(radius), list(schedule[0]), list(schedule[1]), times,
                   [shrink[k] for k in keep], float(sigma))


def _split_key(key: str) -> Tuple[str, str, str]:
    """(kind, mechanism, phase suffix) of a material key: kind "prefactor", "energy", "path"
    (PATH_KEYS) or "linear"."""
    if key in PATH_KEYS:
        return "path", key, ""
    suffix = "_hot" if key.endswith("_hot") else ""
    base = key[:-len(suffix)] if suffix else key
    if base.endswith("_diffusion_prefactor"):
        return "prefactor", base[:-len("_diffusion_prefactor")], suffix
    if base.endswith("_activation_energy"):
        return "energy", base[:-len("_activation_energy")], suffix
    return "linear", base, suffix


def _energy_key(mechanism: str, suffix: str) -> str:
    return "%s_activation_energy%s" % (mechanism, suffix)


def _prefactor_key(mechanism: str, suffix: str) -> str:
    return "%s_diffusion_prefactor%s" % (mechanism, suffix)


class _Parametrisation:
    """Internal variables theta of the fit and their linear map to the reported ones.

    Reported: ln D0 for a prefactor, ln of the value for a path constant, Q [J/mol] for an
    activation energy, the value for any other key. Internal, dimensionless and of order one to
    ten, so that the solver and the finite differences see well-scaled, weakly correlated
    variables: where both D0 and Q of a mechanism are fitted, theta = (ln D(T_ref),
    Q / (R T_ref)), which removes most of the correlation of ln D0 and Q over a narrow
    temperature range; a lone Q is Q / (R T_ref); a lone prefactor ln D0; a path constant ln of
    it; another key value / (its initial value).
    """

    def __init__(self, keys: Sequence[str], initial: Dict[str, float], t_ref: float) -> None:
        self.keys = list(keys)
        self.t_ref = t_ref
        n = len(self.keys)
        # reported = offset + A @ theta
        self.matrix = [[0.0] * n for _ in range(n)]
        index = {k: i for i, k in enumerate(self.keys)}
        for i, key in enumerate(self.keys):
            kind, mech, suffix = _split_key(key)
            if kind == "path":
                self.matrix[i][i] = 1.0
            elif kind == "prefactor":
                self.matrix[i][i] = 1.0
                j = index.get(_energy_key(mech, suffix))
                if j is not None:  # ln D0 = ln D(T_ref) + Q / (R T_ref)
                    self.matrix[i][j] = 1.0
            elif kind == "energy":
                self.matrix[i][i] = GAS_CONSTANT * t_ref
            else:
                self.matrix[i][i] = initial[key]
        self.reported0 = [math.log(initial[k]) if _logarithmic(k) else initial[k]
                          for k in self.keys]

    def bounds(self, theta0: Sequence[float], factor: float) -> Tuple[List[float], List[float]]:
        """Trust box of the search around theta0: ln D within a factor `factor` either way, a path
        constant within a factor 10 (n_v also at most 1), Q (and any other key) within a
        factor 2."""
        low, high = [], []
        for key, t in zip(self.keys, theta0):
            kind = _split_key(key)[0]
            if kind == "path":  # n_v is a fraction: at most 1 (ln 0)
                low.append(t - math.log(10.0))
                high.append(min(t + math.log(10.0), 0.0) if key == "lattice_mobile_fraction"
                            else t + math.log(10.0))
            elif kind == "prefactor":
                low.append(t - math.log(factor))
                high.append(t + math.log(factor))
            else:
                low.append(min(0.5 * t, 2.0 * t))
                high.append(max(0.5 * t, 2.0 * t))
        return low, high

    def theta_of(self, reported: Sequence[float]) -> List[float]:
        import numpy

        return list(numpy.linalg.solve(numpy.array(self.matrix), numpy.array(reported)))

    def reported_of(self, theta: Sequence[float]) -> List[float]:
        return [sum(a * t for a, t in zip(row, theta)) for row in self.matrix]

    def values_of(self, theta: Sequence[float]) -> Dict[str, float]:
        """Material values {key: value in its SI unit}."""
        out = {}
        for key, r in zip(self.keys, self.reported_of(theta)):
            out[key] = math.exp(r) if _logarithmic(key) else r
        return out


def _logarithmic(key: str) -> bool:
    """Whether a key is fitted and reported as ln of its value (prefactors, path constants)."""
    return _split_key(key)[0] in ("prefactor", "path")


@dataclasses.dataclass
class FitResult:
    """Result of fit. Per fitted key (same order as keys): value in its SI unit, the reported
    variable (ln D0 for a prefactor, ln of the value for a path constant, Q [J/mol] for an
    activation energy, the value otherwise), its standard error, and the confidence interval of
    the value (confidence level `level`; a prefactor's or path constant's interval is
    exp(ln value -+ t sigma), not symmetric). covariance and correlation are those of the
    reported variables (s^2 (J^T J)^-1 mapped linearly); residual_variance is
    s^2 = sum of squared weighted residuals / (m - p); dof = m - p; evaluations counts runs of
    every profile (residuals and Jacobians); jacobian_kind is "sensitivity" or "differences".

    identifiable is False when the data cannot tell some keys apart: the smallest singular value
    of the Jacobian with unit columns is below identifiability_tol times the largest (condition
    is their ratio, largest / smallest). Then unidentified lists the undetermined directions
    ({key: coefficient}, unit length in the solver's variables, mapped to the reported ones),
    the keys they involve have an infinite standard error and the interval (0, inf) or
    (-inf, inf), and the values of those keys are one arbitrary point of a set that fits equally
    well; the other keys keep finite intervals (their variance is estimable: s^2 times a
    generalised inverse). covariance and correlation then hold NaN in the undetermined rows."""

    keys: List[str]
    values: Dict[str, float]
    reported: List[float]
    standard_error: List[float]
    interval: Dict[str, Tuple[float, float]]
    covariance: Any
    correlation: Any
    residual_variance: float
    dof: int
    level: float
    t_ref: float
    residuals: Any
    jacobian: Any
    evaluations: int
    success: bool
    message: str
    jacobian_kind: str = "sensitivity"
    identifiable: bool = True
    unidentified: List[Dict[str, float]] = dataclasses.field(default_factory=list)
    condition: float = 1.0

    def contains(self, truth: Dict[str, float]) -> Dict[str, bool]:
        """Whether each interval holds the given value {key: value}."""
        return {k: self.interval[k][0] <= v <= self.interval[k][1] for k, v in truth.items()}

    def table(self) -> str:
        """A Markdown table of the fitted values and their intervals."""
        lines = ["| key | value | %g %% interval | reported variable +- standard error |"
                 % (100.0 * self.level), "|---|---|---|---|"]
        for key, r, se in zip(self.keys, self.reported, self.standard_error):
            low, high = self.interval[key]
            what = {"prefactor": "ln D0", "path": "ln value"}.get(_split_key(key)[0], "value")
            lines.append("| %s | %.6g | [%.6g, %.6g] | %s = %.6g +- %.3g |"
                         % (key, self.values[key], low, high, what, r, se))
        return "\n".join(lines)


class _Model:
    """The forward model: material values -> weighted residuals of every profile."""

    def __init__(self, context: Context, material: Material, profiles: Sequence[Profile],
                 options: Optional[Dict[str, float]], neck_weight: float) -> None:
        import numpy

        self.material = material.clone()
        self.neck = NeckModel(context, options if options is not None else {"rtol": 1e-9})
        self.profiles = list(profiles)
        self.neck_weight = float(neck_weight)
        self.plan = []
        for p in self.profiles:
            t_s = numpy.asarray(p.time, dtype=float)
            t_n = numpy.asarray(p.neck_time, dtype=float)
            out = numpy.unique(numpy.concatenate([t_s, t_n]))
            if out.size == 0:
                raise ValueError("profile %s has no observation" % p.name)
            if len(p.shrinkage) != t_s.size or len(p.neck_ratio) != t_n.size:
                raise ValueError("profile %s: as many observations as times are needed"
                                 % p.name)
            sig_s = numpy.broadcast_to(numpy.asarray(p.shrinkage_sigma, dtype=float), t_s.shape)
            sig_n = numpy.broadcast_to(numpy.asarray(p.neck_sigma, dtype=float), t_n.shape)
            if numpy.any(sig_s <= 0.0) or numpy.any(sig_n <= 0.0):
                raise ValueError("profile %s: standard deviations must be positive" % p.name)
            self.plan.append((out, numpy.searchsorted(out, t_s), numpy.searchsorted(out, t_n),
                              numpy.asarray(p.shrinkage, dtype=float), sig_s,
                              numpy.asarray(p.neck_ratio, dtype=float), sig_n))
        self.evaluations = 0

    def run(self, values: Dict[str, float], profile: Profile, out_times: Sequence[float]) -> Any:
        self.material.update(values)
        return self.neck.two_particles(self.material, profile.radius, profile.radius,
                                       list(profile.schedule_time),
                                       list(profile.schedule_temperature), list(out_times))

    def residuals(self, values: Dict[str, float]) -> Any:
        import numpy

        self.evaluations += 1
        parts = []
        for p, (out, i_s, i_n, y_s, sig_s, y_n, sig_n) in zip(self.profiles, self.plan):
            result = self.run(values, p, out)
            shrink = numpy.asarray(result.shrinkage, dtype=float)
            ratio = numpy.asarray(result.neck_ratio, dtype=float)
            parts.append((shrink[i_s] - y_s) / sig_s)
            parts.append(self.neck_weight * (ratio[i_n] - y_n) / sig_n)
        return numpy.concatenate(parts)

    def jacobian(self, values: Dict[str, float], keys: Sequence[str]) -> Any:
        """d(weighted residuals) / d(ln D0 or Q) of every key, from the forward sensitivities
        (NeckModel.sensitivities, sinter_neck_sensitivities)."""
        import numpy

        self.evaluations += 1
        self.material.update(values)
        parts = []
        for p, (out, i_s, i_n, _, sig_s, _, sig_n) in zip(self.profiles, self.plan):
            sens = self.neck.sensitivities(self.material, p.radius, p.radius,
                                           list(p.schedule_time),
                                           list(p.schedule_temperature), list(keys), out)
            d_shrink = numpy.asarray(sens.d_shrinkage, dtype=float).reshape(out.size, -1)
            d_ratio = numpy.asarray(sens.d_neck_ratio, dtype=float).reshape(out.size, -1)
            parts.append(d_shrink[i_s] / sig_s[:, None])
            parts.append(self.neck_weight * d_ratio[i_n] / sig_n[:, None])
        return numpy.concatenate(parts, axis=0)

    def close(self) -> None:
        self.neck.close()
        self.material.close()


def _require_scipy() -> Any:
    try:
        import numpy  # noqa: F401
        import scipy.optimize
    except ImportError as error:
        raise CalibrationUnavailable(
            "sinter.calibrate.fit needs NumPy and SciPy (scipy.optimize.least_squares); "
            "install them (Debian: apt-get install python3-numpy python3-scipy): %s"
            % error) from error
    return scipy.optimize


def _student_t(level: float, dof: int) -> float:
    """The two-sided Student t quantile of confidence `level` for dof degrees of freedom (the
    normal quantile where scipy.stats is missing or dof is large)."""
    try:
        from scipy.stats import t as student

        return float(student.ppf(0.5 + 0.5 * level, max(dof, 1)))
    except ImportError:  # pragma: no cover - scipy.optimize without scipy.stats is unusual
        from statistics import NormalDist

        return NormalDist().inv_cdf(0.5 + 0.5 * level)


def fit(context: Context, material: Material, profiles: Sequence[Profile], keys: Sequence[str],
        initial: Optional[Dict[str, float]] = None, *, level: float = 0.95,
        t_ref: Optional[float] = None, neck_options: Optional[Dict[str, float]] = None,
        neck_weight: float = 1.0, step: float = 1e-3, max_evaluations: int = 200,
        xtol: float = 1e-10, search_factor: float = 1e3,
        jacobian: str = "auto", identifiability_tol: float = 1e-5,
        refuse_unidentifiable: bool = False) -> FitResult:
    """Fit the material keys to every profile at once by weighted least squares.

    material: the starting material (not changed: a clone is fitted); initial {key: value}
    overrides its starting values. keys: material keys to fit; prefactors D0 [m^2/s] and the
    path constants (PATH_KEYS, docs/7dof.md sec. 3) are fitted in ln of the value, activation
    energies Q [J/mol] linearly, with D0 and Q of one mechanism and phase re-expressed around
    t_ref [K] (default: the reciprocal of the mean 1/T of the schedules) for conditioning. The
    residual of an observation is (model - data) / sigma (neck ratios also times neck_weight).
    The Jacobian: jacobian = "sensitivity" from the forward sensitivities of the model
    (NeckModel.sensitivities; diffusion prefactors, activation energies and path constants),
    "differences" by central differences of size step in the internal variables (each a
    relative change of about step in D, Q or a path), "auto" (default) the first when every key
    allows it. The model runs at neck_options (default rtol 1e-9, well below the effect of a
    step). The search stays within a factor search_factor of each starting D (as the D(T_ref)
    where Q is fitted too), a factor 10 of each path constant and a factor 2 of each starting Q
    or other value. Confidence intervals at `level` from the Student t quantile with m - p
    degrees of freedom and covariance s^2 (J^T J)^-1. Keys the data cannot tell apart (the Jacobian with unit columns has a
    singular value below identifiability_tol times its largest; a path constant fitted with its
    mechanism's D0 is the typical case) make FitResult.identifiable False with infinite
    intervals for them, or raise NotIdentifiable with refuse_unidentifiable. Raises
    CalibrationUnavailable without NumPy/SciPy, ValueError on bad input, SinterError when the
    model fails at a trial point.
    """
    optimize = _require_scipy()
    import numpy

    keys = list(keys)
    if not keys or len(set(keys)) != len(keys):
        raise ValueError("keys must be distinct material keys, at least one")
    if not profiles:
        raise ValueError("at least one profile is needed")
    if not 0.0 < level < 1.0:
        raise ValueError("level must lie in (0, 1), got %r" % level)
    if not search_factor > 1.0:
        raise ValueError("search_factor must exceed 1, got %r" % search_factor)
    if not 0.0 < step < 0.5:
        raise ValueError("step must lie in (0, 0.5), got %r" % step)
    if not 0.0 < identifiability_tol < 1.0:
        raise ValueError("identifiability_tol must lie in (0, 1), got %r" % identifiability_tol)
    start = {k: float(material[k]) for k in keys}
    start.update({k: float(v) for k, v in (initial or {}).items()})
    for key in keys:
        kind = _split_key(key)[0]
        if kind in ("prefactor", "path", "linear") and not start[key] > 0.0:
            raise ValueError("%s must start positive, got %r" % (key, start[key]))
    arrhenius = all(_split_key(k)[0] != "linear" for k in keys)
    if jacobian == "auto":
        jacobian = "sensitivity" if arrhenius else "differences"
    if jacobian not in ("sensitivity", "differences"):
        raise ValueError("jacobian must be 'auto', 'sensitivity' or 'differences', got %r"
                         % (jacobian,))
    if jacobian == "sensitivity" and not arrhenius:
        raise ValueError("sensitivities exist for diffusion prefactors, activation energies "
                         "and path constants only; use jacobian='differences'")
    if t_ref is None:
        inverse = [1.0 / t for p in profiles for t in p.schedule_temperature]
        t_ref = len(inverse) / sum(inverse)
    par = _Parametrisation(keys, start, float(t_ref))
    model = _Model(context, material, profiles, neck_options, neck_weight)
    try:
        def residuals(theta: Any) -> Any:
            return model.residuals(par.values_of(theta))

        a = numpy.array(par.matrix)
        by_differences = jacobian == "differences"

        def jacobian_of(theta: Any) -> Any:
            if not by_differences:  # d r / d theta = d r / d(ln D0, Q) @ A
                return model.jacobian(par.values_of(theta), keys) @ a
            columns = []
            for j in range(len(theta)):
                up, down = numpy.array(theta, dtype=float), numpy.array(theta, dtype=float)
                up[j] += step
                down[j] -= step
                columns.append((residuals(up) - residuals(down)) / (2.0 * step))
            return numpy.column_stack(columns)

        theta0 = numpy.array(par.theta_of(par.reported0))
        solution = optimize.least_squares(residuals, theta0, jac=jacobian_of, method="trf",
                                          bounds=par.bounds(theta0, search_factor),
                                          x_scale=1.0, xtol=xtol, ftol=1e-12, gtol=1e-12,
                                          max_nfev=max_evaluations)
        theta = solution.x
        r = residuals(theta)
        jac = jacobian_of(theta)
        m, p = r.size, len(keys)
        dof = m - p
        if dof <= 0:
            raise ValueError("%d observations cannot fit %d parameters" % (m, p))
        s2 = float(r @ r) / dof
        cov, null, condition = _covariance(jac, a, s2, identifiability_tol)
        se = numpy.sqrt(numpy.diag(cov))
        with numpy.errstate(invalid="ignore", divide="ignore"):
            corr = cov / numpy.outer(se, se)
        reported = par.reported_of(theta)
        quantile = _student_t(level, dof)
        values = par.values_of(theta)
        interval = {}
        for key, rep, s in zip(keys, reported, se):
            if not numpy.isfinite(s):
                interval[key] = (0.0, math.inf) if _logarithmic(key) else (-math.inf, math.inf)
                continue
            low, high = rep - quantile * s, rep + quantile * s
            if _logarithmic(key):
                low, high = math.exp(low), math.exp(high)
            interval[key] = (low, high)
        unidentified = [{k: float(c) for k, c in zip(keys, a @ v)} for v in null]
        message = str(solution.message)
        if null:
            message += ("; not identifiable: the data do not determine %s (only the combinations "
                        "orthogonal to these are fitted)"
                        % "; ".join(_describe(u) for u in unidentified))
        result = FitResult(keys, values, list(reported), list(se), interval, cov, corr, s2, dof,
                           level, float(t_ref), r, jac, model.evaluations,
                           bool(solution.success), message, jacobian, not null, unidentified,
                           condition)
        if null and refuse_unidentifiable:
            raise NotIdentifiable(message, unidentified, result)
        return result
    finally:
        model.close()


def _describe(direction: Dict[str, float]) -> str:
    """'+0.707 neck_boundary_path -0.707 grain_boundary_diffusion_prefactor' (terms >= 1e-3)."""
    return " ".join("%+.3g %s" % (c, k) for k, c in direction.items() if abs(c) >= 1e-3)


def _covariance(jac: Any, a: Any, s2: float, tol: float) -> Tuple[Any, List[Any], float]:
    """Covariance of the reported variables, the undetermined directions in the solver's
    variables (unit vectors) and the condition number of the Jacobian with unit columns.

    With the columns scaled to unit length (a parameter that does not act keeps a zero column),
    a singular value below tol times the largest is an undetermined direction. The covariance
    is then s^2 A D (J_s^T J_s)^+ D A^T over the determined subspace (the pseudo-inverse is a
    generalised inverse, which gives the exact variance of every estimable combination), and
    NaN, an infinite variance on the diagonal, for any reported variable that the undetermined
    directions move (more than 1e-6 of its row of A)."""
    import numpy

    norms = numpy.linalg.norm(jac, axis=0)
    scale = numpy.where(norms > 0.0, 1.0 / numpy.where(norms > 0.0, norms, 1.0), 1.0)
    scaled = jac * scale
    _, sv, vt = numpy.linalg.svd(scaled, full_matrices=False)
    largest = sv[0] if sv.size and sv[0] > 0.0 else 1.0
    condition = float(largest / sv[-1]) if sv[-1] > 0.0 else math.inf
    small = sv < tol * largest
    inv = numpy.zeros((sv.size, sv.size))
    for k in range(sv.size):
        if not small[k]:
            inv += numpy.outer(vt[k], vt[k]) / sv[k] ** 2
    transform = a * scale  # A D
    cov = s2 * transform @ inv @ transform.T
    null = []
    for k in numpy.nonzero(small)[0]:
        v = scale * vt[k]  # the direction in the solver's variables
        null.append(v / numpy.linalg.norm(v))
    if null:
        moved = numpy.zeros(len(cov), dtype=bool)
        for v in null:
            moved |= numpy.abs(a @ v) > 1e-6 * numpy.linalg.norm(a, axis=1)
        cov[moved, :] = numpy.nan
        cov[:, moved] = numpy.nan
        cov[moved, moved] = numpy.inf
    return cov, null, condition


def predict(context: Context, material: Material, profile: Profile,
            out_times: Sequence[float], values: Optional[Dict[str, float]] = None,
            neck_options: Optional[Dict[str, float]] = None) -> Any:
    """The model's NeckResult along a profile's schedule at out_times [s], with the material's
    values, or with `values` {key: value} set on a clone (e.g. FitResult.values)."""
    model = _Model.__new__(_Model)
    model.material = material.clone()
    model.neck = NeckModel(context, neck_options if neck_options is not None else {"rtol": 1e-9})
    try:
        return model.run(dict(values or {}), profile, out_times)
    finally:
        model.close()
