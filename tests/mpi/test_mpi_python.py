"""sinter.mpi under mpiexec (issue 44): a Python host hands libsinter_mpi an mpi4py
communicator. Run as `mpiexec -n NP python3 test_mpi_python.py`; exits 77 (skipped) without
mpi4py or libsinter_mpi.

The bed of tests/mpi/test_mpi_attach.c built from Python: 288 spheres on a jittered lattice
(Hertz-Mindlin with friction, damping and rolling resistance, gravity, conduction, five walls,
a small skin so that the neighbour lists are rebuilt every few steps), on a brick of x slabs
whose borders lie on columns of the lattice, so that particles jiggling about them migrate.
Rank 0 fills the set alone and Domain.distribute hands the particles to their ranks.

 - np 1: the same bits as the serial Python run without domain operations (the domain's
   exchanges are with no one: nothing is summed in another order).
 - np >= 2: every particle owned once; displacements, velocities, spins, temperature changes,
   wall forces and the conduction's energy within 1e-10 relative of the serial run (pairs
   across a border are summed in another order: round-off grown by 150 steps of stiff
   contacts, the C test's tolerance); migrations happened, ghosts exist, the bytes sent over
   all ranks equal those received.
 - A checkpoint written through MPI-IO on np ranks at step 75, read on one rank (rank 0 over
   MPI.COMM_SELF, a brick of one part), holds every particle with the bits the writers held,
   at the writers' time; continued serially to step 150 it stays within 1e-10 of the straight
   serial run (a restart reorders the particles: sums in another order).
 - The small wrappers: rank, size, the duplicated communicator, reduce, exscan, sum (spread
   over the ranks, the bits of the same terms on one rank), a brick's boxes and owners, a
   bisection of points spread over the ranks equal to the one of all of them on one caller,
   loads, balance (a set all in part 0 has imbalance np and is bisected), the counters, and
   errors raised on every rank alike (a missing checkpoint, a bad threshold, a brick's grid
   asked of a bisection, not a communicator).
"""

import math
import os
import shutil
import sys
import tempfile

try:
    from mpi4py import MPI
except ImportError:
    print("SKIP: mpi4py is not installed for this interpreter")
    sys.exit(77)

import sinter
import sinter.mpi

if not sinter.mpi.available():
    print("SKIP: libsinter_mpi is not built (-DSINTER_MPI=ON)")
    sys.exit(77)

NX, NY, NZ = 8, 6, 6
N = NX * NY * NZ
STEPS, HALF = 150, 75
R, A = 1e-3, 1.97e-3  # radius and lattice spacing [m]: 1.5 % overlap
LX = R + A * (NX - 1) + 0.99 * R
LY = R + A * (NY - 1) + 0.99 * R
X0, X1 = R - 2 * A, R + 10 * A  # slabs: every border of 1-4 equal ones on a lattice column
DT = 2e-6
TOL = 1e-10

comm = MPI.COMM_WORLD
failures = []


def expect(condition, what):
    if not condition:
        failures.append("rank %d: %s" % (comm.rank, what))


def lcg(state=[43]):  # noqa: B006 (the generator's state)
    state[0] = (state[0] * 6364136223846793005 + 1442695040888963407) % (1 << 64)
    return (state[0] >> 11) / 9007199254740992.0


