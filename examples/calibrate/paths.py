#!/usr/bin/env python3
"""Fitting the path constants of the reconstruction (docs/calibration.md sec. 2, issue 42).

The 7DOF model's path lengths (docs/7dof.md sec. 3: neck_boundary_path, neck_cone_path,
neck_cap_path; n_v = lattice_mobile_fraction) are material parameters that sinter.calibrate.fit
fits in ln of the value, with forward sensitivities. This script makes synthetic data with the
model along seed 001's Table 3 profiles E14B, E19B and E28B (titanium of
examples/pair/titanium.materials with the boundary path at 0.15 y1 instead of 0.25; shrinkage
every 60 s with Gaussian noise 1e-4, the final neck ratio with noise 0.01) and fits four sets:

1. the boundary path alone, the diffusion data fixed: identifiable;
2. the boundary path with the beta grain-boundary D0: identifiable only because the path also
   acts on the lattice flux II, which D_gb0 does not (correlation 0.999);
3. the same material with lattice diffusion off, the boundary path with the grain-boundary D0
   of both phases: the path enters only as D_gb0 / ds, so the driver must report the set as not
   identifiable (infinite intervals) rather than a precise answer;
4. the cone and cap paths together (diffusion data fixed): identifiable.

Exit status 1 unless every identifiable set holds the truth in its 95 % intervals and set 3 is
reported not identifiable. Run: python3 paths.py [--seed N]  (needs NumPy and SciPy; a few s).
"""

import argparse
import os
import sys
from typing import Any, Dict, List

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(HERE, "..", "..", "bindings", "python"))

import recover  # noqa: E402
import sinter  # noqa: E402
from sinter import calibrate  # noqa: E402

BOUNDARY_PATH = 0.15  # the "true" boundary path, a fraction of the neck radius
#: (title, keys, material changes, whether the set is identifiable) of each fit
CASES = [
    ("boundary path, D0 fixed", ["neck_boundary_path"], {}, True),
    ("boundary path with beta D_gb0", ["neck_boundary_path",
                                       "grain_boundary_diffusion_prefactor_hot"], {}, True),
    ("boundary path with both D_gb0, lattice off",
     ["neck_boundary_path", "grain_boundary_diffusion_prefactor",
      "grain_boundary_diffusion_prefactor_hot"],
     {"lattice_diffusion_prefactor": 0.0, "lattice_diffusion_prefactor_hot": 0.0}, False),
    ("cone and cap paths", ["neck_cone_path", "neck_cap_path"], {}, True),
]


def profiles(ctx: Any, material: Any, rng: Any) -> List[Any]:
    """Synthetic shrinkage every recover.INTERVAL s and a final neck ratio per profile."""
    import numpy

    out = []
    for name, diameter in recover.PROFILES.items():
        times, temps = recover.schedule(name)
        profile = calibrate.Profile(name, diameter / 2.0, times, temps)
        obs = numpy.arange(0.0, times[-1], recover.INTERVAL)
        model = calibrate.predict(ctx, material, profile, list(obs) + [times[-1]])
        shrink = numpy.asarray(model.shrinkage, dtype=float)
        profile.time = obs
        profile.shrinkage = shrink[:-1] + rng.normal(0.0, recover.STRAIN_SIGMA, obs.size)
        profile.shrinkage_sigma = recover.STRAIN_SIGMA
        profile.neck_time = [times[-1]]
        profile.neck_ratio = [float(model.neck_ratio[-1]) + rng.normal(0.0, recover.NECK_SIGMA)]
        profile.neck_sigma = recover.NECK_SIGMA
        out.append(profile)
    return out


def run(seed: int = 2026) -> List[Dict[str, Any]]:
    """Each case's FitResult and truth."""
    import numpy

    rows = []
    for title, keys, changes, identifiable in CASES:
        truth = dict(recover.titanium(), neck_boundary_path=BOUNDARY_PATH, **changes)
        rng = numpy.random.default_rng(seed)
        with sinter.Context() as ctx:
            material = sinter.Material(ctx, "titanium", truth)
            data = profiles(ctx, material, rng)
            values = {k: float(material[k]) for k in keys}
            # start: each path and D0 a factor 1.6 off
            start = {k: v * 1.6 for k, v in values.items()}
            result = calibrate.fit(ctx, material, data, keys, start)
        rows.append({"title": title, "result": result, "truth": values,
                     "identifiable": identifiable})
    return rows


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seed", type=int, default=2026, help="noise seed")
    args = parser.parse_args()
    ok = True
    for row in run(args.seed):
        result, truth = row["result"], row["truth"]
        print("## %s: identifiable %s, condition %.3g, s^2 = %.3f"
              % (row["title"], result.identifiable, result.condition, result.residual_variance))
        print(result.table())
        inside = result.contains(truth)
        for key, value in truth.items():
            print("%-40s true %-10.6g %s" % (key, value, "inside" if inside[key] else "OUTSIDE"))
        ok = ok and result.identifiable == row["identifiable"]
        if result.identifiable:
            ok = ok and all(inside.values())
        else:
            print("undetermined: %s" % result.message.split("not identifiable: ")[-1])
        print()
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
