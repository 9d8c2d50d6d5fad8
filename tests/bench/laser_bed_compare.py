#!/usr/bin/env python3
"""Tables and chart data of tests/bench/laser_bed_work_precision.sh (issue 41).

    laser_bed_compare.py WORK_DIR START "SEEDS" "EXPLICIT_RUNS" "RTOLS" "CAPS"

Reads WORK_DIR/sSEED/{ref,fRTOL,mCAP}/series.csv (and eDT, coupled runs at other steps, if named), the last frames and NAME.cpu (user + sys),
compares every run with ref (coupled at the scene's dt) of the same pour and writes
WORK_DIR/laser_bed.md and WORK_DIR/laser_bed.csv (log10 of the means over the pours).
Errors: the largest absolute difference over the samples after START of the mean, the largest
and the lit particles' mean temperature and of the hot zone (particles at 393 K or more); per
particle (matched by id) the largest temperature difference at the last common frame.
"""
import base64
import csv
import math
import os
import re
import statistics
import struct
import sys

W, START = sys.argv[1], float(sys.argv[2])
SEEDS, EXPLICIT, RTOLS = sys.argv[3].split(), sys.argv[4].split(), sys.argv[5].split()
CAPS = sys.argv[6].split() if len(sys.argv) > 6 else []
QUANTITIES = [('mean temperature', 'mean T [K]'), ('max temperature', 'max T [K]'),
              ('lit mean temperature', 'lit mean T [K]'), ('hot', 'hot zone [particles]')]


def series(path):
    rows = list(csv.reader(open(os.path.join(path, 'series.csv'))))
    head = [h.split(' [')[0] for h in rows[0]]
    out = []
    for r in rows[1:]:
        if len(r) != len(head):
            continue
        s = dict(zip(head, map(float, r)))
        s['hot'] = sum(v for k, v in s.items() if k.startswith('temperature ') and
                       not k.startswith('temperature below'))
        out.append(s)
    return out