def make_bed():
    bed = {"x": [], "v": [], "w": [], "temp": [], "id": []}
    for k in range(N):
        i, j, l = k % NX, (k // NX) % NY, k // (NX * NY)
        bed["x"].append((R + A * i + 0.01 * R * (lcg() - 0.5),
                         R + A * j + 0.01 * R * (lcg() - 0.5),
                         0.99 * R + A * l + 0.01 * R * (lcg() - 0.5)))
        v, w = [], []
        for _ in range(3):
            v.append(0.04 * (lcg() - 0.5))
            w.append(20.0 * (lcg() - 0.5))
        bed["v"].append(tuple(v))
        bed["w"].append(tuple(w))
        bed["temp"].append(300.0 + 100.0 * lcg())
        bed["id"].append(1 + (k * 37) % N)
    return bed


BED = make_bed()


class Run:
    """One rank's set-up of the bed: the whole of it (fill = True) or an empty set."""

    def __init__(self, fill):
        self.ctx = sinter.Context(threads=1)
        mat = sinter.Material(self.ctx, "bed", youngs_modulus=1e7, poisson_ratio=0.3,
                              density=2500.0, damping_ratio=0.3, friction_static=0.5,
                              friction_dynamic=0.5, rolling_friction=0.1,
                              thermal_conductivity=400.0, heat_capacity=400.0)
        self.ps = sinter.Particles(self.ctx)
        self.ps.set_material(0, mat)
        self.walls = sinter.Walls(self.ctx)
        for point, normal in (((0, 0, 0), (0, 0, 1)), ((0, 0, 0), (1, 0, 0)),
                              ((LX, 0, 0), (-1, 0, 0)), ((0, 0, 0), (0, 1, 0)),
                              ((0, LY, 0), (0, -1, 0))):
            self.walls.add_plane(point, normal, mat)
        if fill:
            self.ps.add(BED["x"], R, ids=BED["id"])
            self.ps.set("velocity", BED["v"])
            self.ps.set("spin", BED["w"])
            self.ps.set("temperature", BED["temp"])
        self.stepper = sinter.Stepper(
            self.ctx, self.ps, self.walls, dt=DT, skin=1e-5, options={"thread_choice": 0},
            forces=[sinter.ForceModel(self.ctx, "gravity"),
                    sinter.ForceModel(self.ctx, "hertz_mindlin")],
            heat=[sinter.HeatModel(self.ctx, "conduction")])

    def owned(self):
        """{id: (x, v, w, T)} of this rank's owned particles."""
        n = self.ps.owned_count
        if n == 0:
            return {}
        fields = [self.ps.get(f) for f in ("id", "position", "velocity", "spin",
                                           "temperature")]
        return {int(fields[0][i]): tuple(tuple(float(c) for c in f[i]) if d < 3 else
                                         float(f[i]) for d, f in enumerate(fields[1:]))
                for i in range(n)}

    def close(self):
        self.ctx.close()


def gathered(owned):
    """Every rank's owned particles on every rank, and how often each id was seen."""
    merged, seen = {}, {}
    for part in comm.allgather(owned):
        for k, value in part.items():
            merged[k] = value
            seen[k] = seen.get(k, 0) + 1
    return merged, seen


def rel_diff(a, b):
    d = max(abs(x - y) for x, y in zip(a, b))
    m = max(abs(y) for y in b)
    return d / m if m > 0 else d


def compare(label, got, ref, exact):
    """got and ref: {id: (x, v, w, T)}; displacements and temperature changes by id."""
    start = {BED["id"][k]: (BED["x"][k], BED["temp"][k]) for k in range(N)}
    ids = sorted(ref)
    columns = {
        "displacement": lambda s, i: [s[i][0][d] - start[i][0][d] for d in range(3)],
        "velocity": lambda s, i: list(s[i][1]),
        "spin": lambda s, i: list(s[i][2]),
        "temperature change": lambda s, i: [s[i][3] - start[i][1]],
    }
    for name, column in columns.items():
        a = [c for i in ids for c in column(got, i)]
        b = [c for i in ids for c in column(ref, i)]
        if exact:
            expect(a == b, "%s: %s not the same bits" % (label, name))
        else:
            diff = rel_diff(a, b)
            expect(diff <= TOL, "%s: %s differs by %.3g relative" % (label, name, diff))


def serial(steps):
    run = Run(fill=True)
    run.stepper.step(steps)
    result = (run.owned(), [run.walls.force(k) for k in range(5)],
              run.stepper.heat_energy(0))
    run.close()
    return result


def small_wrappers(dom):
    expect((dom.rank, dom.size) == (comm.rank, comm.size), "rank and size")
    own = dom.comm
    expect(own.Get_size() == comm.size and own.Get_rank() == comm.rank, "the domain's comm")
    expect(MPI.Comm.Compare(own, comm) == MPI.CONGRUENT, "a duplicate of the communicator")
    expect(dom.reduce([comm.rank + 1.0, -comm.rank], sinter.domain.ReduceType.F64,
                      sinter.domain.ReduceOp.MAX) == [float(comm.size), 0.0], "reduce MAX")
    n = comm.size
    expect(dom.reduce([comm.rank + 1], sinter.domain.ReduceType.I64) == [n * (n + 1) // 2],
           "reduce I64 SUM")
    expect(dom.exscan(comm.rank + 1) == (comm.rank * (comm.rank + 1) // 2, n * (n + 1) // 2),
           "exscan")
    # ten terms spread over the ranks, then all on rank 0: the same bits (integer limbs)
    terms = [0.1 * (k + 1) * (-1) ** k for k in range(10)]
    spread = dom.sum(terms[comm.rank::n])
    alone = dom.sum(terms if comm.rank == 0 else [])
    expect(spread == alone, "sum: %r spread, %r on one rank" % (spread, alone))
    expect(abs(spread - math.fsum(terms)) <= 1e-15, "sum: %r" % spread)
    decomp = dom.decomposition
    expect(decomp.kind == sinter.mpi.DecompKind.BRICK and decomp.parts == n, "decomposition")
    expect(decomp.grid == (n, 1, 1), "a slab brick: %r" % (decomp.grid,))
    lo, hi = decomp.box(comm.rank)
    width = (X1 - X0) / n
    expect(abs(lo[0] - (X0 + comm.rank * width)) < 1e-15 and
           abs(hi[0] - (X0 + (comm.rank + 1) * width)) < 1e-15, "the box of this part")
    expect(decomp.owners([(X0 - 1.0, 0, 0), (X1 + 1.0, 0, 0)]) == [0, n - 1], "owners")
    # a bisection of points spread over the ranks equals the one of all of them on one
    # caller (the parts depend on the set of points only), and so do the loads
    points = [(X0 + (X1 - X0) * ((7 * k) % 23) / 23.0, 1e-3 * (k % 5), 2e-3 * (k % 3))
              for k in range(40)]
    weights = [1.0 + k % 4 for k in range(40)]
    mine = range(comm.rank, 40, n)
    lo_hi = ((X0, 0.0, 0.0), (X1, LY, 0.02))
    alone = sinter.mpi.Decomposition.rcb(n, *lo_hi, points, weights)
    spread = sinter.mpi.Decomposition.rcb(n, *lo_hi, [points[k] for k in mine],
                                          [weights[k] for k in mine], domain=dom)
    expect(spread.kind == sinter.mpi.DecompKind.RCB, "a bisection")
    expect([spread.box(p) for p in range(n)] == [alone.box(p) for p in range(n)],
           "a collective bisection equals the one of all points")
    loads = spread.loads([points[k] for k in mine], [weights[k] for k in mine], domain=dom)
    expect(loads == alone.loads(points, weights), "collective loads")
    expect(abs(sum(loads) - sum(weights)) == 0.0, "the loads sum the weights")
    expect(sinter.mpi.imbalance([1.0, 1.0, 2.0]) == 1.5, "imbalance")
    # rebalanced exactly when the imbalance exceeds the threshold (1.1 by default)
    before, replaced = dom.balance([points[k] for k in mine])
    expect(before >= 1.0 and replaced == (before > 1.1), "balance: %r %r" % (before, replaced))
    if n > 1:
        skewed = [(X0, 0.0, 0.0)] * 10 if comm.rank == 0 else []  # all in part 0
        before, replaced = dom.balance(skewed)
        expect(before == float(n) and replaced, "balance of a skewed set: %r" % before)
        expect(dom.decomposition.kind == sinter.mpi.DecompKind.RCB, "a bisection now")
        expect(dom.stats().rebalances >= 1, "rebalances counted")
    # errors: raised alike on every rank, nothing hangs
    raised = []
    for what, call in (
            ("grid of a bisection", lambda: alone.grid),
            ("threshold below 1", lambda: sinter.mpi.Domain(comm, balance_threshold=0.5)),
            ("not a communicator", lambda: sinter.mpi.comm_handle(42)),
            ("a missing checkpoint", lambda: missing_checkpoint(dom))):
        try:
            call()
            raised.append("%s: nothing raised" % what)
        except (sinter.SinterError, TypeError) as err:
            raised.append("%s: %s" % (what, type(err).__name__))
    expect(raised == ["grid of a bisection: SinterError",
                      "threshold below 1: InvalidArgument",
                      "not a communicator: TypeError",
                      "a missing checkpoint: SinterError"], "errors: %r" % raised)
    alone.close()
    spread.close()
    expect(dom.stats().reductions >= 4, "the reduction counters")


def missing_checkpoint(dom):
    run = Run(fill=False)
    try:
        sinter.mpi.checkpoint_read(run.stepper, run.ps, comm, "/nonexistent/sinter.ckpt",
                                   dom.decomposition)
    finally:
        run.close()


def mpi_run(steps, path=None):
    """The bed through sinter.mpi on every rank of comm (rank 0 fills, distribute)."""
    run = Run(fill=comm.rank == 0)
    with sinter.mpi.Domain(comm, (X0, 0.0, 0.0), (X1, LY, 0.02), grid=(comm.size, 1, 1)) as dom:
        dom.attach(run.stepper, run.ps)
        dom.distribute()
        run.stepper.step(steps)
        xs = dom.exchange_stats()
        if path is not None:
            sinter.mpi.checkpoint_write(run.stepper, run.ps, comm, path)
        result = (run.owned(), [run.walls.force(k) for k in range(5)],
                  sinter.domain.heat_energy_global(run.stepper, 0), xs)
    run.close()
    return result


def main():
    exact = comm.size == 1
    label = "np %d" % comm.size
    with sinter.mpi.Domain(comm, (X0, 0.0, 0.0), (X1, LY, 0.02), grid=(comm.size, 1, 1)) as dom:
        small_wrappers(dom)  # (on a domain of its own: it rebalances)
    ref, ref_walls, ref_energy = serial(STEPS)

    owned, walls, energy, xs = mpi_run(STEPS)
    got, seen = gathered(owned)
    expect(sorted(seen) == sorted(BED["id"]) and set(seen.values()) == {1},
           "every particle owned once")
    compare(label, got, ref, exact)
    wall_ref = [c for f in ref_walls for c in f]
    wall_got = [c for f in walls for c in f]
    if exact:
        expect(wall_got == wall_ref and energy == ref_energy, "walls and energy: bits")
    else:
        expect(rel_diff(wall_got, wall_ref) <= TOL, "wall forces")
        expect(abs(energy - ref_energy) <= TOL * abs(ref_energy), "conduction energy")
    expect(len({tuple(w) for w in comm.allgather(wall_got)}) == 1, "walls: bits on every rank")
    mine = [xs.bytes_sent, xs.bytes_received, xs.migrated_in, xs.ghosts]
    sums = [sum(t[k] for t in comm.allgather(mine)) for k in range(4)]
    expect(sums[0] == sums[1], "bytes sent %d, received %d" % (sums[0], sums[1]))
    expect(xs.redistributions > 2, "neighbour lists rebuilt: %d" % xs.redistributions)
    if comm.size > 1:
        expect(sums[2] > 0 and sums[3] > 0, "migrations %d, ghosts %d" % (sums[2], sums[3]))

    # a checkpoint written on np ranks at step 75, read on one
    folder = comm.bcast(tempfile.mkdtemp(prefix="sinter_pympi_") if comm.rank == 0 else None)
    path = os.path.join(folder, "half.ckpt")
    owned, _, _, _ = mpi_run(HALF, path)
    written, _ = gathered(owned)
    if comm.rank == 0:
        run = Run(fill=False)
        one = sinter.mpi.Decomposition.brick(1, (X0, 0.0, 0.0), (X1, LY, 0.02))
        count = sinter.mpi.checkpoint_read(run.stepper, run.ps, MPI.COMM_SELF, path, one)
        expect(count == N, "read %d particles" % count)
        expect(run.owned() == written, "the checkpoint holds the writers' bits")
        expect(abs(run.stepper.time - HALF * DT) <= 1e-15, "the time read")
        run.stepper.step(STEPS - HALF)
        compare("restart np %d -> 1" % comm.size, run.owned(), ref, exact=False)
        one.close()
        run.close()
        shutil.rmtree(folder)

    everything = comm.allgather(failures)
    if comm.rank == 0:
        for lines in everything:
            for line in lines:
                print("FAIL", line)
        print("%s: %s" % (label, "ok" if not any(everything) else "failed"))
    return 1 if any(everything) else 0


if __name__ == "__main__":
    sys.exit(main())
