#!/bin/sh
# Issue 38, scene 3: the periodic representative volume of copper (examples/scenes/copper_rve.scene)
# against the walled packing of the same spheres, over packing seeds. For each seed: a periodic
# green body by rve_pack (805 spheres of copper_packing.scene's powder, solid fraction 0.60), the
# scene run with the three axes periodic, then again with the periodic lines removed (the spheres
# held on the principal planes x, y, z = 0, free on the far faces: copper_packing.scene's set-up).
# Prints per seed and time the mean shrinkage over the axes and the volumetric strain of both,
# and the wall effect (walled - periodic) / periodic, then mean +- standard deviation over seeds.
#
# Usage: tests/bench/rve_wall_effect.sh BUILD_DIR [SEEDS...]   (default seeds 1 2 3 4 5)
set -eu
build=$1
shift
seeds=${*:-1 2 3 4 5}
here=$(cd "$(dirname "$0")/../.." && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
for s in $seeds; do
    "$build/bin/rve_pack" "$s" 805 0.60 "$work/rve_$s.xyz" >"$work/pack_$s.txt"
    edge=$(sed -n 's/.*\[0, \([0-9.e+-]*\)).*/\1/p' "$work/rve_$s.xyz" | head -1)
    sed -e "s/^file = copper_rve.xyz/file = rve_$s.xyz/" \
        -e "s/^\(periodic_[xyz]\) = 0 .*/\1 = 0 $edge/" \
        "$here/examples/scenes/copper_rve.scene" >"$work/periodic_$s.scene"
    grep -v '^periodic_' "$work/periodic_$s.scene" >"$work/walled_$s.scene"
    for kind in periodic walled; do
        /usr/bin/time -f "%U" -o "$work/cpu_${kind}_$s.txt" \
            "$build/bin/sinter" run "$work/${kind}_$s.scene" -o "$work/out_${kind}_$s" \
            --threads 1 >/dev/null 2>&1
    done
    echo "seed $s: $(cat "$work/pack_$s.txt")"
done
python3 - "$work" $seeds <<'PY'
import csv, statistics, sys
work, seeds = sys.argv[1], sys.argv[2:]
def series(path):
    rows = list(csv.reader(open(path)))
    h = rows[0]
    col = {n.split(' [')[0]: i for i, n in enumerate(h)}
    return {float(r[0]): r for r in rows[1:]}, col
times = [100.0, 1000.0, 2000.0, 5000.0]
table = {}
for s in seeds:
    for kind in ("periodic", "walled"):
        rows, col = series(f"{work}/out_{kind}_{s}/series.csv")
        for t in times:
            r = rows[t]
            sx, sy, sz = (float(r[col["shrinkage " + a]]) for a in "xyz")
            vol = 1 - (1 - sx) * (1 - sy) * (1 - sz)
            table[(s, kind, t)] = ((sx + sy + sz) / 3, vol, int(float(r[col["links"]])))
    cpu = {k: float(open(f"{work}/cpu_{k}_{s}.txt").read().split()[-1]) for k in ("periodic", "walled")}
    print(f"seed {s}: CPU periodic {cpu['periodic']:.1f} s, walled {cpu['walled']:.1f} s")
print("t [s] | periodic shrinkage | walled shrinkage | wall effect | periodic vol. strain | walled vol. strain | links periodic / walled")
for t in times:
    p = [table[(s, "periodic", t)][0] for s in seeds]
    w = [table[(s, "walled", t)][0] for s in seeds]
    e = [(b - a) / a for a, b in zip(p, w)]
    pv = [table[(s, "periodic", t)][1] for s in seeds]
    wv = [table[(s, "walled", t)][1] for s in seeds]
    lp = [table[(s, "periodic", t)][2] for s in seeds]
    lw = [table[(s, "walled", t)][2] for s in seeds]
    sd = lambda v: statistics.stdev(v) if len(v) > 1 else 0.0
    print(f"{t:g} | {statistics.mean(p):.4e} +- {sd(p):.1e} | {statistics.mean(w):.4e} +- {sd(w):.1e} | "
          f"{100 * statistics.mean(e):+.2f} % +- {100 * sd(e):.2f} % | {statistics.mean(pv):.4e} +- {sd(pv):.1e} | "
          f"{statistics.mean(wv):.4e} +- {sd(wv):.1e} | {statistics.mean(lp):.0f} / {statistics.mean(lw):.0f}")
PY
