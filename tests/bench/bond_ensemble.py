#!/usr/bin/env python3
"""Springback against bond strength, as an ensemble of random pours (issue 39).

    python3 tests/bench/bond_ensemble.py [--sinter build/bin/sinter] [--seeds 6] [--jobs 1]
                                         [--work DIR] [--trends STRENGTH] [--out FILE]

Runs examples/scenes/press_network.scene (copied into WORKDIR) with `bond_strength = S` added to
its `[force power_law]` section (S = 0: the seed's bonds, which end when a contact opens; S > 0:
a bond formed by seed 000 eq. 18-19 holds the pair in tension, f = K_b E^p_b A_b, until K_b E^p_b
exceeds S; with the scene's K_b = 1e6 Pa and p_b = 2 a bond breaks at the strain
E_b = (S / K_b)^(1/2)), for several `[particles]` seeds, and prints as mean ± sample standard
deviation (n - 1) over the seeds, from the series' solid fraction (overlaps counted once):
  - the poured solid fraction (when the pour came to rest),
  - the solid fraction at the end of the hold and at the end of the run,
  - the springback, relative: (end of hold - final) / end of hold,
  - the porosity drop, relative: 1 - (1 - final) / (1 - poured),
  - the bonds broken in the pour (bonds form there too: a falling sphere's impact reaches the
    seed's activation strain E* = 0.1) and after it, and the kinetic energy at the end.
With --trends S... (default 0 1e5 Pa; none given skips them) the seed's two trends at each
strength S: the
top wall held 0.15, 0.3, 0.6 s, and its travel 1.50, 1.56, 1.62 m of the 2 m box; these share
each seed's pour, so they are also given as differences from the scene's case, seed by seed.
The table (markdown) goes to stdout and, with --out, to that file. Each run takes 2-3 s of CPU.
"""
import argparse
import concurrent.futures
import os
import re
import shutil
import statistics
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SCENE = os.path.join(ROOT, "examples", "scenes", "press_network.scene")
STRENGTHS = [0.0, 500.0, 2500.0, 1e4, 3e4, 1e5]  # Pa: break strains 0, 0.022, 0.05, 0.1, 0.17, 0.32


def variant(text, seed, strength, hold, depth):
    """The scene with its seed, the bond strength and the top wall's hold and depth set."""
    text = re.sub(r"(?m)^seed = \d+", "seed = %d" % seed, text)
    schedule = "schedule = 0 0 0 0,  1.0 0 0 -%g,  %g 0 0 -%g,  %g 0 0 0" % (
        depth, 1.0 + hold, depth, 1.3 + hold)
    text, n = re.subn(r"(?m)^schedule = .*$", schedule, text)
    if n != 1:
        sys.exit("press_network.scene: expected one schedule line")
    if strength > 0.0:
        text, n = re.subn(r"(?m)^\[force power_law\]$",
                          "[force power_law]\nbond_strength = %r" % strength, text)
        if n != 1:
            sys.exit("press_network.scene: expected one [force power_law] section")
    return text


def run(sinter, work, name, text):
    """One run; returns (t_pour, rows, header) of its series."""
    scene = os.path.join(work, name + ".scene")
    with open(scene, "w") as f:
        f.write(text)
    out = os.path.join(work, name)
    result = subprocess.run([sinter, "run", scene, "-o", out, "--log", "info", "--threads", "1"],
                            capture_output=True, text=True)
    if result.returncode != 0:
        raise RuntimeError("%s failed: %s" % (name, result.stderr[-2000:]))
    poured_at = float(re.search(r"poured: at rest at t = ([0-9.eE+-]+) s", result.stderr).group(1))
    with open(os.path.join(out, "series.csv")) as f:
        header = [h.strip() for h in f.readline().strip().split(",")]
        rows = [[float(x) for x in line.split(",")] for line in f if line.strip()]
    return poured_at, rows, header


def measures(poured_at, rows, header, hold):
    col = {name: header.index(name) for name in header}
    time, solid = col["time [s]"], col["solid fraction [1]"]

    def at(t):
        return min(rows, key=lambda r: abs(r[time] - t))

    phi_p = at(poured_at)[solid]
    phi_h = at(poured_at + 1.0 + hold)[solid]
    phi_f = rows[-1][solid]
    bb = col.get("broken bonds [1]")
    broken_pour = at(poured_at)[bb] if bb is not None else 0.0
    broken = rows[-1][bb] if bb is not None else 0.0
    kinetic = rows[-1][col["kinetic energy [J]"]]
    return {"poured": phi_p, "held": phi_h, "final": phi_f,
            "springback": (phi_h - phi_f) / phi_h,
            "drop": 1.0 - (1.0 - phi_f) / (1.0 - phi_p),
            "broken_pour": broken_pour, "broken_after": broken - broken_pour, "kinetic": kinetic}


def summary(values, fmt="%.4f", sign=False):
    mean = (("%+" + fmt[1:]) if sign else fmt) % statistics.mean(values)
    return mean + " ± " + fmt % statistics.stdev(values)


