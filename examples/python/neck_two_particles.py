#!/usr/bin/env python3
"""Seed 001: the neck between two copper spheres (R = 25 um) sintering at 1293 K.

The 7DOF two-particle model of Thomsen et al. (seed 001 sec. 2.2, specified by
docs/7dof.md) gives the neck ratio x/R and the shrinkage Delta L / L0 (centre
approach) against time. The copper data are the material defaults (seed 001
table 2). Printed next to the reference numbers of docs/7dof.md sec. 6.2 (an
independent RKF45 integration of the same specification); plotted into
neck_two_particles.png when matplotlib imports, written to
neck_two_particles.csv otherwise. Units: SI.

If the loaded libsinter does not have sinter_neck_two_particles yet, the
example says so and exits 0.

    python3 neck_two_particles.py [--out DIR] [--no-plot]
"""

import argparse
import math
import os
import sys

import sinter
from sinter import _lib

RADIUS = 25e-6  # m, both spheres (50 um diameter, the seed's sec. 4.1 size)
TEMPERATURE = 1293.0  # K, isothermal
END_TIME = 5000.0  # s
# docs/7dof.md sec. 6.2: t [s] -> (x/R, Delta L / L0)
REFERENCE = {1.0: (0.0892, 3.49e-4), 10.0: (0.1276, 1.11e-3), 100.0: (0.1856, 3.47e-3),
             300.0: (0.2232, 5.87e-3), 1000.0: (0.2742, 1.029e-2),
             3000.0: (0.3313, 1.693e-2), 5000.0: (0.3618, 2.123e-2)}


def write_output(ctx, out_dir, times, ratio, shrinkage, plot):
    if plot:
        try:
            import matplotlib

            matplotlib.use("Agg")
            import matplotlib.pyplot as pyplot
        except ImportError:
            pyplot = None
        if pyplot is not None:
            figure, (top, bottom) = pyplot.subplots(2, 1, sharex=True, figsize=(6, 6))
            top.loglog(times, ratio, label="libsinter")
            bottom.loglog(times, shrinkage, label="libsinter")
            ref_t = sorted(REFERENCE)
            top.loglog(ref_t, [REFERENCE[t][0] for t in ref_t], "o", label="docs/7dof.md 6.2")
            bottom.loglog(ref_t, [REFERENCE[t][1] for t in ref_t], "o", label="docs/7dof.md 6.2")
            top.set_ylabel("neck ratio x/R [-]")
            bottom.set_ylabel("shrinkage dL/L0 [-]")
            bottom.set_xlabel("time [s]")
            top.set_title("Two copper spheres, R = 25 um, 1293 K (seed 001)")
            top.legend()
            figure.tight_layout()
            path = os.path.join(out_dir, "neck_two_particles.png")
            figure.savefig(path, dpi=100)
            pyplot.close(figure)
            return path
    with sinter.Series(ctx, [("time", "s"), ("neck ratio", "1"), ("shrinkage", "1")]) as series:
        for row in zip(times, ratio, shrinkage):
            series.append(row)
        path = os.path.join(out_dir, "neck_two_particles.csv")
        series.write_csv(path)
    return path


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--out", default=".", help="directory for the plot / CSV")
    parser.add_argument("--no-plot", action="store_true", help="write CSV, do not plot")
    args = parser.parse_args(argv)
    if "sinter_neck_two_particles" in _lib.missing_functions:
        print("%s has no sinter_neck_two_particles yet (the neck model is being written); "
              "nothing to do" % sinter.library_path)
        return 0
    os.makedirs(args.out, exist_ok=True)

    # Output times: log-spaced from 0.1 s to 5000 s, plus the reference times.
    times = sorted(set([10.0 ** (-1.0 + 0.05 * k) for k in range(int(20 * math.log10(
        END_TIME * 10.0)) + 1)] + list(REFERENCE)))
    times = [t for t in times if t <= END_TIME]
    with sinter.Context() as ctx:
        copper = sinter.Material(ctx, "copper")  # the neck defaults are copper's
        with sinter.NeckModel(ctx) as model:
            result = model.two_particles(copper, RADIUS, RADIUS, times=0.0,
                                         temperatures=TEMPERATURE, out_times=times)
            stats = model.stats
        ratio = [float(x) for x in result.neck_ratio]
        shrinkage = [float(s) for s in result.shrinkage]
        print("two copper spheres, R = %g m, T = %g K (libsinter %s): %d steps, %.3f s"
              % (RADIUS, TEMPERATURE, sinter.__version__, stats.steps, stats.seconds))
        print("%8s  %10s %10s  %11s %11s" % ("t [s]", "x/R", "ref", "dL/L0", "ref"))
        worst = 0.0
        for t, (ref_ratio, ref_shrinkage) in sorted(REFERENCE.items()):
            k = times.index(t)
            print("%8g  %10.4f %10.4f  %11.4e %11.4e"
                  % (t, ratio[k], ref_ratio, shrinkage[k], ref_shrinkage))
            worst = max(worst, abs(ratio[k] / ref_ratio - 1.0))
        print("largest relative difference of x/R from docs/7dof.md 6.2: %.2f %%" % (100 * worst))
        print("wrote", write_output(ctx, args.out, times, ratio, shrinkage,
                                    plot=not args.no_plot))
    if worst > 0.05:
        print("error: the neck ratio is more than 5 % off the reference")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
