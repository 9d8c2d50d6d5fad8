#!/usr/bin/env python3
"""The press scene (seed 000 sec. 7) as an ensemble of random pours (issue 39).

    python3 tests/bench/press_ensemble.py [--sinter build/bin/sinter] [--seeds 6] [--work DIR]

Runs examples/scenes/press_network.scene (copied into WORKDIR with its [particles] seed, the top
wall's hold time or its press depth changed) for several seeds, and prints, as mean ± standard
deviation over the seeds (sample standard deviation, n - 1):
  - the poured fraction (the series' volume fraction when the pour came to rest),
  - the fraction at the end of the hold, and at the end of the run,
  - the porosity drop (1 - (1 - final) / (1 - poured)), relative,
  - the springback: the fraction lost between the end of the hold and the end of the run;
for the scene as it is and for the seed's two trends: a longer hold (0.15, 0.3, 0.6 s) and a
deeper press (depth 1.50, 1.56, 1.62 m of the top wall's 2 m travel). A chaotic result is an
ensemble: quote these, not one run. Takes about 30 runs of 2-3 s.
"""
import argparse
import os
import re
import shutil
import statistics
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SCENE = os.path.join(ROOT, "examples", "scenes", "press_network.scene")


def variant(text, seed, hold, depth):
    text = re.sub(r"(?m)^seed = \d+", "seed = %d" % seed, text)
    schedule = "schedule = 0 0 0 0,  1.0 0 0 -%g,  %g 0 0 -%g,  %g 0 0 0" % (
        depth, 1.0 + hold, depth, 1.3 + hold)
    return re.sub(r"(?m)^schedule = .*$", schedule, text)


def run(sinter, work, name, text):
    scene = os.path.join(work, name + ".scene")
    with open(scene, "w") as f:
        f.write(text)
    out = os.path.join(work, name)
    result = subprocess.run([sinter, "run", scene, "-o", out, "--log", "info"],
                            capture_output=True, text=True)
    if result.returncode != 0:
        sys.exit("%s failed: %s" % (name, result.stderr[-2000:]))
    poured_at = float(re.search(r"poured: at rest at t = ([0-9.eE+-]+) s", result.stderr).group(1))
    with open(os.path.join(out, "series.csv")) as f:
        header = f.readline().strip().split(",")
        rows = [[float(x) for x in line.split(",")] for line in f if line.strip()]
    time, fraction = header.index("time [s]"), header.index("volume fraction [1]")

    def at(t):
        return min(rows, key=lambda r: abs(r[time] - t))[fraction]

    return poured_at, at(poured_at), rows, time, fraction


def summary(values):
    return "%.4f ± %.4f" % (statistics.mean(values), statistics.stdev(values))


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--sinter", default=os.path.join(ROOT, "build", "bin", "sinter"))
    parser.add_argument("--seeds", type=int, default=6)
    parser.add_argument("--work", default="/tmp/press_ensemble")
    args = parser.parse_args()
    shutil.rmtree(args.work, ignore_errors=True)
    os.makedirs(args.work)
    with open(SCENE) as f:
        base = f.read()
    cases = [("scene (hold 0.3 s, depth 1.56 m)", 0.3, 1.56),
             ("hold 0.15 s", 0.15, 1.56), ("hold 0.6 s", 0.6, 1.56),
             ("depth 1.50 m", 0.3, 1.50), ("depth 1.62 m", 0.3, 1.62)]
    print("| case | poured fraction | end of hold | final fraction | porosity drop | springback |")
    print("|---|---|---|---|---|---|")
    for label, hold, depth in cases:
        poured, held, final, drop, spring = [], [], [], [], []
        for seed in range(1, args.seeds + 1):
            name = "s%d_h%g_d%g" % (seed, hold, depth)
            t_p, phi_p, rows, time, fraction = run(args.sinter, args.work, name,
                                                   variant(base, seed, hold, depth))
            hold_end = t_p + 1.0 + hold
            phi_h = min(rows, key=lambda r: abs(r[time] - hold_end))[fraction]
            phi_f = rows[-1][fraction]
            poured.append(phi_p)
            held.append(phi_h)
            final.append(phi_f)
            drop.append(1.0 - (1.0 - phi_f) / (1.0 - phi_p))
            spring.append(phi_h - phi_f)
        print("| %s | %s | %s | %s | %s | %s |" % (label, summary(poured), summary(held),
                                                 summary(final), summary(drop), summary(spring)))
    print("\n%d seeds per case (1..%d); mean ± sample standard deviation." % (args.seeds, args.seeds))


if __name__ == "__main__":
    main()