COLUMNS = [("poured", "poured solid fraction", "%.4f"), ("held", "end of hold", "%.4f"),
           ("final", "final", "%.4f"), ("springback", "springback (rel.)", "%.4f"),
           ("drop", "porosity drop (rel.)", "%.4f"),
           ("broken_pour", "bonds broken in the pour", "%.0f"),
           ("broken_after", "bonds broken after it", "%.0f"),
           ("kinetic", "final kinetic energy [J]", "%.2g")]


def table(label, cases, results, lines):
    lines.append("| %s | %s |" % (label, " | ".join(c[1] for c in COLUMNS)))
    lines.append("|---" * (len(COLUMNS) + 1) + "|")
    for key, text in cases:
        r = results[key]
        lines.append("| %s | %s |" % (text, " | ".join(
            summary([m[c[0]] for m in r], c[2]) for c in COLUMNS)))
    lines.append("")


def paired(label, base, cases, results, lines):
    """Each case minus `base`, seed by seed (the same pour): mean ± sample sd of the differences."""
    keys = [("held", "end of hold"), ("final", "final"), ("springback", "springback"),
            ("drop", "porosity drop")]
    lines.append("| %s | %s |" % (label, " | ".join("d(%s)" % k[1] for k in keys)))
    lines.append("|---" * (len(keys) + 1) + "|")
    for key, text in cases:
        lines.append("| %s | %s |" % (text, " | ".join(
            summary([a[k] - b[k] for a, b in zip(results[key], results[base])], "%.4f", True)
            for k, _ in keys)))
    lines.append("")


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--sinter", default=os.path.join(ROOT, "build", "bin", "sinter"))
    parser.add_argument("--seeds", type=int, default=6)
    parser.add_argument("--jobs", type=int, default=1)
    parser.add_argument("--work", default="/tmp/bond_ensemble")
    parser.add_argument("--trends", type=float, nargs="*", default=[0.0, 1e5])
    parser.add_argument("--out", default=None)
    args = parser.parse_args()
    if args.seeds < 2:
        sys.exit("--seeds: at least 2 for a standard deviation")
    shutil.rmtree(args.work, ignore_errors=True)
    os.makedirs(args.work)
    with open(SCENE) as f:
        base = f.read()
    # (strength, hold, depth): the strengths at the scene's press, then the trends
    cases = [(s, 0.3, 1.56) for s in STRENGTHS]
    for t in args.trends:
        if (t, 0.3, 1.56) not in cases:
            cases.append((t, 0.3, 1.56))
        cases += [(t, h, 1.56) for h in (0.15, 0.6)]
        cases += [(t, 0.3, d) for d in (1.50, 1.62)]
    jobs = [(case, seed) for case in cases for seed in range(1, args.seeds + 1)]
    results = {case: [] for case in cases}
    with concurrent.futures.ThreadPoolExecutor(max_workers=args.jobs) as pool:
        futures = {}
        for (s, hold, depth), seed in jobs:
            name = "s%d_b%g_h%g_d%g" % (seed, s, hold, depth)
            futures[pool.submit(run, args.sinter, args.work, name,
                                variant(base, seed, s, hold, depth))] = ((s, hold, depth), seed)
        for future in concurrent.futures.as_completed(futures):
            case, seed = futures[future]
            t_p, rows, header = future.result()
            results[case].append((seed, measures(t_p, rows, header, case[1])))
    for case in results:  # in seed order, so the output does not depend on --jobs
        results[case] = [m for _, m in sorted(results[case], key=lambda x: x[0])]
    lines = []
    table("bond_strength [Pa] (break strain)",
          [((s, 0.3, 1.56), "%g (%s)" % (s, "seed's bonds" if s == 0.0 else
                                         "%.3f" % (s / 1e6) ** 0.5)) for s in STRENGTHS],
          results, lines)
    for t in args.trends:
        table("bond_strength %g Pa: case" % t,
              [((t, 0.15, 1.56), "hold 0.15 s"), ((t, 0.3, 1.56), "hold 0.3 s (scene)"),
               ((t, 0.6, 1.56), "hold 0.6 s"), ((t, 0.3, 1.50), "depth 1.50 m"),
               ((t, 0.3, 1.56), "depth 1.56 m (scene)"), ((t, 0.3, 1.62), "depth 1.62 m")],
              results, lines)
        paired("bond_strength %g Pa: case minus the scene's, same seed" % t, (t, 0.3, 1.56),
               [((t, 0.15, 1.56), "hold 0.15 s"), ((t, 0.6, 1.56), "hold 0.6 s"),
                ((t, 0.3, 1.50), "depth 1.50 m"), ((t, 0.3, 1.62), "depth 1.62 m")],
               results, lines)
    lines.append("%d seeds per case (1..%d); mean ± sample standard deviation; solid fractions "
                 "from series.csv; springback = (end of hold - final) / end of hold."
                 % (args.seeds, args.seeds))
    text = "\n".join(lines)
    print(text)
    if args.out:
        with open(args.out, "w") as f:
            f.write(text + "\n")


if __name__ == "__main__":
    main()
