#!/bin/sh
# Work-precision of the quasi-static stepper's neck integration over whole runs (issue 45):
# strategy 2 (the seed's per-pair RK4 with step doubling) against strategy 3 (the necks in CVODE,
# the default) on the copper packing (805 spheres, 1293 K, 5000 s) and the titanium packing (800
# spheres of titanium_packing.scene's kind, its E14B furnace, 8880 s), errors of the shrinkage and
# of the neck radius against a converged reference, CPU time of every run in the same session.
#
#   tests/bench/qs_work_precision.sh BUILD_DIR WORK_DIR [JOBS]
#
# Runs JOBS (2) processes at a time; each process alternates the strategies (qs_strategies
# --repeat 2), so a slow minute of the host falls on both. Writes WORK_DIR/{cu,ti}.md (tables)
# and WORK_DIR/{cu,ti}.svg (charts). The references (strategy 3 at rtol 1e-7, the global step
# held to an approach of 5e-5 L0 for every link) are made once and kept.
set -e
B=$(cd "$1" && pwd)/bin/qs_strategies
W=$2
JOBS=${3:-2}
HERE=$(cd "$(dirname "$0")" && pwd)
SCENE=$HERE/../../examples/scenes/titanium_packing.scene
mkdir -p "$W/runs"
cd "$W"
[ -f copper805.xyz ] || "$B" --make-packing copper805.xyz --fraction 0.6 --friction 0.1
[ -f ti800.xyz ] || "$(dirname "$B")/ti_shrinkage" --make "$SCENE" ti800.xyz --count 800

CU="--packing copper805.xyz"
TI="--packing ti800.xyz --scene $SCENE"
# strategy 3 as the default sets it, spelled out
S3="--set qs_strain_fraction 0.01 --set qs_young_pairs 1 --set qs_grown_rk4 1"
REF="--strategies '' --reference 3 1e-7 --reference-set qs_max_strain 5e-5"
REF="$REF --reference-set qs_strain_fraction 0 --reference-set qs_young_pairs 1"
REF="$REF --reference-set qs_grown_rk4 1"

{
    [ -f ref_cu.txt ] || echo "$B $CU $REF --save-reference ref_cu.txt > ref_cu.log"
    [ -f ref_ti.txt ] || echo "$B $TI $REF --save-reference ref_ti.txt > ref_ti.log"
    for P in cu ti; do
        [ $P = cu ] && A=$CU || A=$TI
        echo "$B $A --no-reference --strategies '2 3' --rtols 1e-6 --max-strains '5e-5 7e-5' $S3 --repeat 2 --save-runs runs/$P-a > runs/$P-a.log"
        echo "$B $A --no-reference --strategies '2 3' --rtols '1e-5 1e-7' --max-strains '1e-4 2e-4' $S3 --save-runs runs/$P-b > runs/$P-b.log"
        echo "$B $A --no-reference --strategies 3 --rtols '1e-4 1e-6' --max-strains 2e-4 $S3 --set qs_grown_rk4 0 --save-runs runs/$P-cvode > runs/$P-cvode.log"
    done
} | xargs -d '\n' -P "$JOBS" -I{} sh -c {}

for P in cu ti; do
    [ $P = cu ] && END=5000 || END=8880
    [ $P = cu ] && TITLE="805 copper spheres, 1293 K, 5000 s" || TITLE="800 titanium spheres, E14B, 8880 s"
    "$B" --compare ref_$P.txt "$(ls runs/$P-*.txt | tr '\n' ' ')" --end $END --svg $P.svg \
        --scene "$TITLE" > $P.md 2>&1 || true
done
