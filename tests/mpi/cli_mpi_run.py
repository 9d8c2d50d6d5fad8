#!/usr/bin/env python3
"""`mpiexec -n N sinter run` (src/cli/run_mpi.c) against the serial `sinter run` (issue 44).

usage: cli_mpi_run.py SINTER MPIEXEC SCENES WORK CASE [NP]

CASE
  series NP   mech.scene to END on NP ranks and serially: on one rank every column of
              series.csv is the serial text byte for byte; on more, every value within a
              relative 1e-10 (the per-rank partial sums and the forces summed in another order
              differ by round-off that the short horizon does not amplify past it; the solid
              fraction's lenses and the contacts are counted once, by the owner of the pair's
              smaller id). The union of the last frame's VTU pieces, sorted by id, equals the
              serial frame within 1e-10 of the box.
  heat NP     the same for mech_heat.scene (conduction: the wall heat-flow columns from the
              ranks' snapshots, the temperatures).
  restart     mech.scene stopped at T1 (--stop-at) on 4 ranks, continued from its
              checkpoint.mpi on 2 ranks to END: the series runs on without a gap, and its last
              row agrees with the straight serial run within a relative 1e-10 (the restart
              reorders the particles, so the sums' round-off differs, within the same horizon;
              its first step builds the neighbour lists afresh, so it counts at most one
              rebuild more).
  staggered NP
              press_staggered.scene without its [pour] (the random cloud falls onto the floor
              under the moving top wall; the staggered stepper, the averaged electric model,
              conduction and Joule heating) to 0.1 s on NP ranks and serially: on one rank
              series.csv is the serial text byte for byte (the currents and the staggered
              stepper's columns included); on more, every value within a relative 1e-10,
              except the neighbour rebuilds: a migration refused inside a fixed-point attempt
              redistributes again at the next accepted state, so a decomposed run may count
              up to two more.
  qs NP       copper_lattice.scene (the quasi-static stepper: 27 touching copper spheres,
              7DOF necks, bonded links, K u = f) to QS_END on NP ranks and serially. The
              contacts are the links, each counted once by the rank that owns its smaller id
              (the serial runner's contacts column counts the pairs that overlapped at the start
              of the advance call, a sample behind): contacts = links and coordination = 2
              links / particles in every row after the first; in the first (no links yet) the
              overlapping pairs, which must equal those counted here from the serial frame with
              the contact search's test (27 of the lattice's 54 touching pairs overlap by
              round-off). The neighbour rebuilds count one per advance call
              after the first (each call redistributes the particles and makes the ghosts again;
              the serial run builds once): 1, 1, 2, 3, ... On one rank
              every other column is the serial text byte for byte. On more, the split solve
              (block-Jacobi PCG over the ranks, against the serial block SSOR) stops at another
              approximation of the same target |r| <= 1e-7 |f|, and the necks' CVODE carries the
              difference on: every value must lie within the serial run's own spread when its
              solve target moves by a decade, 1e-7 to 1e-6 (measured at 300 s: 3.1e-9, the
              neck radii; the decomposed runs differ by at most 1.0e-9). Then the same scene with
              the target at 1e-12 in both runs: every value within a relative 1e-10 (measured
              1.2e-11, the shrinkage), and the union of the last frame's pieces, by id, the
              serial frame within 1e-12 of the lattice's edge.
  qsrestart   copper_lattice.scene stopped at QS_T1 on 4 ranks, continued from its
              checkpoint.mpi on 2 ranks to QS_END: the links travel with the records of their
              smaller ids, the first step's extents and green density with the global part
              (the shrinkage's reference: taken again, the shrinkage would restart from 0);
              the last row within the same decade's spread of the straight serial run.
  qspacking NP
              the same for copper_packing.scene to QS_PACK_END (805 spheres compacted by
              [compact] on rank 0 before the distribution, as the serial set-up compacts them;
              1797 overlapping pairs at the start, 1971 links at 100 s), without the target-1e-12
              part: at np 1 the serial text byte for byte but the contacts after the first row;
              at np 2 within the serial run's spread 1e-7 -> 1e-6 (measured 1.2e-8 against
              1.45e-7, the neck radii).
  refused     mech.scene with an [output] track (its series columns are not written over the
              ranks yet) and a periodic quasi-static scene (copper_rve): exit
              status 1 on every rank, the reason on stderr, within the time limit (no rank
              waits forever).
              (Scenes with a [pour]: cli_mpi_pour.py.)
"""
import base64
import os
import re
import shutil
import struct
import subprocess
import sys

