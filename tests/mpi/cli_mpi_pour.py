#!/usr/bin/env python3
"""`mpiexec -n N sinter run` of a scene with a [pour] or a [compact] (src/cli/run_mpi_pour.c,
src/cli/run_mpi.c, issue 44).

usage: cli_mpi_pour.py SINTER MPIEXEC SCENE WORK CASE [NP]

SCENE is tests/mpi/pour_press.scene: 300 spheres poured from a cloud to rest (the pour ends when
the kinetic energy per particle is below 1e-3 J, after 0.5 s at least), then pressed by the top
wall for 0.3 s, with conduction, Joule heating and the network electric model.

CASE
  pour NP     the whole programme on NP ranks and serially. On one rank series.csv is the serial
              text byte for byte (every column, the pour's samples, its end, the press) and the
              pour ends at the same time (--log info's "poured" line). On more: the pour is
              chaotic, so the rows are compared within a relative 1e-10 up to HORIZON only
              (measured at np 2-4: 5e-13 to 0.5 s, 1.1e-11 to 0.6 s; the first row above 1e-10
              at 0.72 s); beyond it the outcome is compared against the spread over the random
              cloud's seed (8 serial seeds, 1-8: the pour's end 1.64 +- 0.088 s, the solid
              fraction at the pour's end 0.512 +- 0.016, at the end of the press
              0.6159 +- 0.0005): the pour's end within 0.25 s of the serial one, those solid
              fractions within 0.05 and 0.0015 (3 standard deviations). The end time counts
              from the pour's end on every rank count: the last row's time is the pour's end +
              0.3 s. The union of the last frame's pieces holds every particle once. The wall
              currents (the network model: the walls are its only sources) sum to 0 within
              1e-6 of the largest in every row where current flows (the pressed bed; measured
              1e-9, the solve's tolerance).
  restart     stopped during the pour (--stop-at 0.8) on 4 ranks and continued from its
              checkpoint.mpi on 2: the pour goes on and ends, the press follows, the series has
              no gap and ends at the pour's end + 0.3 s, its outcome within the seed spread as
              above. Then a run on 1 rank stopped after the pour (at 1.7 s; the serial pour ends
              at 1.6 s) and continued on 3 ranks: the pour is not repeated, the run ends at the
              serial end time with as many rows, the top wall presses at the end and the solid
              fraction is within the seed spread as above.
  compact NP  SCENE is tests/mpi/compact_explicit.scene instead: 200 spheres compacted
              (sinter_pack_compact: rank 0 compacts its copy of the scene's particles before it
              spreads them) and released for 0.02 s with the explicit stepper. The
              compaction's --log info line is the serial one, once. On one rank series.csv is the
              serial text byte for byte; on more, to 0.005 s (the pile is chaotic: measured at
              np 2, 3, 4: 2.9e-12, 8.3e-12, 3.0e-12 at 0.005 s, 5e-11 to 1.4e-10 at 0.006 s,
              1e-9 at 0.009 s), every value within a relative 1e-10.
  refused     on 2 ranks, exit status 1 on every rank and the reason once, from rank 0, within
              the time limit: a pour with a [stepper] temperature_schedule (the furnace the serial
              runner delays to the pour's end), a pour that has not come to rest by its t_max
              (the serial runner's NOT_CONVERGED, with the energy per particle), and a restart
              from a checkpoint.mpi whose pour state (checkpoint.mpi.pour) is missing, and a
              [compact] after a [pour] (the poured bed would have to be gathered).
"""
import os
import re
import shutil
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import cli_mpi_run as base  # noqa: E402  (its check(), failures, series(), vtu_particles())

HORIZON = 0.6  # [s], see above
POURED = re.compile(r"poured: at rest at t = (\S+) s")
# 3 standard deviations of the 8 serial seeds' outcomes (see above)
TOL_POUR_END, TOL_SOLID_POURED, TOL_SOLID_END = 0.25, 0.05, 0.0015
END_AFTER_POUR = 0.3  # the scene's end_time [s]
check = base.check


