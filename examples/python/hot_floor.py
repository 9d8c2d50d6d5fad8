#!/usr/bin/env python3
"""Seed 003 sec. 5.1: a particle settling on a floor held at 700 K, with and without softening.

A sphere (r = 1 mm, 300 K, k = 60 W/(m K), C = 100 J/(kg K), rho = 3000 kg/m^3,
E0 = 1 MPa, nu = 0.3, critically damped contact xi = 1) rests under gravity on a
rigid floor at 700 K and warms up by conduction. With thermal softening
(exponential, seed 003 eq. 42, theta* = 400 K) its stiffness falls as it warms,
the overlap and the contact area grow, and it reaches the floor's temperature
sooner. The seed reports: static contact force 1.23e-4 N in both cases,
equilibrium near 12 s with softening and 18 s without, a contact area about 63 %
larger with softening and a temperature about 7 % higher at t = 8 s.
(docs/validation.md explains the reading of the seed's floor conductivity.)

Prints the static force, the equilibrium times and the area ratio; plots the
temperature against time into hot_floor.png when matplotlib imports, and writes
hot_floor.csv (through sinter.Series) otherwise. Units: SI.

    python3 hot_floor.py [--out DIR] [--end-time 40] [--no-plot] [--wall-reading 0|1|2]
"""

import argparse
import math
import os
import sys

import sinter

RADIUS = 1e-3  # m
THETA_0 = 300.0  # K, particle
THETA_FLOOR = 700.0  # K
DT = 2e-5  # s, the seed's step
SAMPLE = 0.1  # s between samples of the temperature curve
# "Equilibrium": the particle's temperature within this fraction of the initial
# difference from the floor's (0.5 %: 2 K, a line's width on the seed's Fig. 5e;
# docs/validation.md).
EQUILIBRIUM_FRACTION = 5e-3


def simulate(ctx, softening, end_time, wall_reading=None):
    """Run one case; return (times, temperatures, wall force z, centre height, stats)."""
    particle = sinter.Material(
        ctx, "particle", density=3000.0, youngs_modulus=1e6, poisson_ratio=0.3,
        damping_ratio=1.0, thermal_conductivity=60.0, heat_capacity=100.0)
    if softening:
        particle.update(softening_law=2, softening_temperature=400.0)  # seed 003 eq. 42
    # A rigid floor (E* = E/(1 - nu^2) of the particle) conducting with the particle's k.
    floor = sinter.Material(ctx, "floor", youngs_modulus=1e13, poisson_ratio=0.3,
                            thermal_conductivity=60.0)
    particles = sinter.Particles(ctx)
    particles.set_material(0, particle)
    particles.add([(0.0, 0.0, RADIUS)], RADIUS, temperature=THETA_0)  # placed tangentially
    walls = sinter.Walls(ctx)
    walls.add_plane((0.0, 0.0, 0.0), (0.0, 0.0, 1.0), floor, temperature=THETA_FLOOR)
    forces = [sinter.ForceModel(ctx, "hertz_mindlin"), sinter.ForceModel(ctx, "gravity")]
    heat = [sinter.HeatModel(ctx, "conduction")]
    if wall_reading is not None:  # the particle-wall conductance's reading (default 1: Hertz)
        heat[0]["wall_reading"] = wall_reading
    times, temperatures = [0.0], [THETA_0]
    with sinter.Stepper(ctx, particles, walls, dt=DT, forces=forces, heat=heat,
                        domain=((-0.01,) * 3, (0.01,) * 3)) as stepper:
        steps = int(round(end_time / SAMPLE))
        for k in range(1, steps + 1):
            stepper.advance(k * SAMPLE)
            times.append(stepper.time)
            with particles.view("temperature", writable=False) as theta:
                temperatures.append(theta[0])
        force_z = walls.force(0)[2]
        with particles.view("position", writable=False) as x:
            height = x[0, 2]
        stats = stepper.stats
    return times, temperatures, force_z, height, stats


def equilibrium_time(times, temperatures):
    """First sample time after which the temperature stays within the equilibrium band."""
    band = EQUILIBRIUM_FRACTION * abs(THETA_FLOOR - THETA_0)
    reached = None
    for t, theta in zip(times, temperatures):
        if abs(THETA_FLOOR - theta) <= band:
            reached = t if reached is None else reached
        else:
            reached = None
    return reached