# [s]: the lowest layer meets the floor from 0.004 s on (about 1000 contacts at 0.02 s); the
# round-off of a different summation order grows about 10x per 0.002 s once the pile forms
# (1e-14 at 0.014 s, 2e-11 at 0.02 s, 1e-8 at 0.026 s, 1e-2 at 0.036 s on 2 or 4 ranks), so
# the horizon of the 1e-10 comparison ends at 0.02 s
END = "0.02"
T1 = "0.01"
# [s]: six samples of copper_lattice.scene (interval 50 s), a few seconds at np 4
QS_END = "300"
QS_T1 = "150"
# [s]: copper_packing.scene's compaction (on rank 0) and its first sample (interval 100 s)
QS_PACK_END = "100"
ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
           OMP_NUM_THREADS="1")
failures = []


def check(ok, what):
    if not ok:
        failures.append(what)
        print("FAIL:", what)


def run(cmd, timeout=120):
    p = subprocess.run(cmd, env=ENV, capture_output=True, text=True, timeout=timeout)
    return p.returncode, p.stdout, p.stderr


def mpi(mpiexec, np, args, timeout=120):
    return run([mpiexec, "-n", str(np), "--oversubscribe"] + args, timeout)


def series(path):
    with open(path) as f:
        lines = f.read().splitlines()
    return lines[0].split(","), [line.split(",") for line in lines[1:]]


def rel_diff(a, b):
    """|a - b| / max(|a|, |b|) of two series values as written (0 where both are 0)."""
    x, y = float(a), float(b)
    scale = max(abs(x), abs(y))
    return abs(x - y) / scale if scale > 0 else 0.0


def compare_series(what, head, rows_s, rows_m, tol, horizon=float("inf")):
    """Every value of rows_m within tol (relative) of rows_s's, row by row up to the time
    horizon; returns the largest relative difference."""
    worst = 0.0
    for rs, rm in zip(rows_s, rows_m):
        if float(rs[0]) > horizon:
            break
        for k, (a, b) in enumerate(zip(rs, rm)):
            rel = rel_diff(a, b)
            worst = max(worst, rel)
            check(rel <= tol, "%s, t = %s, %s: %s vs %s" % (what, rs[0], head[k], a, b))
    return worst


