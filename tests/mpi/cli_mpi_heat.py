#!/usr/bin/env python3
"""`mpiexec -n N sinter run` of scenes with beam heat sources (issues 43/44).

usage: cli_mpi_heat.py SINTER MPIEXEC SCENES WORK NP [frozen]

laser_bed.scene shortened: a lattice of 2223 steel spheres (3 layers resting on the floor, so
that contacts cross the ranks' borders), the laser on from the start over the middle, a
ray-traced [heat beam] added that enters slanted (its shadows cross the borders), convection
and radiation of the exposed surface (heat/exposure.h), no frozen heat stage; 400 steps to
2e-4 s. On one rank series.csv is the serial runner's text byte for byte (the lit particles'
columns included); on NP ranks every value within a relative 1e-12 (the beam's powers are the
same bits on any number of ranks, tests/unit/test_domain_heat.c; the conduction and the
columns' sums add the same terms in another order: 2e-14 observed).

With `frozen`: the same bed with the frozen heat stage (frozen_heat = 1, frozen_ke 1e-12 J,
frozen_settle 20) and no contact law (gravity with gz = 0: the bed is at rest, so it freezes
after 20 steps), to 2e-3 s: the heat steps by backward Euler (implicit conduction across the
ranks) under the laser and the beam; the frozen stage's columns ("frozen", "heat steps", ...)
equal on every rank count, np 1 the serial text byte for byte, np 2-4 within 1e-12 (observed
3e-14). No checkpoint is written while the stage holds the mechanics (its per-particle rates
do not travel in portable checkpoints yet): the runner says so.
"""
import os
import re
import shutil
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import cli_mpi_run as base  # noqa: E402  (its ENV, check(), failures, series(), compare_series())

ENV = base.ENV
check = base.check

END = "2e-4"


def shortened(scenes, work, frozen):
    text = open(os.path.join(scenes, "laser_bed.scene")).read()
    text = re.sub(r"^#[^\n]*\n", "", text, flags=re.M)
    text = re.sub(r"\[particles\]\n(?:[^\[\n][^\n]*\n)*",
                  "[particles]\nmethod = lattice\nmaterial = steel\nradius = 0.0005\n"
                  "spacing = 0.001\nbox_min = 0.0005 0.0105 0.0005\n"
                  "box_max = 0.0395 0.0295 0.003\ntemperature = 373\n\n", text)
    text = text.replace("intensity_schedule = 0 0, 0.1199 0, 0.12 1.2732e7\n"
                        "x_schedule = 0.12 0, 0.62 0.05", "intensity = 1.2732e7\nx = 0.02")
    text = re.sub(r"frozen_[a-z]+ = [^\n]*\n", "", text)
    if frozen:
        text = text.replace("[force hertz_mindlin]\n", "[force gravity]\ngz = 0\n")
        text = text.replace("[force gravity]\n\n", "")
        text = text.replace("dt = 5e-7\n", "dt = 5e-7\nfrozen_heat = 1\nfrozen_ke = 1e-12\n"
                            "frozen_settle = 20\nfrozen_rtol = 1e-5\n")
        check("frozen_heat = 1" in text and "gz = 0" in text, "the frozen scene is not made")
    text = text.replace("[heat convection]\ntemperature = 273",
                        "[heat beam]\nx = 0.015\ny = 0.02\nz = 0.02\ndx = 0.3\ndz = -1\n"
                        "radius = 0.006\npower = 50\nrays = 12\n\n"
                        "[heat convection]\ntemperature = 273\nexposed = 1")
    text = text.replace("[heat radiation]\ntemperature = 273",
                        "[heat radiation]\ntemperature = 273\nexposed = 1")
    text = text.replace("interval = 0.01", "interval = 5e-5")
    for part in ("[heat laser]", "[heat beam]", "exposed = 1", "method = lattice",
                 "x = 0.02"):
        check(part in text, "the shortened scene lacks " + part)
    check(frozen or "frozen_heat" not in text, "the shortened scene keeps frozen_heat")
    path = os.path.join(work, "laser_bed_frozen.scene" if frozen else "laser_bed_short.scene")
    with open(path, "w") as f:
        f.write(text)
    return path


def main():
    sinter, mpiexec, scenes, work, np = sys.argv[1:6]
    np = int(np)
    frozen = len(sys.argv) > 6 and sys.argv[6] == "frozen"
    end = "2e-3" if frozen else END
    os.makedirs(work, exist_ok=True)
    scene = shortened(scenes, work, frozen)
    outs = []
    for n in (0, np):
        out = os.path.join(work, "serial" if n == 0 else "np%d" % n)
        shutil.rmtree(out, ignore_errors=True)
        args = [sinter, "run", scene, "-o", out, "--end-time", end]
        cmd = args + ["--progress", "0"] if n == 0 else [mpiexec, "-n", str(n),
                                                          "--oversubscribe"] + args
        p = subprocess.run(cmd, env=ENV, capture_output=True, text=True, timeout=200)
        check(p.returncode == 0, "run on %d ranks: %s" % (n, p.stderr))
        if frozen and n > 0:
            check("no checkpoint" in p.stderr, "no word of the skipped checkpoint: " + p.stderr)
        if p.returncode != 0:
            sys.exit(1)
        outs.append(os.path.join(out, "series.csv"))
    (head_s, rows_s), (head_m, rows_m) = base.series(outs[0]), base.series(outs[1])
    check(head_s == head_m, "headers differ: %s / %s" % (head_s, head_m))
    check("lit particles [1]" in head_s, "no lit columns: %s" % head_s)
    check(len(rows_s) == len(rows_m) == (42 if frozen else 5),
          "rows %d / %d" % (len(rows_s), len(rows_m)))
    if frozen:
        steps = head_s.index("heat steps [1]")
        check(rows_s[-1][head_s.index("frozen [1]")] == "1" and int(rows_s[-1][steps]) >= 20,
              "the bed did not freeze: %s" % rows_s[-1])
        for rs, rm in zip(rows_s, rows_m):
            check(rs[steps:steps + 2] == rm[steps:steps + 2], "heat steps or wake-ups differ")
    lit = head_s.index("lit particles [1]")
    check(float(rows_s[-1][lit]) > 50, "the beams lit %s particles" % rows_s[-1][lit])
    check(frozen or float(rows_s[-1][2]) > 500, "only %s contacts" % rows_s[-1][2])
    if np == 1:
        check(open(outs[0]).read() == open(outs[1]).read(), "np 1: series.csv differs")
    worst = base.compare_series("np %d" % np, head_s, rows_s, rows_m, 1e-12)
    print("laser + beam bed%s, np %d: %d rows, largest relative difference %.3g"
          % (" (frozen)" if frozen else "", np, len(rows_m), worst))
    sys.exit(1 if base.failures else 0)


if __name__ == "__main__":
    main()
