#!/bin/sh
# Work-precision on seed 003's laser bed (sec. 5.4, examples/scenes/laser_bed.scene; issue 41):
# the fully coupled explicit stepper against heat at its own pace (frozen mechanics) over the
# first 10 ms of the laser track, over several random pours.
#
#   tests/bench/laser_bed_work_precision.sh BUILD_DIR WORK_DIR [SEEDS] [JOBS]
#
# SEEDS: the pours ([particles] seed; default "1 2 3 4 5", 5 is the scene's); JOBS processes
# at a time (default 2). Per pour, in WORK_DIR/sSEED:
# 1. settle: the scene, coupled (frozen_heat 0), through `sinter run` to a checkpoint at
#    the sample at 0.11 s (the bed still creeping), then coupled on to the sample at 0.12 s, the
#    beam's switch-on (a second checkpoint; its CPU is not counted: every run below starts there).
# 2. From 0.12 s to END = 0.13 s (the beam 1 mm along its track; the scenes ask for samples
#    every 1 ms, but a restart keeps the checkpoint's output schedule, so the first sample
#    after 0.12 s is the one at 0.13 s and the comparison is at END):
#    ref   coupled, explicit heat, the scene's dt 5e-7 s: the reference (its own error against
#          a smaller step is not measured here: a restart keeps the checkpoint's dt whatever
#          the scene says, and a pour at another step is another pour);
#    fRTOL frozen_heat 1 (the scene's frozen_ke, 1e-12 J per particle; frozen_atol 1e-3 of
#          frozen_rtol in kelvin) at frozen_rtol 1e-3 .. 1e-6 and 1e-8 (the frozen limit:
#          the heat step converged, what is left is the frozen bed's);
#    mCAP  frozen at frozen_rtol 1e-4 with frozen_dt_max CAP (2e-4, 5e-5 s): a heat step takes
#          the beam's power at its start, and its error control does not see the beam reach
#          new particles within the step (RESULTS.md), so the beam's travel per step is capped.
# 3. Errors against ref, the largest difference over the samples after 0.12 s (with END =
#    0.13 s the one at END): the mean temperature, the largest temperature, the mean
#    temperature of the lit particles (those the beam has heated: the seed's 5.4 quantity), the
#    hot zone (particles at 393 K or more, 20 K above the start, from the series' temperature
#    histogram); and per particle (by id) at END from the last frames.
#    CPU: user + sys (/usr/bin/time) of each run; evaluations: explicit steps (one force and
#    heat evaluation each) + heat steps (one backward Euler solve each, PCG).
# Writes WORK_DIR/laser_bed.md (per-pour rows, then mean ± sample standard deviation over the
# pours), laser_bed.csv (log10 of the means) and laser_bed_cpu.svg, laser_bed_evaluations.svg
# (errors against CPU, against evaluations: lit mean, max, mean T and per particle; the hot
# zone's, often 0, in the table only), drawn by `sinter plot`. Runs already in WORK_DIR
# are kept (rerun to redo the tables only). The staggered stepper is not run: see RESULTS.md.
set -e
B=$(cd "$1" && pwd)/bin/sinter
W=$2
SEEDS=${3:-"1 2 3 4 5"}
JOBS=${4:-2}
HERE=$(cd "$(dirname "$0")" && pwd)
SCENE=$HERE/../../examples/scenes/laser_bed.scene
# --stop-at a little before the sample: a sample's time carries the steps' rounding (the one
# at 0.11 s reads 0.10999999999999999 s) and --stop-at T stops at the first sample >= T
STOP1=0.1099
START=0.1199
END=0.13
RTOLS="1e-3 1e-4 1e-5 1e-6 1e-8"
CAPS="2e-4 5e-5" # frozen_dt_max [s] at frozen_rtol 1e-4: the beam 20 and 5 um per heat step
mkdir -p "$W"
W=$(cd "$W" && pwd)
cd "$W"