def poured(err):
    """The pour's end [s] from --log info's line, or None."""
    m = POURED.search(err)
    return float(m.group(1)) if m else None


def run_serial(sinter, scene, out):
    shutil.rmtree(out, ignore_errors=True)
    rc, _, err = base.run([sinter, "run", scene, "-o", out, "--progress", "0", "--log", "info"])
    check(rc == 0, "serial run: " + err)
    return poured(err)


def run_mpi(sinter, mpiexec, np, scene, out, extra=(), clear=True):
    if clear:
        shutil.rmtree(out, ignore_errors=True)
    rc, stdout, err = base.mpi(mpiexec, np, [sinter, "run", scene, "-o", out, "--log", "info",
                                             "--progress", "0"] + list(extra), timeout=240)
    check(rc == 0, "np %d %s: %s" % (np, " ".join(extra), err))
    check(err.count("poured:") <= 1, "the pour's end reported by more than rank 0: " + err)
    return rc, stdout, poured(err)


def value(head, row, name):
    return float(row[head.index(name)])


def outcome(head, rows, pour_end):
    """The solid fractions at the pour's end and at the last row."""
    at = [r for r in rows if abs(float(r[0]) - pour_end) <= 1e-9]
    check(len(at) == 1, "no row at the pour's end %g" % pour_end)
    solid = "solid fraction [1]"
    return (value(head, at[0], solid) if at else float("nan")), value(head, rows[-1], solid)


def compare_outcome(what, ref, got):
    """ref, got: (pour end, head, rows) of the serial and the decomposed run."""
    (te_s, head, rows_s), (te_m, _, rows_m) = ref, got
    check(te_m is not None and abs(te_m - te_s) <= TOL_POUR_END,
          "%s: the pour ended at %s, serially at %g" % (what, te_m, te_s))
    if te_m is None:
        return
    last = float(rows_m[-1][0])
    check(abs(last - (te_m + END_AFTER_POUR)) <= 1e-9,
          "%s: the run ended at %.17g, not the pour's end %g + %g" % (what, last, te_m,
                                                                      END_AFTER_POUR))
    (p_s, e_s), (p_m, e_m) = outcome(head, rows_s, te_s), outcome(head, rows_m, te_m)
    check(abs(p_m - p_s) <= TOL_SOLID_POURED,
          "%s: solid fraction at the pour's end %g, serially %g" % (what, p_m, p_s))
    check(abs(e_m - e_s) <= TOL_SOLID_END,
          "%s: solid fraction at the end %g, serially %g" % (what, e_m, e_s))
    top = value(head, rows_m[-1], "top force [N]")
    check(top > 0.0, "%s: the top wall does not press at the end (%g N)" % (what, top))
    print("%s: pour end %g (serial %g), solid fraction at it %.4f (%.4f), at the end %.5f "
          "(%.5f)" % (what, te_m, te_s, p_m, p_s, e_m, e_s))


def case_pour(sinter, mpiexec, scene, work, np):
    ref, out = os.path.join(work, "serial"), os.path.join(work, "np%d" % np)
    te_s = run_serial(sinter, scene, ref)
    rc, _, te_m = run_mpi(sinter, mpiexec, np, scene, out)
    if rc != 0 or te_s is None:
        check(te_s is not None, "the serial run reports no pour end")
        return
    head_s, rows_s = base.series(os.path.join(ref, "series.csv"))
    head_m, rows_m = base.series(os.path.join(out, "series.csv"))
    check(head_s == head_m, "headers differ: %s / %s" % (head_s, head_m))
    if np == 1:
        check(te_m == te_s, "np 1: the pour ended at %s, serially at %g" % (te_m, te_s))
        check(open(os.path.join(ref, "series.csv")).read() ==
              open(os.path.join(out, "series.csv")).read(), "np 1: series.csv differs")
    worst = base.compare_series("np %d" % np, head_s, rows_s, rows_m, 1e-10, HORIZON)
    compare_outcome("np %d" % np, (te_s, head_s, rows_s), (te_m, head_m, rows_m))
    # Kirchhoff: the walls are the network's only sources, so the currents into them sum to 0
    # within the solve's tolerance (those of ghosts' potentials across ranks included)
    walls = [k for k, name in enumerate(head_m) if name.endswith(" current [A]") and
             not name.startswith(("mean ", "max "))]
    check(len(walls) == 6, "the wall current columns: %s" % walls)
    flowing = 0
    for r in rows_m:
        i = [float(r[k]) for k in walls]
        scale = max(abs(x) for x in i)
        flowing += scale > 0
        check(abs(sum(i)) <= 1e-6 * scale, "t = %s: wall currents %s do not sum to 0" % (r[0], i))
    check(flowing > 0, "no current flows")
    last = len(rows_m) - 1
    pieces = [os.path.join(out, "frames", "frame_%05d_r%04d.vtu" % (last, q)) for q in range(np)]
    ps = base.vtu_particles(pieces)
    check(sorted(ps) == list(range(len(ps))) and len(ps) == 300,
          "the last frame's pieces hold %d particles, not the 300 once" % len(ps))
    print("np %d: %d rows (serial %d), within %.3g of the serial ones to %g s"
          % (np, len(rows_m), len(rows_s), worst, HORIZON))