def contact_area(height):
    """Contact area with the floor, pi a^2 with a^2 = r^2 - L^2 (L: centre-plane distance)."""
    return math.pi * max(RADIUS * RADIUS - height * height, 0.0)


def at_time(times, values, t):
    return min(zip(times, values), key=lambda item: abs(item[0] - t))[1]


def write_output(ctx, out_dir, results, plot):
    if plot:
        try:
            import matplotlib

            matplotlib.use("Agg")
            import matplotlib.pyplot as pyplot
        except ImportError:
            pyplot = None
        if pyplot is not None:
            figure, axes = pyplot.subplots(figsize=(6, 4))
            for label, (times, temperatures) in results.items():
                axes.plot(times, temperatures, label=label)
            axes.axhline(THETA_FLOOR, color="grey", linewidth=0.5)
            axes.set_xlabel("time [s]")
            axes.set_ylabel("particle temperature [K]")
            axes.set_title("Seed 003 sec. 5.1: particle on a 700 K floor")
            axes.legend()
            figure.tight_layout()
            path = os.path.join(out_dir, "hot_floor.png")
            figure.savefig(path, dpi=100)
            pyplot.close(figure)
            return path
    # Without matplotlib: the library's own CSV writer.
    labels = list(results)
    columns = [("time", "s")] + [("temperature " + label, "K") for label in labels]
    with sinter.Series(ctx, columns) as series:
        times = results[labels[0]][0]
        for row in range(len(times)):
            series.append([times[row]] + [results[label][1][row] for label in labels])
        path = os.path.join(out_dir, "hot_floor.csv")
        series.write_csv(path)
    return path


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--out", default=".", help="directory for hot_floor.png / .csv")
    parser.add_argument("--end-time", type=float, default=40.0, help="simulated time [s]")
    parser.add_argument("--no-plot", action="store_true", help="write CSV, do not plot")
    parser.add_argument("--wall-reading", type=int, choices=(0, 1, 2), default=None,
                        help="conduction's wall_reading: 0 eq. 34's area over the centre-plane "
                             "distance, 1 Hertz's area (the default), 2 the mirror particle")
    args = parser.parse_args(argv)
    os.makedirs(args.out, exist_ok=True)

    with sinter.Context() as ctx:
        cases = {}
        for label, softening in (("with softening", True), ("without softening", False)):
            cases[label] = simulate(ctx, softening, args.end_time, args.wall_reading)

        mass = 3000.0 * 4.0 / 3.0 * math.pi * RADIUS ** 3
        print("seed 003 sec. 5.1, libsinter %s, dt = %g s, %g s simulated"
              % (sinter.__version__, DT, args.end_time))
        print("weight m g = %.4e N (seed: static contact force 1.23e-4 N)" % (mass * 9.81))
        areas = {}
        for label, (times, temperatures, force_z, height, stats) in cases.items():
            t_eq = equilibrium_time(times, temperatures)
            areas[label] = contact_area(height)
            print("%-18s static force %.4e N, equilibrium (within %.1f K) %s, "
                  "final contact area %.4e m^2, %d steps in %.2f s"
                  % (label, abs(force_z), EQUILIBRIUM_FRACTION * (THETA_FLOOR - THETA_0),
                     "at %.1f s" % t_eq if t_eq is not None else "not reached",
                     areas[label], stats.steps, stats.seconds_total))
        soft, hard = cases["with softening"], cases["without softening"]
        print("contact area ratio (softening / none): %.3f (seed: about 1.63)"
              % (areas["with softening"] / areas["without softening"]))
        if args.end_time >= 8.0:
            print("temperature at 8 s: %.1f K with softening, %.1f K without: ratio %.3f "
                  "(seed: about 1.07)" % (at_time(soft[0], soft[1], 8.0),
                                          at_time(hard[0], hard[1], 8.0),
                                          at_time(soft[0], soft[1], 8.0)
                                          / at_time(hard[0], hard[1], 8.0)))
        path = write_output(ctx, args.out,
                            {label: case[:2] for label, case in cases.items()},
                            plot=not args.no_plot)
        print("wrote", path)

        # Sanity checks, so that the example fails loudly if the library regresses.
        for label, case in cases.items():
            if abs(abs(case[2]) - mass * 9.81) > 1e-3 * mass * 9.81:
                print("error: the static force of case '%s' is not the weight" % label)
                return 1
        if not areas["with softening"] > areas["without softening"]:
            print("error: softening did not enlarge the contact area")
            return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
