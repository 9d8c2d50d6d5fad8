#!/usr/bin/env python3
"""How often recover.py's 95 % intervals hold the truth over many noise seeds.

For seeds 1..N (default 20) it runs recover.run and counts, per fitted key, the seeds whose
interval holds the true value, and the mean and spread of z = (fitted - true) / standard error
(in ln D0 for prefactors): about 95 % of the seeds, mean 0 and spread 1 when the intervals are
right. Run: python3 coverage.py [--seeds N] [--out DIR]  (about 5 s a seed).
"""

import argparse
import math
import os
import statistics
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import recover  # noqa: E402


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=20)
    parser.add_argument("--out", default="out/calibrate_coverage")
    args = parser.parse_args()
    inside = {k: 0 for k in recover.KEYS}
    z = {k: [] for k in recover.KEYS}
    for seed in range(1, args.seeds + 1):
        result, truth = recover.run(args.out, seed)
        for key, ok in result.contains(truth).items():
            inside[key] += ok
        for i, key in enumerate(result.keys):
            true = math.log(truth[key]) if "prefactor" in key else truth[key]
            z[key].append((result.reported[i] - true) / result.standard_error[i])
    print("| key | seeds inside the 95 % interval | mean z | spread of z |")
    print("|---|---|---|---|")
    for key in recover.KEYS:
        print("| %s | %d / %d | %.2f | %.2f |" % (key, inside[key], args.seeds,
                                                statistics.mean(z[key]),
                                                statistics.pstdev(z[key])))
    return 0


if __name__ == "__main__":
    sys.exit(main())
