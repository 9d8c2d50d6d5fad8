#!/usr/bin/env python3
"""A bed settling in a box on several MPI ranks, driven from Python (sinter.mpi, issue 44).

Rank 0 fills a jittered lattice of glass spheres (r = 0.5 mm, Hertz-Mindlin with friction and
damping, gravity) in a box of five walls; every rank sets up the same materials, walls and
stepper over its own set. A sinter.mpi.Domain over MPI.COMM_WORLD decomposes the box (slabs
across x, one per rank, or with --balance a bisection rebalanced at the rebuilds), is attached
as the stepper's collective operations and hands each particle to the rank whose part holds
it; the library then migrates particles, trades ghosts and reduces through MPI by itself.
Every --report steps rank 0 prints the time, the largest speed, the force on the floor (the
same bits on every rank) and the exchange figures per step summed over the ranks; at the
end a portable checkpoint (MPI-IO, restartable on another number of ranks) goes to
DIR/mpi_bed.ckpt. Units: SI.

    mpiexec -n 2 python3 mpi_bed.py [--out DIR] [--steps 2000] [--report 500] [--balance]

Needs mpi4py (Debian: python3-mpi4py) and libsinter built with -DSINTER_MPI=ON; without them
it says so and exits 0.
"""

import argparse
import os
import random
import sys

import sinter
import sinter.mpi

RADIUS = 0.5e-3  # m
SPACING = 1.02e-3  # m, lattice spacing (a small gap)
NX, NY, NZ = 10, 6, 8
BOX = (NX * SPACING, NY * SPACING, 0.02)  # m
DT = 2e-6  # s


def setup(ctx, fill):
    """Materials, walls and stepper (the same on every rank); the particles on rank 0 only."""
    glass = sinter.Material(ctx, "glass", youngs_modulus=5e7, poisson_ratio=0.25,
                            density=2500.0, damping_ratio=0.3, friction_static=0.4,
                            friction_dynamic=0.4)
    particles = sinter.Particles(ctx)
    particles.set_material(0, glass)
    walls = sinter.Walls(ctx)
    for point, normal in (((0, 0, 0), (0, 0, 1)), ((0, 0, 0), (1, 0, 0)),
                          ((BOX[0], 0, 0), (-1, 0, 0)), ((0, 0, 0), (0, 1, 0)),
                          ((0, BOX[1], 0), (0, -1, 0))):
        walls.add_plane(point, normal, glass)
    if fill:
        jitter = random.Random(7)
        points = [(SPACING * (i + 0.5) + 1e-5 * (jitter.random() - 0.5),
                   SPACING * (j + 0.5) + 1e-5 * (jitter.random() - 0.5),
                   RADIUS + SPACING * k) for k in range(NZ) for j in range(NY) for i in range(NX)]
        particles.add(points, RADIUS, ids=range(1, len(points) + 1))
    stepper = sinter.Stepper(ctx, particles, walls, dt=DT, skin=5e-5,
                             forces=[sinter.ForceModel(ctx, "gravity"),
                                     sinter.ForceModel(ctx, "hertz_mindlin")])
    return particles, walls, stepper


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--out", default=".", help="folder of the checkpoint")
    parser.add_argument("--steps", type=int, default=2000)
    parser.add_argument("--report", type=int, default=500, help="steps between reports")
    parser.add_argument("--balance", action="store_true",
                        help="a bisection rebalanced at the rebuilds instead of a brick")
    args = parser.parse_args(argv)
    if not sinter.mpi.available():
        print("mpi_bed: needs mpi4py and libsinter_mpi (-DSINTER_MPI=ON); nothing run")
        return 0
    from mpi4py import MPI

    comm = MPI.COMM_WORLD
    kind = sinter.mpi.DecompKind.RCB if args.balance else sinter.mpi.DecompKind.BRICK
    # the brick: slabs across x (a brick chosen by area would cut the tall box across z,
    # above the bed); the bisection cuts where the particles are
    with sinter.Context(threads=1) as ctx, \
            sinter.mpi.Domain(comm, (0.0, 0.0, 0.0), BOX, decomposition=kind,
                              grid=(comm.size, 1, 1)) as domain:
        particles, walls, stepper = setup(ctx, fill=comm.rank == 0)
        domain.attach(stepper, particles)
        domain.distribute()
        if comm.rank == 0:
            print("%d ranks, %s, %d particles" % (comm.size, kind.name.lower(), NX * NY * NZ))
            print("   time [s]  max speed [m/s]  floor force [N]  owned min-max  ghosts  "
                  "kB/step  messages/step  migrated")
        done, last = 0, domain.exchange_stats()
        while done < args.steps:
            n = min(args.report, args.steps - done)
            stepper.step(n)
            done += n
            now = domain.exchange_stats()
            speed = max((sum(c * c for c in v) ** 0.5 for v in
                         particles.get("velocity")[:particles.owned_count]), default=0.0)
            speed = domain.reduce([speed], op=sinter.domain.ReduceOp.MAX)[0]
            figures = comm.allgather((now.owned, now.ghosts, now.bytes_sent - last.bytes_sent,
                                      now.messages_sent - last.messages_sent,
                                      now.migrated_out - last.migrated_out))
            if comm.rank == 0:
                owned = [f[0] for f in figures]
                print("%11.4g  %15.4g  %15.6g  %6d-%-6d  %6d  %7.1f  %13.1f  %8d" % (
                    stepper.time, speed, walls.force(0)[2], min(owned), max(owned),
                    sum(f[1] for f in figures), sum(f[2] for f in figures) / 1024.0 / n,
                    sum(f[3] for f in figures) / n, sum(f[4] for f in figures)))
            last = now
        os.makedirs(args.out, exist_ok=True)
        path = os.path.join(args.out, "mpi_bed.ckpt")
        sinter.mpi.checkpoint_write(stepper, particles, comm, path)
        if comm.rank == 0:
            print("checkpoint: %s (restartable on any number of ranks)" % path)
        stepper.close()
    return 0


if __name__ == "__main__":
    sys.exit(main())
