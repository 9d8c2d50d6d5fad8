#!/usr/bin/env python3
"""A written estimate (issue 44) of a packed bed of N spheres on P MPI ranks through
libsinter_mpi, from the measured cost per particle-step at np 1 and the communication model
that mpi_packed_bed's counters confirmed on 2 to 16 ranks (RESULTS.md, "The packed bed through
libsinter_mpi"). Prints one row per P: time per step and its parts, parallel efficiency.

Per rank: n = N / P spheres in a cube of m = n^(1/3) lattice spacings s; the ghosts are the
spheres within the cut-off c of it (continuum, k = c / s): g = 6 m^2 k + 3 pi m k^2 + 4/3 pi k^3
(faces, edges, corners of the cube's Minkowski sum with a ball of radius c). Each step:
  compute   t_p n                      (t_p: the measured seconds per particle-step at np 1)
  ghost     f t_p g / 2                (pairs across a border are evaluated on both sides,
                                        Newton's third law off; f: the force share of a step)
  halo      H (26 a + 104 g / b_mem)   (H forward halos of 13 doubles, 26 neighbours; within
                                        a node the bytes are copied through memory)
  network   H (104 G / b_nic)          (the node's ranks share its NIC; G: the ghosts of the
                                        node's block of R ranks, a cube of R^(1/3) ranks a side)
  reduce    r a log2(P)                (r MPI_Allreduce of a few hundred bytes per step;
                                        recursive doubling: log2 P latencies, Thakur,
                                        Rabenseifner and Gropp 2005)
Efficiency: compute / (compute + ghost + halo + network + reduce). Nothing overlaps (the
attach's exchanges are blocking). Rebuild traffic (144-byte ghost records and migrations at
a neighbour-list rebuild, every tens to hundreds of steps in a packed bed) is left out: at
one rebuild per 50 steps it adds 144 g / 50 bytes a step, 1.4 % of the halos' 208 g.

  python3 tests/bench/mpi_scaling_estimate.py [--tp 1.0e-7] [--n 1e8] [--alpha 1.5e-6] ...
"""
import argparse
import math


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--n", type=float, default=1e8, help="spheres")
    ap.add_argument("--tp", type=float, default=1.0e-7, help="s per particle-step at np 1")
    ap.add_argument("--k", type=float, default=1.1, help="ghost cut-off over the spacing")
    ap.add_argument("--force-share", type=float, default=0.6, help="force phase of a step")
    ap.add_argument("--halos", type=int, default=2, help="forward halos per step")
    ap.add_argument("--reductions", type=int, default=7, help="MPI_Allreduce per step")
    ap.add_argument("--alpha", type=float, default=1.5e-6, help="MPI latency across nodes, s")
    ap.add_argument("--alpha-node", type=float, default=0.4e-6, help="latency within a node, s")
    ap.add_argument("--nic", type=float, default=25e9, help="a node's NIC, bytes/s")
    ap.add_argument("--mem", type=float, default=3e9, help="memory copy per rank, bytes/s")
    ap.add_argument("--ranks-per-node", type=int, default=64)
    ap.add_argument("--ranks", default="64,128,256,512,1024,4096,16384")
    a = ap.parse_args()
    print(f"# N={a.n:.3g} t_p={a.tp * 1e6:.3g} us k={a.k} H={a.halos} r={a.reductions} "
          f"alpha={a.alpha * 1e6:.2g} us (node {a.alpha_node * 1e6:.2g} us) "
          f"NIC={a.nic / 1e9:.3g} GB/s mem={a.mem / 1e9:.3g} GB/s/rank R={a.ranks_per_node}")
    print("| P | spheres/rank | ghosts/rank | compute ms | ghost work ms | halo ms | "
          "network ms | reductions ms | step ms | efficiency |")
    print("|---|---|---|---|---|---|---|---|---|---|")

    def ghosts(m):
        k = a.k
        return 6 * m * m * k + 3 * math.pi * m * k * k + 4 / 3 * math.pi * k ** 3

    for p in (int(x) for x in a.ranks.split(",")):
        n = a.n / p
        m = n ** (1 / 3)
        g = ghosts(m)
        nodes = max(1, p // a.ranks_per_node)
        alpha = a.alpha if nodes > 1 else a.alpha_node
        compute = a.tp * n
        ghost = a.force_share * a.tp * g / 2
        halo = a.halos * (26 * alpha + 104 * g / a.mem)
        side = min(p, a.ranks_per_node) ** (1 / 3)
        network = a.halos * 104 * ghosts(m * side) / a.nic if nodes > 1 else 0.0
        reduce = a.reductions * alpha * math.log2(p)
        step = compute + ghost + halo + network + reduce
        print(f"| {p} | {n:.3g} | {g:.3g} ({100 * g / n:.1f} %) | {compute * 1e3:.3g} | "
              f"{ghost * 1e3:.3g} | {halo * 1e3:.3g} | {network * 1e3:.3g} | "
              f"{reduce * 1e3:.3g} | {step * 1e3:.3g} | {compute / step:.2f} |")


if __name__ == "__main__":
    main()
