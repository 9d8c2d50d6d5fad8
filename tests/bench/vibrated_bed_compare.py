#!/usr/bin/env python3
"""Two runs of a vibrated bed (seed 003 sec. 5.2) compared by their temperatures (issue 41).

    tests/bench/vibrated_bed_compare.py REF_DIR RUN_DIR [--every N] [--from T0]

Reads the frames (frames/frame_NNNNN.vtu, written by `sinter run`) both runs have, and prints
per sample time the mean particle temperature and its spread (standard deviation over the
particles) of both and their differences; then the largest and the mean absolute difference
of each over the common samples. The bed is chaotic: two runs that differ only in the order
of a sum part after a few tenths of a second, so the comparison is of these statistics, not of
particles. With --from T0, also both runs' time averages of the two statistics over the
common samples from T0 on (a bias of one run shows there, the waves average out).
"""
import base64
import glob
import math
import os
import re
import struct
import sys


def temperatures(path):
    text = open(path).read()
    m = re.search(r'<DataArray[^>]*Name="temperature"[^>]*>\s*([^<]*)<', text)
    data = m.group(1).strip()
    # the byte count (UInt64) and the values are encoded each on its own
    size = struct.unpack('<Q', base64.b64decode(data[:12]))[0]
    return struct.unpack('<%dd' % (size // 8), base64.b64decode(data[12:])[:size])


def frame_times(run):
    pvd = glob.glob(os.path.join(run, '*.pvd'))[0]
    out = {}
    for t, f in re.findall(r'timestep="([^"]+)"[^>]*file="([^"]+)"', open(pvd).read()):
        out[round(float(t), 9)] = os.path.join(run, f)
    return out


def stats(path):
    t = temperatures(path)
    mean = sum(t) / len(t)
    return mean, math.sqrt(sum((v - mean) ** 2 for v in t) / len(t))


def main():
    args = sys.argv[1:]
    every = 1
    t_from = None
    if '--from' in args:
        k = args.index('--from')
        t_from = float(args[k + 1])
        del args[k:k + 2]
    if '--every' in args:
        k = args.index('--every')
        every = int(args[k + 1])
        del args[k:k + 2]
    ref, run = frame_times(args[0]), frame_times(args[1])
    common = sorted(set(ref) & set(run))
    # the last frame of a run still going may be incomplete: only frames both finished
    common = [t for t in common if t < max(common)] if len(common) > 1 else common
    dm, ds = [], []
    avg = [0.0, 0.0, 0.0, 0.0, 0]
    print('| t [s] | mean T ref [K] | mean T run [K] | spread ref [K] | spread run [K] |')
    print('|---|---|---|---|---|')
    for k, t in enumerate(common):
        a, b = stats(ref[t]), stats(run[t])
        if t_from is not None and t >= t_from:
            avg = [avg[0] + a[0], avg[1] + b[0], avg[2] + a[1], avg[3] + b[1], avg[4] + 1]
        dm.append(abs(a[0] - b[0]))
        ds.append(abs(a[1] - b[1]))
        if k % every == 0 or k == len(common) - 1:
            print('| %g | %.3f | %.3f | %.3f | %.3f |' % (t, a[0], b[0], a[1], b[1]))
    print('\n%d common samples to t = %g s' % (len(common), common[-1]))
    print('mean temperature: largest difference %.3f K, mean absolute %.3f K' %
          (max(dm), sum(dm) / len(dm)))
    print('spread: largest difference %.3f K, mean absolute %.3f K' % (max(ds), sum(ds) / len(ds)))
    if avg[4] > 0:
        n = avg[4]
        print('averaged over %d samples from t = %g s: mean temperature %.3f K (ref) %.3f K '
              '(run), spread %.3f K (ref) %.3f K (run)' %
              (n, t_from, avg[0] / n, avg[1] / n, avg[2] / n, avg[3] / n))


if __name__ == '__main__':
    main()
