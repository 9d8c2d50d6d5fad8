#!/usr/bin/env python3
"""Recover known diffusion data from synthetic dilatometry (docs/calibration.md).

1. The 7DOF two-particle model runs seed 001's Table 3 profiles E14B, E19B and E28B with the
   titanium data of examples/pair/titanium.materials (the "truth").
2. Each run becomes a dilatometer record: the thermal strain of expansion_table.csv added to the
   sintering strain (the negative of the model's shrinkage), Gaussian noise of standard
   deviation 1e-4 (1 um on a 10 mm sample) added, one line every 60 s, written as
   OUT/E*.dil.csv. The final neck ratio of each profile is also "measured", with standard
   deviation 0.01 (the size of an SEM reading of fracture surfaces).
3. read_dilatometry reads the files back and removes the thermal strain; sinter.calibrate.fit
   fits the beta-phase grain-boundary and surface D0 and Q to the three profiles at once, from a
   start a factor 5 and 3 % away (D0, Q of the grain boundary) and a factor 1/4 and 3 % away
   (surface).
4. Each true value must lie inside its 95 % confidence interval; the script exits 1 otherwise.

Run: python3 recover.py [--out DIR] [--seed N]  (needs NumPy and SciPy; about 10 s).
"""

import argparse
import configparser
import os
import sys
from typing import Any, Dict, List, Tuple

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "bindings", "python"))

import sinter  # noqa: E402
from sinter import calibrate  # noqa: E402

#: Profiles of seed 001's Table 3 used here: name -> mean diameter [m].
PROFILES = {"E14B": 66.6e-6, "E19B": 65.3e-6, "E28B": 66.5e-6}
#: The fitted keys (beta phase: the profiles above spend their hold at 1373 K or 1573 K).
KEYS = ["grain_boundary_diffusion_prefactor_hot", "grain_boundary_activation_energy_hot",
        "surface_diffusion_prefactor_hot", "surface_activation_energy_hot"]
#: The start of the search, relative to the truth: factor on D0, factor on Q.
START = {KEYS[0]: 5.0, KEYS[1]: 1.03, KEYS[2]: 0.25, KEYS[3]: 0.97}
STRAIN_SIGMA = 1e-4  # dilatometer noise, dL/L0 [-]
NECK_SIGMA = 0.01  # final neck ratio x/R [-]
INTERVAL = 60.0  # s between dilatometer lines


def titanium() -> Dict[str, float]:
    """Seed 001's Table 4 titanium, as examples/pair/titanium.materials holds it."""
    parser = configparser.ConfigParser()
    parser.read(os.path.join(HERE, "..", "pair", "titanium.materials"))
    return {k: float(v) for k, v in parser["material titanium"].items()}


def schedule(name: str) -> Tuple[List[float], List[float]]:
    """Table 3's schedule (time [s], temperature [K]) from examples/pair/NAME.csv."""
    times, temps = [], []
    with open(os.path.join(HERE, "..", "pair", name + ".csv")) as handle:
        next(handle)
        for line in handle:
            t, temp = line.split(",")
            times.append(float(t))
            temps.append(float(temp))
    return times, temps


def run(out_dir: str, seed: int = 2026,
        jacobian: str = "auto") -> Tuple[Any, Dict[str, float]]:
    """Make the synthetic records, fit them; returns (FitResult, true values)."""
    import numpy

    os.makedirs(out_dir, exist_ok=True)
    truth = titanium()
    table = calibrate.read_expansion_table(os.path.join(HERE, "expansion_table.csv"))
    rng = numpy.random.default_rng(seed)
    profiles = []
    with sinter.Context() as ctx:
        material = sinter.Material(ctx, "titanium", truth)
        for name, diameter in PROFILES.items():
            times, temps = schedule(name)
            plain = calibrate.Profile(name, diameter / 2.0, times, temps)
            record_t = numpy.arange(0.0, times[-1] + 0.5 * INTERVAL, INTERVAL)
            record_t[-1] = min(record_t[-1], times[-1])
            record_temp = numpy.interp(record_t, times, temps)
            model = calibrate.predict(ctx, material, plain, record_t)
            thermal = calibrate.thermal_strain(record_temp, temps[0], cte_table=table)
            measured = (numpy.asarray(thermal) - numpy.asarray(model.shrinkage)
                        + rng.normal(0.0, STRAIN_SIGMA, record_t.size))
            path = os.path.join(out_dir, name + ".dil.csv")
            calibrate.write_dilatometry(path, record_t, record_temp, measured)
            # the record read back, corrected for expansion, and the measured final neck
            data = calibrate.read_dilatometry(path, cte_table=table)
            profile = calibrate.Profile.from_dilatometry(data, diameter / 2.0, STRAIN_SIGMA,
                                                         schedule=(times, temps))
            profile.neck_time = [times[-1]]
            profile.neck_ratio = [float(model.neck_ratio[-1]) + rng.normal(0.0, NECK_SIGMA)]
            profile.neck_sigma = NECK_SIGMA
            profiles.append(profile)
        start = {k: truth[k] * START[k] for k in KEYS}
        result = calibrate.fit(ctx, material, profiles, KEYS, start, jacobian=jacobian)
    return result, {k: truth[k] for k in KEYS}


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default="out/calibrate", help="folder for the records")
    parser.add_argument("--seed", type=int, default=2026, help="noise seed")
    parser.add_argument("--jacobian", default="auto", choices=("auto", "sensitivity",
                                                               "differences"),
                        help="forward sensitivities (auto) or central differences")
    args = parser.parse_args()
    result, truth = run(args.out, args.seed, args.jacobian)
    print(result.table())
    print("residual variance s^2 = %.3f on %d degrees of freedom; %d evaluations of the "
          "three profiles; Jacobian by %s; %s" % (result.residual_variance, result.dof,
                                                  result.evaluations, result.jacobian_kind,
                                                  result.message))
    inside = result.contains(truth)
    for key, value in truth.items():
        print("%-40s true %-10.6g %s" % (key, value, "inside" if inside[key] else "OUTSIDE"))
    return 0 if all(inside.values()) else 1


if __name__ == "__main__":
    sys.exit(main())