def array(text, name, kind):
    m = re.search(r'<DataArray[^>]*Name="%s"[^>]*>\s*([^<]*)<' % name, text)
    data = m.group(1).strip()
    size = struct.unpack('<Q', base64.b64decode(data[:12]))[0]
    return struct.unpack('<%d%s' % (size // 8, kind), base64.b64decode(data[12:])[:size])


def last_frame(path):
    """{id: temperature} of the run's last frame, and its time."""
    pvd = [f for f in os.listdir(path) if f.endswith('.pvd')][0]
    frames = re.findall(r'timestep="([^"]+)"[^>]*file="([^"]+)"',
                        open(os.path.join(path, pvd)).read())
    t, f = max(frames, key=lambda x: float(x[0]))
    text = open(os.path.join(path, f)).read()
    return float(t), dict(zip(array(text, 'id', 'Q'), array(text, 'temperature', 'd')))


def error(run, ref, key):  # largest difference over the common samples after START
    r = {round(s['time'], 9): s[key] for s in ref if s['time'] > START + 1e-9}
    d = [abs(s[key] - r[round(s['time'], 9)]) for s in run if round(s['time'], 9) in r]
    return max(d) if d else float('nan')


def evaluations(start, run, dt):
    """Explicit steps (each a force and heat evaluation) and heat steps from the start
    checkpoint (start: the last row of the run that wrote it) to the run's end."""
    a, b = start, run[-1]
    frozen = b.get('frozen time', 0.0) - a.get('frozen time', 0.0)
    heat = b.get('heat steps', 0.0) - a.get('heat steps', 0.0)
    return round((b['time'] - a['time'] - frozen) / dt) + heat, heat, frozen


def scene_dt(path):
    m = re.search(r'^dt = (\S+)', open(path).read(), re.M)
    return float(m.group(1))


names = EXPLICIT + ['f' + r for r in RTOLS] + ['m' + c for c in CAPS]
label = {n: {'e': 'explicit, coupled, dt %s s', 'f': 'frozen, frozen_rtol %s',
             'm': 'frozen, frozen_rtol 1e-4, frozen_dt_max %s s'}[n[0]] % n[1:] for n in names}
results = {n: [] for n in names}  # per pour: dict of figures
ref_figures = []
missing = [s for s in SEEDS if not os.path.exists(os.path.join(W, 's' + s, 'ref.cpu'))]
SEEDS = [s for s in SEEDS if s not in missing]  # pours whose reference has not run (yet)
for seed in SEEDS:
    d = os.path.join(W, 's' + seed)
    ref = series(os.path.join(d, 'ref'))
    start = series(os.path.join(d, 'start'))[-1]
    ref_cpu = float(open(os.path.join(d, 'ref.cpu')).read())
    t_ref, p_ref = last_frame(os.path.join(d, 'ref'))
    ref_figures.append({'cpu': ref_cpu, 'eval': evaluations(start, ref, scene_dt(os.path.join(d, 'ref.scene')))[0],
                        **{k: ref[-1][k] for k, _ in QUANTITIES}})
    for n in names:
        if not os.path.exists(os.path.join(d, n + '.cpu')):
            continue
        run = series(os.path.join(d, n))
        cpu = float(open(os.path.join(d, n + '.cpu')).read())
        ev, heat, frozen = evaluations(start, run, scene_dt(os.path.join(d, n + '.scene')))
        t, p = last_frame(os.path.join(d, n))
        diff = [abs(p[i] - p_ref[i]) for i in p_ref] if abs(t - t_ref) < 1e-9 else [math.nan]
        f = {'cpu': cpu, 'ratio': cpu / ref_cpu, 'eval': ev, 'heat': heat,
             'particle': max(diff), 'over5': sum(x > 5.0 for x in diff),
             'frozen': frozen}
        for k, _ in QUANTITIES:
            f[k] = error(run, ref, k)
        results[n].append((seed, f))


# the means and the chart over the pours that have every run (a pour whose bed does not come
# to rest in the window runs coupled throughout: its frozen runs are the reference's bits, and
# where only some were run it stays in the per-pour table)
complete = [seed for seed in SEEDS if all(seed in [x for x, _ in results[n]] for n in names)]
for n in names:
    results[n + '*'] = [(x, f) for x, f in results[n] if x in complete]


def ms(values):  # mean ± sample standard deviation
    v = [x for x in values if not math.isnan(x)]
    if not v:
        return math.nan, math.nan
    return statistics.mean(v), statistics.stdev(v) if len(v) > 1 else 0.0


def fmt(values, digits='%.3g'):
    m, s = ms(values)
    return (digits + ' ± ' + digits) % (m, s)


with open(os.path.join(W, 'laser_bed.md'), 'w') as o:
    if missing:
        o.write('Pours without their reference run (left out): %s\n\n' % ' '.join(missing))
    o.write('Reference (coupled, the scene\'s dt), per pour: CPU [s], evaluations, at the end: '
            'mean T, max T, lit mean T [K], hot zone [particles]\n\n')
    o.write('| pour | CPU [s] | evaluations | mean T | max T | lit mean T | hot zone |\n')
    o.write('|---|---|---|---|---|---|---|\n')
    for seed, f in zip(SEEDS, ref_figures):
        o.write('| %s | %.1f | %d | %.3f | %.2f | %.2f | %d |\n' %
                (seed, f['cpu'], f['eval'], f['mean temperature'], f['max temperature'],
                 f['lit mean temperature'], f['hot']))
    o.write('\nPer pour: errors against the reference (largest over the samples; per particle '
            'at the end)\n\n')
    o.write('| run | pour | CPU [s] | CPU / ref | evaluations | heat steps | frozen [s] | ' +
            ' | '.join(h for _, h in QUANTITIES) + ' | per particle [K] | particles > 5 K |\n')
    o.write('|---|---|---|---|---|---|---|' + '---|' * len(QUANTITIES) + '---|---|\n')
    for n in names:
        for seed, f in results[n]:
            o.write('| %s | %s | %.1f | %.3f | %d | %d | %.4f | ' %
                    (n, seed, f['cpu'], f['ratio'], f['eval'], f['heat'], f['frozen']) +
                    ' | '.join('%.3g' % f[k] for k, _ in QUANTITIES) +
                    ' | %.3g | %d |\n' % (f['particle'], f['over5']))
    o.write('\nMean ± sample standard deviation over the pours with every run (%s)\n\n'
            % ' '.join(complete))
    o.write('| run | pours | CPU / ref | evaluations | ' +
            ' | '.join('error ' + h for _, h in QUANTITIES) +
            ' | per particle [K] | particles > 5 K |\n')
    o.write('|---|---|---|---|' + '---|' * len(QUANTITIES) + '---|---|\n')
    for n in names:
        fs = [f for _, f in results[n + '*']]
        if not fs:
            continue
        col = lambda k: [f[k] for f in fs]
        o.write('| %s | %d | %s | %s | ' % (label[n], len(fs), fmt(col('ratio')),
                                           fmt(col('eval'), '%.4g')) +
                ' | '.join(fmt(col(k)) for k, _ in QUANTITIES) +
                ' | %s | %s |\n' % (fmt(col('particle')), fmt(col('over5'))))

lg = lambda v: math.log10(v) if v > 0 else math.nan
groups = [('explicit', EXPLICIT), ('frozen', ['f' + r for r in RTOLS]),
          ('frozen dt_max', ['m' + c for c in CAPS])]
groups = [g for g in groups if g[1]]
# charted (the hot zone's error is often 0 particles: in the tables only)
short = [('lit mean temperature', 'lit mean T'), ('max temperature', 'max T'),
         ('mean temperature', 'mean T'), ('particle', 'per particle')]
head = ['log10 CPU time [log10 s]', 'log10 evaluations [log10 1]']
for _, q in short:
    for g, _ in groups:
        head.append('%s error (%s) [log10 K]' % (q, g))
with open(os.path.join(W, 'laser_bed.csv'), 'w') as o:
    o.write(','.join(head) + '\n')
    for gi, (g, members) in enumerate(groups):
        rows = []
        for n in members:
            fs = [f for _, f in results[n + '*']]
            if not fs:
                continue
            row = [lg(ms([f['cpu'] for f in fs])[0]), lg(ms([f['eval'] for f in fs])[0])]
            for k, _ in short:
                for gj in range(len(groups)):
                    row.append(lg(ms([f[k] for f in fs])[0]) if gj == gi else math.nan)
            rows.append(row)
        for row in sorted(rows):
            o.write(','.join('%.6g' % v if not math.isnan(v) else 'nan' for v in row) + '\n')
print(open(os.path.join(W, 'laser_bed.md')).read())