def case_restart(sinter, mpiexec, scene, work):
    ref = os.path.join(work, "serial")
    te_s = run_serial(sinter, scene, ref)
    head_s, rows_s = base.series(os.path.join(ref, "series.csv"))
    # stopped during the pour on 4 ranks, continued on 2
    out = os.path.join(work, "during")
    checkpoint = os.path.join(out, "checkpoint.mpi")
    rc, stdout, te = run_mpi(sinter, mpiexec, 4, scene, out, ["--stop-at", "0.8"])
    check(rc == 0 and "stopped (--stop-at)" in stdout and te is None,
          "np 4 to 0.8 s: not stopped during the pour: %s" % stdout)
    check(os.path.exists(checkpoint + ".pour"), "no checkpoint.mpi.pour")
    rc, _, te = run_mpi(sinter, mpiexec, 2, scene, out, ["--restart", checkpoint], clear=False)
    if rc != 0:
        return
    head, rows = base.series(os.path.join(out, "series.csv"))
    times = [float(r[0]) for r in rows]
    check(all(abs(b - a - 0.02) < 1e-9 for a, b in zip(times, times[1:])),
          "the series has a gap or a repeat")
    compare_outcome("restart np 4 -> np 2 during the pour", (te_s, head_s, rows_s),
                    (te, head, rows))
    # stopped after the pour on 1 rank (the serial bits), continued on 3
    out = os.path.join(work, "after")
    checkpoint = os.path.join(out, "checkpoint.mpi")
    stop = te_s + 0.1
    rc, _, te = run_mpi(sinter, mpiexec, 1, scene, out, ["--stop-at", "%g" % stop])
    check(rc == 0 and te == te_s, "np 1 to %g s: the pour ended at %s" % (stop, te))
    rc, _, te = run_mpi(sinter, mpiexec, 3, scene, out, ["--restart", checkpoint], clear=False)
    check(te is None, "the pour was repeated after the restart (ended at %s)" % te)
    if rc != 0:
        return
    head, rows = base.series(os.path.join(out, "series.csv"))
    check(len(rows) == len(rows_s), "rows %d, serial %d" % (len(rows), len(rows_s)))
    check(float(rows[-1][0]) == float(rows_s[-1][0]),
          "ended at %s, serially at %s" % (rows[-1][0], rows_s[-1][0]))
    compare_outcome("restart np 1 -> np 3 after the pour", (te_s, head_s, rows_s),
                    (te_s, head, rows))


