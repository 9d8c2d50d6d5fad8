#!/bin/sh
# The quasi-static stepper's strategy cost over whole runs (issue 42): strategies 1, 2 and 3
# (3 is the library's own addition, not in seed 001) at the same neck tolerance qs_rtol, on
# copper packings of increasing size (seed 001 sec. 4.1's green body: N spheres placed in a box
# scaled by 1.5 (N / 805)^(1/3), then compacted towards green density 0.6), sintered at 1293 K
# from t = 0 to END. Each packing's reference is strategy 3 at rtol 1e-8; qs_strategies prints every run's CPU seconds, global
# steps and its neck and shrinkage errors against it, so the costs can be read at matched
# tolerance and at matched error. Seed 001 reports strategy 1 about two orders of magnitude
# slower than strategy 2; RESULTS.md's earlier "80 times" was the first second of the 805 packing.
#
#   tests/bench/qs_strategy_cost.sh BUILD_DIR [SIZES] [END] [RTOL]
#
# SIZES default "27 54 108 216", END 5000 s (seed 001's copper run), RTOL 1e-4.
# qs_strategies --make-packing has one fixed random seed, so an ensemble takes packings of
# neighbouring sizes (e.g. "50 54 58"). Output: one block per size in OUT_DIR
# (default ./qs_strategy_cost), and a summary table on stdout.
set -eu
build=${1:?usage: qs_strategy_cost.sh BUILD_DIR [SIZES] [END] [RTOL]}
sizes=${2:-"27 54 108 216"}
end=${3:-5000}
rtol=${4:-1e-4}
out=${OUT_DIR:-./qs_strategy_cost}
bench="$build/bin/qs_strategies"
mkdir -p "$out"
echo "# qs_strategy_cost: $(uname -n), $(date -u +%Y-%m-%dT%H:%MZ), END $end s, qs_rtol $rtol"
echo "| spheres | strategy | CPU [s] | global steps | CPU / strategy 2 |"
echo "|---|---|---|---|---|"
for n in $sizes; do
    box=$(awk -v n="$n" 'BEGIN { s = 1.5 * (n / 805.0) ^ (1.0 / 3.0); printf "%.6e %.6e %.6e", 0.5e-3 * s, 0.5e-3 * s, 0.4e-3 * s }')
    # shellcheck disable=SC2086
    "$bench" --make-packing "$out/p$n.xyz" --count "$n" --box $box --fraction 0.6 \
        --friction 0.1 > "$out/make$n.txt"
    OMP_NUM_THREADS=1 "$bench" --packing "$out/p$n.xyz" --end "$end" --strategies "1 2 3" \
        --rtols "$rtol" --reference 3 1e-8 > "$out/run$n.txt"
    # rows "| S | rtol | max strain | CPU | steps | ..." of qs_strategies' table
    awk -v n="$n" -F'|' '
        $2 ~ /^ *[123] *$/ && $3 ~ /e-/ {
            s = $2 + 0; cpu[s] = $5 + 0; steps[s] = $6 + 0
        }
        END {
            for (s = 1; s <= 3; ++s)
                if (s in cpu)
                    printf "| %d | %d | %.3f | %d | %.2f |\n", n, s, cpu[s], steps[s],
                           (2 in cpu && cpu[2] > 0) ? cpu[s] / cpu[2] : 0
        }' "$out/run$n.txt"
done
