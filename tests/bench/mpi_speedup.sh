#!/usr/bin/env bash
# mpi_speedup.sh -- libsinter_mpi's np 2 speed-up on the peer benchmark's 64k packed bed
# (build/bin/mpi_packed_bed), measured by runs at np 1 and np 2 by turns in the same minutes:
# round k runs np 1 then np 2 (odd k: np 2 first), so that a slow minute of a shared host
# slows both sides of a pair. Prints each run's TIME line, then per round the ratio of the
# wall times per step (np 1 / np 2) and of the CPU seconds per step (summed over the ranks:
# np 2's cost over np 1's), and over the rounds their median, range, mean and standard
# deviation; the load averages (1 min) at the start and end.
#
#   tests/bench/mpi_speedup.sh                  # 6 rounds of 200 steps, heat on (~5-15 min)
#   ROUNDS=4 STEPS=100 HEAT=0 tests/bench/mpi_speedup.sh
#
# Settings (environment, defaults in brackets): BUILD [build] ROUNDS [6] STEPS [200] N [40]
# HEAT [1] MPIEXEC [mpiexec --oversubscribe] WRAP [] (a command before the program on every rank,
# e.g. "setsid -w": each rank in its own session, so its own scheduler autogroup)
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
BUILD="$(cd "${BUILD:-$ROOT/build}" && pwd)"
ROUNDS="${ROUNDS:-6}"
STEPS="${STEPS:-200}"
N="${N:-40}"
HEAT="${HEAT:-1}"
MPIEXEC="${MPIEXEC:-mpiexec --oversubscribe}"
WRAP="${WRAP:-}"
echo "# $(date -u '+%F %T') UTC, libsinter $(git -C "$ROOT" rev-parse --short HEAD), build $BUILD," \
     "load $(cut -d' ' -f1-3 /proc/loadavg), autogroups $(cat /proc/sys/kernel/sched_autogroup_enabled 2>/dev/null || echo ?)," \
     "MPIEXEC=$MPIEXEC WRAP=$WRAP"
echo "# CPU: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ *//'), $(nproc) cores"
run() { # np -> "wall cpu" on stdout, the program's lines on stderr
  local out
  # shellcheck disable=SC2086 # MPIEXEC and WRAP are split into words on purpose
  out=$(LD_LIBRARY_PATH="$BUILD/lib" $MPIEXEC -n "$1" $WRAP "$BUILD/bin/mpi_packed_bed" \
          --n "$N" --steps "$STEPS" --heat "$HEAT")
  echo "$out" >&2
  echo "$out" | awk '/^TIME/ {
      for (i = 2; i <= NF; ++i) { split($i, kv, "="); v[kv[1]] = kv[2] }
      print v["wall_per_step"], v["cpu_per_step_sum"] }'
}
ratios=""
for ((k = 0; k < ROUNDS; ++k)); do
  if ((k % 2 == 0)); then a=$(run 1); b=$(run 2); else b=$(run 2); a=$(run 1); fi
  line=$(echo "$a $b" | awk '{ printf "%.4f %.4f %s %s %s %s", $1 / $3, $4 / $2, $1, $2, $3, $4 }')
  echo "ROUND $k np1 wall/step $(echo "$a" | cut -d' ' -f1) s, np2 $(echo "$b" | cut -d' ' -f1) s:" \
       "speed-up $(echo "$line" | cut -d' ' -f1), CPU np2/np1 $(echo "$line" | cut -d' ' -f2)," \
       "load $(cut -d' ' -f1 /proc/loadavg), $(date -u +%T)"
  ratios="$ratios$line"$'\n'
done
printf '%s' "$ratios" | sort -g | awk -v n3="$((N * N * N))" '
  { s[NR] = $1; sum += $1; sq += $1 * $1; csum += $2; w1 += $3; c1 += $4; c1q += $4 * $4; w2 += $5; c2 += $6 }
  END { n = NR; med = n % 2 ? s[(n + 1) / 2] : 0.5 * (s[n / 2] + s[n / 2 + 1]);
        sd = n > 1 ? sqrt((sq - sum * sum / n) / (n - 1)) : 0;
        c1sd = n > 1 ? sqrt((c1q - c1 * c1 / n) / (n - 1)) : 0;
        printf "SPEEDUP rounds=%d median=%.3f range=%.3f-%.3f mean=%.3f sd=%.3f cpu_np2_over_np1_mean=%.3f\n",
               n, med, s[1], s[n], sum / n, sd, csum / n;
        printf "MEANS np1 wall/step %.4g s, CPU/step %.4g +- %.2g s (%.4g us CPU per particle-step);" \
               " np2 wall/step %.4g s, CPU/step (both ranks) %.4g s\n",
               w1 / n, c1 / n, c1sd, 1e6 * c1 / n / n3, w2 / n, c2 / n }'
echo "# end $(date -u '+%F %T') UTC, load $(cut -d' ' -f1-3 /proc/loadavg)"