def case_compact(sinter, mpiexec, scene, work, np):
    ref, out = os.path.join(work, "serial"), os.path.join(work, "np%d" % np)
    end = [] if np == 1 else ["--end-time", "0.005"]
    shutil.rmtree(ref, ignore_errors=True)
    rc, _, err_s = base.run([sinter, "run", scene, "-o", ref, "--progress", "0", "--log",
                             "info"] + end)
    check(rc == 0, "serial run: " + err_s)
    shutil.rmtree(out, ignore_errors=True)
    rc, _, err = base.mpi(mpiexec, np, [sinter, "run", scene, "-o", out, "--log", "info"] + end,
                          timeout=240)
    check(rc == 0, "np %d: %s" % (np, err))
    if rc != 0:
        return
    line = [x for x in err_s.splitlines() if "compacted:" in x]
    check(len(line) == 1 and err.count("compacted:") == 1 and line[0] in err,
          "the compaction's line differs or is not from rank 0 alone: %s / %s" % (line, err))
    head_s, rows_s = base.series(os.path.join(ref, "series.csv"))
    head_m, rows_m = base.series(os.path.join(out, "series.csv"))
    check(head_s == head_m and len(rows_s) == len(rows_m), "headers or row counts differ")
    if np == 1:
        check(open(os.path.join(ref, "series.csv")).read() ==
              open(os.path.join(out, "series.csv")).read(), "np 1: series.csv differs")
    worst = base.compare_series("np %d" % np, head_s, rows_s, rows_m, 1e-10)
    print("compact, np %d: %d rows, largest relative difference %.3g" % (np, len(rows_m), worst))


def refused(sinter, mpiexec, scene, out, reason, extra=()):
    rc, _, err = base.mpi(mpiexec, 2, [sinter, "run", scene, "-o", out] + list(extra),
                          timeout=120)
    check(rc != 0, "%s: ran on 2 ranks" % reason)
    check(reason in err and "MPI" in err, "%s: the reason is missing: %s" % (reason, err))
    check(err.count("sinter (MPI") == 1, "%s: not from rank 0 alone: %s" % (reason, err))
    print("refused:", err.strip().splitlines()[0] if err.strip() else "")


def case_refused(sinter, mpiexec, scene, work):
    text = open(scene).read()
    furnace = os.path.join(work, "furnace.scene")
    with open(furnace, "w") as f:  # (a furnace prescribes the temperatures: no heat models)
        f.write(re.sub(r"\[heat [a-z]+\]\n(?:[^\[\n][^\n]*\n|\n)*", "", text).replace(
            "[stepper]\n", "[stepper]\ntemperature_schedule = 0 300, 1 400\n"))
    refused(sinter, mpiexec, furnace, os.path.join(work, "furnace"), "temperature_schedule")
    short = os.path.join(work, "short.scene")
    with open(short, "w") as f:  # still falling at 0.3 s
        f.write(re.sub(r"\nt_min = .*\nt_max = .*\n", "\nt_min = 0.1\nt_max = 0.3\n", text))
    refused(sinter, mpiexec, short, os.path.join(work, "short"), "did not come to rest")
    both = os.path.join(work, "both.scene")
    with open(both, "w") as f:
        f.write(text + "\n[compact]\nbox_min = -0.6 -0.6 -1\nbox_max = 0.6 0.6 0\n"
                "stop_at_jamming = yes\n")
    refused(sinter, mpiexec, both, os.path.join(work, "both"), "[compact] after a [pour]")
    out = os.path.join(work, "nopour")
    rc, _, _ = run_mpi(sinter, mpiexec, 2, scene, out, ["--stop-at", "0.1"])
    os.remove(os.path.join(out, "checkpoint.mpi.pour"))
    refused(sinter, mpiexec, scene, out, "checkpoint.mpi.pour",
            ["--restart", os.path.join(out, "checkpoint.mpi")])


def main():
    sinter, mpiexec, scene, work, case = sys.argv[1:6]
    os.makedirs(work, exist_ok=True)
    if case == "pour":
        case_pour(sinter, mpiexec, scene, work, int(sys.argv[6]))
    elif case == "compact":
        case_compact(sinter, mpiexec, scene, work, int(sys.argv[6]))
    elif case == "restart":
        case_restart(sinter, mpiexec, scene, work)
    elif case == "refused":
        case_refused(sinter, mpiexec, scene, work)
    else:
        sys.exit("unknown case " + case)
    sys.exit(1 if base.failures else 0)


if __name__ == "__main__":
    main()
