#!/usr/bin/env bash
# speedup_table.sh -- libsinter's 2-thread speed-up on the packed bed of the peer benchmark,
# measured by alternating blocks of steps in one run (peer_bench --alternate): one thread, then
# two, then two, then one, ... each block ~50-150 ms. On a host whose speed moves by up to 60 %
# within minutes (RESULTS.md, issue 9, sessions 18-19), separate 1- and 2-thread runs give a
# ratio of two draws from different minutes; neighbouring blocks share the host's minute. The
# run is one simulation (the same bits on any thread count), so its SANITY / THERMAL lines are
# the peer harness's and the error level is peer_table.sh's. Prints one line per cell: the
# ratio of the summed times, the median of the block pairs' ratios and their range.
#
#   tests/bench/speedup_table.sh                       # every packed-bed cell (~5 min)
#   CELLS="thermal:20:100:40000:1" tests/bench/speedup_table.sh
#
# Settings (environment, defaults in brackets):
#   BUILD [build]   PEERS_DIR (required: the peer benchmark's folder, not in this repository)   DATA [/tmp/peer_data]   THREADS [2]
#   CELLS: scene:n:block:steps:heat ... (N = n^3; steps in all, half on each side)
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
BUILD="$(cd "${BUILD:-$ROOT/build}" && pwd)"
: "${PEERS_DIR:?set PEERS_DIR to the folder of the peer benchmark, not in this repository}"
PEERS_DIR="$(cd "$PEERS_DIR" && pwd)"
DATA="${DATA:-/tmp/peer_data}"
THREADS="${THREADS:-2}"
CELLS="${CELLS:-thermal:10:500:200000:1 thermal:20:100:40000:1 thermal:40:10:2000:1
thermal:80:2:200:1 thermal:100:1:80:1 thermal:10:500:200000:0 thermal:20:100:40000:0
thermal:40:10:2000:0 thermal:80:2:200:0 thermal:100:1:80:0}"
mkdir -p "$DATA"
cd "$DATA"
echo "# $(date -u '+%F %T') UTC, libsinter $(git -C "$ROOT" rev-parse --short HEAD), build $BUILD," \
     "load $(cut -d' ' -f1-3 /proc/loadavg)"
echo "# CPU: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ *//'), $(nproc) cores"
for cell in $CELLS; do
  IFS=: read -r scene n block steps heat <<< "$cell"
  base="${scene}_n$n"
  [ -f "$base.xyz" ] || python3 "$PEERS_DIR/gen_lattice.py" --scene "$scene" --n "$n" --out "$DATA" > /dev/null
  line=$(LD_LIBRARY_PATH="$BUILD/lib" "$BUILD/bin/peer_bench" --scene "$scene" --xyz "$base.xyz" \
           --box "$base.box" --steps "$steps" --dt 1e-5 --heat "$heat" --threads "$THREADS" \
           --alternate "$block" | grep '^ALTERNATE')
  echo "$scene n=$n N=$((n * n * n)) heat=$heat ${line#ALTERNATE } $(date -u +%T)"
done
