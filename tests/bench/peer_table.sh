#!/usr/bin/env bash
# peer_table.sh -- libsinter against LIGGGHTS and LAMMPS on the canonical scenes of
# the peer benchmark (kept outside this repository: $PEERS_DIR), one cell at a time and interleaved (the peers and libsinter's
# single-thread run pinned to one core, then libsinter on two threads), so that each ratio
# comes from the same minutes. Prints one line per run: the programs' "Loop time" [s] and
# libsinter's peak resident memory [kB], and the round trip of a cache line between the two
# cores before and after the 2-thread run (rt_ns, core_latency.c: the 2-thread times follow
# it). RESULTS.md, "Performance (issue 9)", sessions 4 and 8.
#
#   tests/bench/peer_table.sh                     # every cell, two runs each (~10 min)
#   CELLS="thermal:40:500:1" REPS=3 tests/bench/peer_table.sh
#   tests/bench/peer_table.sh > t.txt; tests/bench/peer_summary.sh t.txt  # best of the runs
#
# Settings (environment, defaults in brackets):
#   BUILD [build]         libsinter's build directory (bin/peer_bench, lib/)
#   PEERS_DIR (required)  the peer benchmark's folder (its LIGGGHTS and LAMMPS decks,
#                         gen_lattice.py, run_peers.sh), which is not in this repository
#   DATA [/tmp/peer_data] lattices, made with gen_lattice.py when missing
#   REPS [2]  PIN [1] (core for the single-thread runs)
#   LIG2 [0]  1: LIGGGHTS also on two MPI ranks (mpirun -np 2, Open MPI), after its one-rank
#             run, printed as liggghts2= (its 2-core speed-up beside ours, session 23)
#   CELLS: scene:n:steps:heat ... (N = n^3); LAMMPS runs the mechanics (heat 0) only, as this
#          LAMMPS has no heat conduction: in.mech on the packed lattice is the packed bed
#          without heat.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
BUILD="$(cd "${BUILD:-$ROOT/build}" && pwd)"
: "${PEERS_DIR:?set PEERS_DIR to the folder of the peer benchmark, not in this repository}"
PEERS_DIR="$(cd "$PEERS_DIR" && pwd)"
DATA="${DATA:-/tmp/peer_data}"
REPS="${REPS:-2}"
PIN="${PIN:-1}"
LIG2="${LIG2:-0}"
CELLS="${CELLS:-thermal:10:20000:1 thermal:20:4000:1 thermal:40:500:1 thermal:80:100:1
thermal:100:100:1 thermal:10:20000:0 thermal:20:4000:0 thermal:40:500:0 thermal:80:100:0
thermal:100:100:0 mech:10:20000:0 mech:20:4000:0 mech:40:2000:0}"
mkdir -p "$DATA"
cd "$DATA"
loop_time() { grep 'Loop time' "$1" | awk '{print $4}'; }
# the round trip of a cache line between the two cores [ns], before and after the 2-thread
# run (rt_ns): 60-80 ns with both on one die, ~350 ns on two (core_latency.c)
round_trip() { "$BUILD/bin/core_latency" 0 1 100000 | awk '{print $(NF-1)}'; }
echo "# $(date -u '+%F %T') UTC, libsinter $(git -C "$ROOT" rev-parse --short HEAD), build $BUILD," \
     "load $(cut -d' ' -f1-3 /proc/loadavg)"
echo "# CPU: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ *//'), $(nproc) cores"
for cell in $CELLS; do
  IFS=: read -r scene n steps heat <<< "$cell"
  base="${scene}_n$n"
  [ -f "$base.xyz" ] || python3 "$PEERS_DIR/gen_lattice.py" --scene "$scene" --n "$n" --out "$DATA" > /dev/null
  L=$(awk '{print $2}' "$base.box")
  for _ in $(seq "$REPS"); do
    taskset -c "$PIN" liggghts -nocite -echo none -screen none -log lig.log \
      -in "$PEERS_DIR/liggghts/in.$scene" -var data "$base.lmp" -var L "$L" -var steps "$steps" \
      -var dt 1e-5 -var heat "$heat"
    lig=$(loop_time lig.log)
    lig2=
    if [ "$LIG2" = 1 ]; then
      mpirun --allow-run-as-root -np 2 liggghts -nocite -echo none -screen none -log lig2.log \
        -in "$PEERS_DIR/liggghts/in.$scene" -var data "$base.lmp" -var L "$L" -var steps "$steps" \
        -var dt 1e-5 -var heat "$heat" > /dev/null
      lig2=" liggghts2=$(loop_time lig2.log)"
    fi
    lmp_t=-
    if [ "$heat" = 0 ]; then
      OMP_NUM_THREADS=1 taskset -c "$PIN" lmp -nocite -echo none -screen none -log lmp.log \
        -in "$PEERS_DIR/lammps/in.mech" -var data "$base.lmp" -var L "$L" -var steps "$steps" \
        -var dt 1e-5
      lmp_t=$(loop_time lmp.log)
    fi
    run() { # threads, pinning
      LD_LIBRARY_PATH="$BUILD/lib" $2 "$BUILD/bin/peer_bench" --scene "$scene" --xyz "$base.xyz" \
        --box "$base.box" --steps "$steps" --dt 1e-5 --heat "$heat" --threads "$1" --stats \
        > sinter.log 2> sinter.stats
      echo "$(loop_time sinter.log) $(grep peak_rss sinter.stats | awk '{print $3}')"
    }
    read -r one rss1 <<< "$(run 1 "taskset -c $PIN")"
    rt0=$(round_trip)
    read -r two rss2 <<< "$(run 2 "")"
    echo "$scene n=$n N=$((n * n * n)) steps=$steps heat=$heat liggghts=$lig$lig2 lammps=$lmp_t" \
         "one=$one two=$two rss1_kB=$rss1 rss2_kB=$rss2 rt_ns=$rt0/$(round_trip) $(date -u +%T)"
  done
done
