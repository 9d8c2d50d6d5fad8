#!/usr/bin/env python3
"""`mpiexec -n N sinter run` of a scene with continuous insertion (issues 43/44).

usage: cli_mpi_insert.py SINTER MPIEXEC SCENES WORK NP

powder_bed.scene as it is (a hopper region pouring steel powder at 3e-5 kg/s onto a plate, a
mesh blade, conduction, a ray-traced beam later on, the temperature histogram), sampled every
5e-4 s (each insertion) to 3e-3 s: the scene starts empty, so the decomposition's box is the
insertion region's; every rank draws the same spheres, rank 0 adds them and the redistribution
moves them to their ranks. On one rank series.csv is the serial text byte for byte except the
volume and solid fractions, which the MPI runner leaves nan beside a mesh wall and with
[output] solid_box (not formed yet); on NP ranks every other value within a relative 1e-10,
the inserted mass and its target and the histogram's counts the same text.
"""
import os
import re
import shutil
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import cli_mpi_run as base  # noqa: E402  (its ENV, check(), failures, series(), rel_diff())

ENV = base.ENV
check = base.check

END = "3e-3"
NAN_HERE = ("volume fraction [1]", "solid fraction [1]")


def main():
    sinter, mpiexec, scenes, work, np = sys.argv[1:6]
    np = int(np)
    os.makedirs(work, exist_ok=True)
    text = open(os.path.join(scenes, "powder_bed.scene")).read()
    text = re.sub(r"(\[output\]\n(?:[^\[\n][^\n]*\n)*?)interval = [^\n]*\n",
                  r"\1interval = 5e-4\n", text)
    check("[insert]" in text and "interval = 5e-4" in text, "the scene is not made")
    for name in ("powder_psd.csv", "powder_bed_track.txt", "powder_bed_blade.stl"):
        shutil.copy(os.path.join(scenes, name), work)
    scene = os.path.join(work, "powder_bed_short.scene")
    with open(scene, "w") as f:
        f.write(text)
    outs = []
    for n in (0, np):
        out = os.path.join(work, "serial" if n == 0 else "np%d" % n)
        shutil.rmtree(out, ignore_errors=True)
        args = [sinter, "run", scene, "-o", out, "--end-time", END]
        cmd = args + ["--progress", "0"] if n == 0 else [mpiexec, "-n", str(n),
                                                          "--oversubscribe"] + args
        p = subprocess.run(cmd, env=ENV, capture_output=True, text=True, timeout=280)
        check(p.returncode == 0, "run on %d ranks: %s" % (n, p.stderr))
        if p.returncode != 0:
            sys.exit(1)
        outs.append(os.path.join(out, "series.csv"))
    (head_s, rows_s), (head_m, rows_m) = base.series(outs[0]), base.series(outs[1])
    check(head_s == head_m, "headers differ: %s / %s" % (head_s, head_m))
    check(len(rows_s) == len(rows_m) == 7, "rows %d / %d" % (len(rows_s), len(rows_m)))
    mass = head_s.index("inserted mass [kg]")
    check(float(rows_s[-1][mass]) > 0.5 * 3e-5 * 3e-3, "inserted %s kg" % rows_s[-1][mass])
    worst = 0.0
    for rs, rm in zip(rows_s, rows_m):
        for k, (a, b) in enumerate(zip(rs, rm)):
            if head_s[k] in NAN_HERE:
                check(b == "nan" or a == b, "t = %s, %s: %s vs %s" % (rs[0], head_s[k], a, b))
            elif a == b:  # (also an empty bed's -inf extremes)
                continue
            elif np == 1 or k in (mass, mass + 1) or head_s[k].startswith("temperature "):
                check(a == b, "np %d, t = %s, %s: %s != %s" % (np, rs[0], head_s[k], a, b))
            else:
                rel = base.rel_diff(a, b)
                worst = max(worst, rel)
                check(rel <= 1e-10, "np %d, t = %s, %s: %s vs %s" % (np, rs[0], head_s[k], a, b))
    print("powder bed (insertion), np %d: %d rows, %s kg inserted, largest relative difference "
          "%.3g" % (np, len(rows_m), rows_m[-1][mass], worst))
    sys.exit(1 if base.failures else 0)


if __name__ == "__main__":
    main()