def vtu_array(text, name):
    """The values of the VTU's array NAME (ASCII or base64 binary)."""
    m = re.search(r'(<DataArray[^>]*Name="%s"[^>]*>)(.*?)</DataArray>' % name, text, re.S)
    tag, body = m.group(1), m.group(2).strip()
    if 'format="binary"' not in tag:
        return [float(v) if "Float" in tag else int(v) for v in body.split()]
    # base64: a UInt64 byte count (12 characters), then the values
    raw = base64.b64decode(body[12:])
    code = {"Float64": "d", "UInt64": "Q", "Int64": "q", "Int32": "i"}[
        re.search(r'type="(\w+)"', tag).group(1)]
    return list(struct.unpack("<%d%s" % (len(raw) // struct.calcsize(code), code), raw))


def vtu_particles(paths):
    """id -> position of every particle in the VTU pieces."""
    out = {}
    for path in paths:
        text = open(path).read()
        ids = [int(v) for v in vtu_array(text, "id")]
        pos = [float(v) for v in vtu_array(text, "position")]
        for k, i in enumerate(ids):
            check(i not in out, "particle %d in two pieces" % i)
            out[i] = pos[3 * k:3 * k + 3]
    return out


def serial(sinter, scene, work):
    out = os.path.join(work, "serial")
    shutil.rmtree(out, ignore_errors=True)
    rc, _, err = run([sinter, "run", scene, "-o", out, "--end-time", END, "--progress", "0"])
    check(rc == 0, "serial run: " + err)
    return out


def case_series(sinter, mpiexec, scenes, work, np, name="mech"):
    scene = os.path.join(scenes, name + ".scene")
    ref = serial(sinter, scene, work)
    out = os.path.join(work, "np%d" % np)
    shutil.rmtree(out, ignore_errors=True)
    rc, _, err = mpi(mpiexec, np, [sinter, "run", scene, "-o", out, "--end-time", END])
    check(rc == 0, "mpi run np %d: %s" % (np, err))
    if rc != 0:
        return
    head_s, rows_s = series(os.path.join(ref, "series.csv"))
    head_m, rows_m = series(os.path.join(out, "series.csv"))
    check(head_s == head_m, "headers differ: %s / %s" % (head_s, head_m))
    check(len(rows_s) == len(rows_m), "rows %d / %d" % (len(rows_s), len(rows_m)))
    worst = 0.0
    for rs, rm in zip(rows_s, rows_m):
        for k, (a, b) in enumerate(zip(rs, rm)):
            if np == 1:
                check(a == b, "np 1, t = %s, %s: %s != %s" % (rs[0], head_s[k], a, b))
            else:
                rel = rel_diff(a, b)
                worst = max(worst, rel)
                check(rel <= 1e-10, "np %d, t = %s, %s: %s vs %s" % (np, rs[0], head_s[k], a, b))
    last = len(rows_s) - 1
    pieces = [os.path.join(out, "frames", "frame_%05d_r%04d.vtu" % (last, q)) for q in range(np)]
    pvtu = open(os.path.join(out, "frames", "frame_%05d.pvtu" % last)).read()
    check(pvtu.count("<Piece ") == np, "the .pvtu lists %d pieces" % np)
    check(os.path.exists(os.path.join(out, name + ".pvd")), "no %s.pvd" % name)
    ps = vtu_particles(pieces)
    ss = vtu_particles([os.path.join(ref, "frames", "frame_%05d.vtu" % last)])
    check(sorted(ps) == sorted(ss), "the pieces' ids are not the serial frame's")
    box = 0.0105
    dev = max((abs(a - b) for i in ss if i in ps for a, b in zip(ss[i], ps[i])), default=0.0)
    check(dev <= 1e-10 * box, "positions differ by %g m" % dev)
    print("np %d: %d rows, largest relative difference %.3g, positions within %.3g m"
          % (np, len(rows_m), worst, dev))


def case_staggered(sinter, mpiexec, scenes, work, np):
    text = open(os.path.join(scenes, "press_staggered.scene")).read()
    text = re.sub(r"\n\[pour\]\n(?:[^\[\n][^\n]*\n)*", "\n", text)
    check("[pour]" not in text, "the [pour] section is still there")
    scene = os.path.join(work, "press_staggered_nopour.scene")
    with open(scene, "w") as f:
        f.write(text)
    outs = []
    for n in (0, np):
        out = os.path.join(work, "serial" if n == 0 else "np%d" % n)
        shutil.rmtree(out, ignore_errors=True)
        args = [sinter, "run", scene, "-o", out, "--end-time", "0.1", "--progress", "0"]
        rc, _, err = run(args) if n == 0 else mpi(mpiexec, n, args[:-2])
        check(rc == 0, "run on %d ranks: %s" % (n, err))
        if rc != 0:
            return
        outs.append(series(os.path.join(out, "series.csv")))
    (head_s, rows_s), (head_m, rows_m) = outs
    check(head_s == head_m, "headers differ: %s / %s" % (head_s, head_m))
    check("contraction [1]" in head_s and "max particle current [A]" in head_s,
          "the staggered and electric columns are missing: %s" % head_s)
    check(len(rows_s) == len(rows_m), "rows %d / %d" % (len(rows_s), len(rows_m)))
    worst = 0.0
    for rs, rm in zip(rows_s, rows_m):
        for k, (a, b) in enumerate(zip(rs, rm)):
            if np == 1:
                check(a == b, "np 1, t = %s, %s: %s != %s" % (rs[0], head_s[k], a, b))
            elif head_s[k] == "neighbour rebuilds [1]":
                check(0 <= int(float(b)) - int(float(a)) <= 2, "rebuilds %s vs %s" % (a, b))
            elif a != "nan" or b != "nan":
                rel = rel_diff(a, b)
                worst = max(worst, rel)
                check(rel <= 1e-10, "np %d, t = %s, %s: %s vs %s" % (np, rs[0], head_s[k], a, b))
    print("staggered, np %d: %d rows, largest relative difference %.3g" % (np, len(rows_m), worst))


def case_restart(sinter, mpiexec, scenes, work):
    scene = os.path.join(scenes, "mech.scene")
    ref = serial(sinter, scene, work)
    out = os.path.join(work, "restart")
    shutil.rmtree(out, ignore_errors=True)
    rc, out4, err = mpi(mpiexec, 4, [sinter, "run", scene, "-o", out, "--end-time", END,
                                     "--stop-at", T1])
    check("stopped (--stop-at)" in out4, "no stop message: " + out4)
    check(rc == 0, "np 4 to %s: %s" % (T1, err))
    rc, _, err = mpi(mpiexec, 2, [sinter, "run", scene, "-o", out, "--end-time", END,
                                  "--restart", os.path.join(out, "checkpoint.mpi")])
    check(rc == 0, "np 2 from the checkpoint: %s" % err)
    if rc != 0:
        return
    head, rows = series(os.path.join(out, "series.csv"))
    _, rows_s = series(os.path.join(ref, "series.csv"))
    times = [float(r[0]) for r in rows]
    check(all(b > a for a, b in zip(times, times[1:])), "times not increasing")
    check(len(rows) == len(rows_s), "rows %d, serial %d" % (len(rows), len(rows_s)))
    worst = 0.0
    for k, (a, b) in enumerate(zip(rows_s[-1], rows[-1])):
        if head[k] == "neighbour rebuilds [1]":  # the restart builds its lists afresh
            check(int(float(b)) - int(float(a)) in (0, 1), "rebuilds %s vs %s" % (a, b))
            continue
        rel = rel_diff(a, b)
        worst = max(worst, rel)
        check(rel <= 1e-10, "restart, last row, %s: %s vs %s" % (head[k], a, b))
    check(os.path.exists(os.path.join(out, "frames", "frame_%05d.pvtu" % (len(rows) - 1))),
          "no last frame")
    print("restart np 4 -> np 2: %d rows, last row within %.3g" % (len(rows), worst))


def qs_scene(scenes, work, rtol, name="copper_lattice"):
    """NAME.scene with the solve's target qs_solve_rtol = rtol (None: the scene's)."""
    src = os.path.join(scenes, name + ".scene")
    if rtol is None:
        return src
    text = open(src).read().replace("[stepper]\n", "[stepper]\nqs_solve_rtol = %s\n" % rtol)
    check("qs_solve_rtol" in text, "no [stepper] section to set the target in")
    path = os.path.join(work, "%s_rtol%s.scene" % (name, rtol))
    with open(path, "w") as f:
        f.write(text)
    return path


def qs_serial(sinter, scene, out, end):
    shutil.rmtree(out, ignore_errors=True)
    rc, _, err = run([sinter, "run", scene, "-o", out, "--end-time", end, "--progress", "0"],
                     timeout=300)
    check(rc == 0, "serial run of %s: %s" % (scene, err))
    return series(os.path.join(out, "series.csv"))


def qs_spread(sinter, scenes, work, name, end):
    """The serial run's largest relative change when its solve target moves 1e-7 -> 1e-6."""
    head, a = qs_serial(sinter, qs_scene(scenes, work, None, name), os.path.join(work, "serial"),
                        end)
    _, b = qs_serial(sinter, qs_scene(scenes, work, "1e-6", name),
                     os.path.join(work, "serial_1e-6"), end)
    spread = max(rel_diff(x, y) for ra, rb in zip(a, b) for x, y in zip(ra, rb))
    check(spread > 0.0, "the serial run does not move with its target")
    return head, a, spread


def overlapping_pairs(frame):
    """The pairs of the ASCII frame's spheres with d^2 < (r_i + r_j)^2, d > 0 (the contact
    search's test, in the same double arithmetic)."""
    text = open(frame).read()
    x, r = vtu_array(text, "position"), vtu_array(text, "radius")
    n, count = len(r), 0
    for i in range(n):
        for j in range(i + 1, n):
            dx, dy, dz = x[3 * j] - x[3 * i], x[3 * j + 1] - x[3 * i + 1], x[3 * j + 2] - x[3 * i + 2]
            d2, rs = dx * dx + dy * dy + dz * dz, r[i] + r[j]
            count += d2 < rs * rs and d2 != 0.0
    return count, n


def qs_compare(head, rows_s, rows_m, np, tol, what, first_pairs, n):
    """The MPI series against the serial one (see the module's text); the largest difference.
    first_pairs: the overlapping pairs of the first row's state (None: not the first row)."""
    check(len(rows_s) == len(rows_m), "%s: rows %d / %d" % (what, len(rows_s), len(rows_m)))
    col = {name: k for k, name in enumerate(head)}
    worst = 0.0
    for row, (rs, rm) in enumerate(zip(rows_s, rows_m)):
        links = float(rm[col["links [1]"]])
        contacts = float(rm[col["contacts [1]"]])
        expected = first_pairs if row == 0 and first_pairs is not None else links
        check(contacts == expected, "%s, t = %s: contacts %s, expected %s (links %s)"
              % (what, rm[0], contacts, expected, links))
        check(rel_diff(rm[col["coordination number [1]"]], 2.0 * contacts / n) < 1e-15,
              "%s, t = %s: coordination %s" % (what, rm[0], rm[col["coordination number [1]"]]))
        for k, (a, b) in enumerate(zip(rs, rm)):
            name = head[k]
            if name in ("contacts [1]", "coordination number [1]"):
                continue
            if name == "neighbour rebuilds [1]":
                continue  # one per advance call: checked by the caller where it knows them
            if np == 1:
                check(a == b, "np 1, t = %s, %s: %s != %s" % (rs[0], name, a, b))
            else:
                worst = max(worst, rel_diff(a, b))
                check(rel_diff(a, b) <= tol, "%s, t = %s, %s: %s vs %s (tolerance %.3g)"
                      % (what, rs[0], name, a, b, tol))
    return worst


def case_qs(sinter, mpiexec, scenes, work, np, name="copper_lattice", end=QS_END, tight=True):
    head, rows_s, spread = qs_spread(sinter, scenes, work, name, end)
    pairs, n = overlapping_pairs(os.path.join(work, "serial", "frames", "frame_00000.vtu"))
    out = os.path.join(work, "np%d" % np)
    shutil.rmtree(out, ignore_errors=True)
    rc, _, err = mpi(mpiexec, np, [sinter, "run", qs_scene(scenes, work, None, name), "-o", out,
                                   "--end-time", end], timeout=300)
    check(rc == 0, "mpi run np %d: %s" % (np, err))
    if rc != 0:
        return
    head_m, rows_m = series(os.path.join(out, "series.csv"))
    check(head == head_m, "headers differ: %s / %s" % (head, head_m))
    check("relative density [1]" in head and "solid fraction [1]" in head,
          "the sintering columns are missing: %s" % head)
    worst = qs_compare(head, rows_s, rows_m, np, spread, "np %d" % np, pairs, n)
    rebuilds = [int(float(r[head.index("neighbour rebuilds [1]")])) for r in rows_m]
    check(rebuilds == [max(1, k) for k in range(len(rows_m))], "rebuilds %s" % rebuilds)
    print("%s np %d: %d rows, %d overlapping pairs at the start; default target: largest "
          "relative difference %.3g (the serial run's spread 1e-7 -> 1e-6: %.3g)"
          % (name, np, len(rows_m), pairs, worst, spread))
    if not tight:
        return
    # the exchange itself, without the solve's approximation: the target at 1e-12 in both
    scene12 = qs_scene(scenes, work, "1e-12", name)
    head12, rows12 = qs_serial(sinter, scene12, os.path.join(work, "serial_1e-12"), end)
    out12 = os.path.join(work, "np%d_1e-12" % np)
    shutil.rmtree(out12, ignore_errors=True)
    rc, _, err = mpi(mpiexec, np, [sinter, "run", scene12, "-o", out12, "--end-time", end])
    check(rc == 0, "mpi run np %d, target 1e-12: %s" % (np, err))
    if rc != 0:
        return
    _, rows12_m = series(os.path.join(out12, "series.csv"))
    worst12 = qs_compare(head12, rows12, rows12_m, np, 1e-10, "np %d, target 1e-12" % np,
                         pairs, n)
    last = len(rows12_m) - 1
    pieces = [os.path.join(out12, "frames", "frame_%05d_r%04d.vtu" % (last, q)) for q in range(np)]
    ps = vtu_particles(pieces)
    ss = vtu_particles([os.path.join(work, "serial_1e-12", "frames", "frame_%05d.vtu" % last)])
    check(sorted(ps) == sorted(ss), "the pieces' ids are not the serial frame's")
    edge = 150e-6
    dev = max((abs(a - b) for i in ss if i in ps for a, b in zip(ss[i], ps[i])), default=0.0)
    check(dev <= 1e-12 * edge, "positions differ by %g m" % dev)
    print("target 1e-12: largest relative difference %.3g, positions within %.3g m"
          % (worst12, dev))


def case_qsrestart(sinter, mpiexec, scenes, work):
    head, rows_s, spread = qs_spread(sinter, scenes, work, "copper_lattice", QS_END)
    scene = qs_scene(scenes, work, None)
    out = os.path.join(work, "restart")
    shutil.rmtree(out, ignore_errors=True)
    rc, out4, err = mpi(mpiexec, 4, [sinter, "run", scene, "-o", out, "--end-time", QS_END,
                                     "--stop-at", QS_T1])
    check(rc == 0 and "stopped (--stop-at)" in out4, "np 4 to %s: %s %s" % (QS_T1, out4, err))
    rc, _, err = mpi(mpiexec, 2, [sinter, "run", scene, "-o", out, "--end-time", QS_END,
                                  "--restart", os.path.join(out, "checkpoint.mpi")])
    check(rc == 0, "np 2 from the checkpoint: %s" % err)
    if rc != 0:
        return
    head_m, rows = series(os.path.join(out, "series.csv"))
    check(head == head_m, "headers differ")
    times = [float(r[0]) for r in rows]
    check(times == [float(r[0]) for r in rows_s], "times %s" % times)
    worst = qs_compare(head, rows_s[-1:], rows[-1:], 2, spread, "restart, last row", None, 27)
    print("qs restart np 4 -> np 2: %d rows, last row within %.3g (spread %.3g)"
          % (len(rows), worst, spread))


def case_refused(sinter, mpiexec, scenes, work):
    # mech.scene following particles 0 and 1 in its series ([output] track: not written over
    # the ranks yet)
    followed = os.path.join(work, "mech_followed.scene")
    with open(os.path.join(scenes, "mech.scene")) as f, open(followed, "w") as g:
        g.write(f.read().replace("[output]\n", "[output]\ntrack = 0 1\n", 1).replace(
            "file = mech_n10.xyz", "file = " + os.path.join(scenes, "mech_n10.xyz"), 1))
    for path, reason in ((followed, "[output] track"),
                         (os.path.join(scenes, "copper_rve.scene"), "periodic axes")):
        name = os.path.basename(path)
        out = os.path.join(work, "refused")
        rc, _, err = mpi(mpiexec, 2, [sinter, "run", path, "-o", out], timeout=60)
        check(rc != 0, "%s ran on 2 ranks" % name)
        check(reason in err and "MPI" in err, "%s: the reason is missing: %s" % (name, err))
        check(err.count("sinter (MPI") == 1, "%s: not from rank 0 alone: %s" % (name, err))
        print(name, "refused:", err.strip().splitlines()[0] if err.strip() else "")


def main():
    sinter, mpiexec, scenes, work, case = sys.argv[1:6]
    os.makedirs(work, exist_ok=True)
    if case == "series":
        case_series(sinter, mpiexec, scenes, work, int(sys.argv[6]))
    elif case == "heat":
        case_series(sinter, mpiexec, scenes, work, int(sys.argv[6]), "mech_heat")
    elif case == "staggered":
        case_staggered(sinter, mpiexec, scenes, work, int(sys.argv[6]))
    elif case == "restart":
        case_restart(sinter, mpiexec, scenes, work)
    elif case == "qs":
        case_qs(sinter, mpiexec, scenes, work, int(sys.argv[6]))
    elif case == "qspacking":
        case_qs(sinter, mpiexec, scenes, work, int(sys.argv[6]), "copper_packing", QS_PACK_END,
                tight=False)
    elif case == "qsrestart":
        case_qsrestart(sinter, mpiexec, scenes, work)
    elif case == "refused":
        case_refused(sinter, mpiexec, scenes, work)
    else:
        sys.exit("unknown case " + case)
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
