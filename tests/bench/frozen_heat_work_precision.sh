#!/bin/sh
# Work-precision of heat at its own pace (frozen mechanics, issue 41) on a seed 003 scene:
# conduction_box (sec. 5.3) or laser_bed (sec. 5.4).
#
#   tests/bench/frozen_heat_work_precision.sh BUILD_DIR WORK_DIR conduction_box|laser_bed
#
# 1. The scene through `sinter run` to a checkpoint once its bed rests and is frozen (STOP).
# 2. From that checkpoint, frozen continuations to the scene's end at several tolerances
#    (frozen_rtol; frozen_atol 1e-3 of it in kelvin) and a converged one (REF: 100 times the
#    tightest; backward Euler's error falls as the square root of the tolerance, so the
#    reference's own is about a tenth of the tightest run's): error of the mean and of the
#    largest temperature (largest difference over the samples) against the converged run.
# Not here: the fully coupled run over a window after STOP. A continuation of a checkpoint
# taken while frozen stays frozen whatever the scene's frozen_heat says (the stage's state is
# the checkpoint's), so it needs a checkpoint taken before the bed rests (RESULTS.md, issue 41).
# CPU time (user + sys) of every continuation from /usr/bin/time; evaluations: heat steps
# (series column "heat steps", each one backward Euler solve). Writes WORK_DIR/SCENE/SCENE.md
# (the table), SCENE.csv (log10 of CPU, heat steps and the errors) and SCENE_cpu.svg,
# SCENE_heat.svg (errors against CPU, against heat steps), drawn by `sinter plot`.
# Checkpoints and runs already in WORK_DIR are kept (rerun to redo the tables only).
set -e
B=$(cd "$1" && pwd)/bin/sinter
W=$2
S=$3
HERE=$(cd "$(dirname "$0")" && pwd)
SCENES=$HERE/../../examples/scenes
case $S in
conduction_box) STOP=2; RTOLS="1e-2 1e-3 1e-4 1e-5"; REF=1e-7 ;;
laser_bed) STOP=0.12; RTOLS="1e-3 1e-4 1e-5 1e-6"; REF=1e-8 ;;
*) echo "usage: $0 BUILD_DIR WORK_DIR conduction_box|laser_bed" >&2; exit 2 ;;
esac
mkdir -p "$W/$S"
cd "$W/$S"
cp "$SCENES/$S.scene" base.scene
for f in "$SCENES"/*.xyz "$SCENES"/*.csv; do cp "$f" . ; done

# a copy of the scene with `key = value` lines put first in its [stepper] section (a later
# key of the same name is dropped)
variant() { # NAME KEY=VALUE...
    name=$1; shift
    python3 - "$name" "$@" <<'EOF'
import sys
name, sets = sys.argv[1], [a.split('=', 1) for a in sys.argv[2:]]
keys = {k for k, _ in sets}
out, section = [], ''
for line in open('base.scene'):
    s = line.strip()
    if s.startswith('['):
        section = s
    if section == '[stepper]' and s.split('=')[0].strip() in keys:
        continue
    out.append(line)
    if s == '[stepper]':
        out += ['%s = %s\n' % (k, v) for k, v in sets]
open(name + '.scene', 'w').write(''.join(out))
EOF
}

run() { # NAME END: continue NAME.scene from the checkpoint to END, CPU into NAME.cpu
    [ -f "$1.cpu" ] && return 0
    /usr/bin/time -o "$1.time" -f "%U %S" "$B" run "$1.scene" -o "$1" \
        --restart settle/checkpoint.bin --end-time "$2" --progress 0 > "$1.log" 2>&1
    awk '{print $1 + $2}' "$1.time" > "$1.cpu"
}

[ -f settle/checkpoint.bin ] ||
    "$B" run base.scene -o settle --stop-at $STOP --progress 0 > settle.log 2>&1 || true
[ -f settle/checkpoint.bin ] || { echo "no checkpoint: see $W/$S/settle.log" >&2; exit 1; }

END=$(sed -n 's/^end_time *= *\([^ #]*\).*/\1/p' base.scene)
variant ref frozen_heat=1 frozen_rtol=$REF frozen_atol=$(python3 -c "print('%g' % (1e-3 * $REF))")
run ref "$END"
for r in $RTOLS; do
    a=$(python3 -c "print('%g' % (1e-3 * $r))")
    variant "f$r" frozen_heat=1 frozen_rtol=$r frozen_atol=$a
    run "f$r" "$END"
done

python3 - "$S" "$RTOLS" "$REF" <<'EOF'
import csv, math, sys
scene, rtols, ref_rtol = sys.argv[1], sys.argv[2].split(), sys.argv[3]

def series(name):
    rows = list(csv.reader(open(name + '/series.csv')))
    head = [h.split(' [')[0] for h in rows[0]]
    return [dict(zip(head, map(float, r))) for r in rows[1:] if len(r) == len(head)]

def error(run, ref, key):  # largest difference over the samples both have (same times)
    r = {round(s['time'], 9): s[key] for s in ref}
    d = [abs(s[key] - r[round(s['time'], 9)]) for s in run if round(s['time'], 9) in r]
    return max(d) if d else float('nan')

start = series('settle')[-1]['heat steps']  # the checkpoint's count
cpu = lambda name: float(open(name + '.cpu').read())
lg = lambda v: math.log10(v) if v > 0 else float('nan')
ref = series('ref')
rows = []
for r in rtols + [ref_rtol]:
    name = 'f' + r if r != ref_rtol else 'ref'
    f = series(name)
    rows.append((r, cpu(name), f[-1]['heat steps'] - start, error(f, ref, 'mean temperature'),
                 error(f, ref, 'max temperature')))
with open(scene + '.md', 'w') as o:
    o.write('| frozen_rtol | CPU [s] | heat steps | error mean T [K] | error max T [K] |\n')
    o.write('|---|---|---|---|---|\n')
    for r, c, e, em, ex in rows:
        o.write('| %s%s | %.2f | %d | %.3g | %.3g |\n' %
                (r, ' (reference)' if r == ref_rtol else '', c, e, em, ex))
with open(scene + '.csv', 'w') as o:
    o.write('log10 CPU time [log10 s],log10 heat steps [log10 1],'
            'error of the mean temperature [log10 K],error of the max temperature [log10 K]\n')
    for r, c, e, em, ex in rows[:-1]:
        o.write('%.6g,%.6g,%.6g,%.6g\n' % (lg(c), lg(e), lg(em), lg(ex)))
print(open(scene + '.md').read())
EOF
T="frozen heat against a converged run, $STOP s to the end"
for x in "CPU time" "heat steps"; do
    f=$(echo "$x" | cut -d' ' -f1 | tr 'A-Z' 'a-z')
    "$B" plot . --file "$S.csv" --x "log10 $x" --panel "error of the mean temperature" \
        --panel "error of the max temperature" --title "$S: $T (log10)" -o "${S}_$f.svg"
done