# a copy of the scene with SECTION.KEY=VALUE put first in [SECTION] (a later key of the same
# name in that section is dropped)
variant() { # FILE SECTION.KEY=VALUE...
    python3 - "$SCENE" "$@" <<'EOF'
import sys
scene, name, sets = sys.argv[1], sys.argv[2], [a.split('=', 1) for a in sys.argv[3:]]
sets = [(k.split('.', 1)[0], k.split('.', 1)[1], v) for k, v in sets]
out, section = [], ''
for line in open(scene):
    s = line.strip()
    if s.startswith('['):
        section = s[1:-1].split()[0]
    if any(section == sec and s.split('=')[0].strip() == key for sec, key, _ in sets):
        continue
    out.append(line)
    if s.startswith('['):
        out += ['%s = %s\n' % (key, v) for sec, key, v in sets if sec == section]
open(name, 'w').write(''.join(out))
EOF
}

# NAME in sSEED: run NAME.scene from CHECKPOINT to END (or --stop-at), CPU into NAME.cpu
cat > run.sh.new <<'EOF'
#!/bin/sh
# run.sh SINTER DIR NAME CHECKPOINT|- ARGS...: one run, CPU (user + sys) into DIR/NAME.cpu
B=$1; cd "$2"; N=$3; C=$4; shift 4
[ -f "$N.cpu" ] && exit 0
R=""; [ "$C" = - ] || R="--restart $C"
/usr/bin/time -o "$N.time" -f "%U %S" "$B" run "$N.scene" -o "$N" $R "$@" --progress 0 \
    > "$N.log" 2>&1 && tail -n 1 "$N.time" | awk '{print $1 + $2}' > "$N.cpu"
EOF
mv run.sh.new run.sh # a new file: a run.sh still being read keeps its own

# the runs after START: the temperature histogram (and samples every 1 ms after the first)
out() { variant "$@" output.interval=0.001 "output.temperature_bins=393 453 3"; }
for s in $SEEDS; do
    mkdir -p "s$s"
    variant "s$s/settle.scene" "particles.seed=$s" stepper.frozen_heat=0
    variant "s$s/start.scene" "particles.seed=$s" stepper.frozen_heat=0
    out "s$s/ref.scene" "particles.seed=$s" stepper.frozen_heat=0
    for r in $RTOLS; do
        a=$(python3 -c "print('%g' % (1e-3 * $r))")
        out "s$s/f$r.scene" "particles.seed=$s" stepper.frozen_heat=1 \
            "stepper.frozen_rtol=$r" "stepper.frozen_atol=$a"
    done
    for c in $CAPS; do
        out "s$s/m$c.scene" "particles.seed=$s" stepper.frozen_heat=1 stepper.frozen_rtol=1e-4 \
            stepper.frozen_atol=1e-7 "stepper.frozen_dt_max=$c"
    done
done

X="sh $W/run.sh $B"
for s in $SEEDS; do echo "$X $W/s$s settle - --stop-at $STOP1"; done | xargs -d '\n' -P "$JOBS" -I{} sh -c {}
for s in $SEEDS; do echo "$X $W/s$s start settle/checkpoint.bin --stop-at $START"; done |
    xargs -d '\n' -P "$JOBS" -I{} sh -c {}
{
    for s in $SEEDS; do
        echo "$X $W/s$s ref start/checkpoint.bin --end-time $END"
        for r in $RTOLS; do echo "$X $W/s$s f$r start/checkpoint.bin --end-time $END"; done
        for c in $CAPS; do echo "$X $W/s$s m$c start/checkpoint.bin --end-time $END"; done
    done
} | xargs -d '\n' -P "$JOBS" -I{} sh -c {}

python3 "$HERE/laser_bed_compare.py" "$W" "$START" "$SEEDS" "" "$RTOLS" "$CAPS"
T="laser bed, beam's first 10 ms, $(echo $SEEDS | wc -w) pours, against the coupled run"
for x in "CPU time" "evaluations"; do
    f=$(echo "$x" | cut -d' ' -f1 | tr 'A-Z' 'a-z')
    "$B" plot . --file laser_bed.csv --x "log10 $x" --panel "lit mean T" --panel "max T" \
        --panel "mean T" --panel "per particle" --title "$T (log10 of the means)" \
        -o "laser_bed_$f.svg"
done
