#!/usr/bin/env python3
"""Restart continues a scene exactly (issue 35), for one scene of examples/scenes.

    scene_restart.py SINTER SCENE WORKDIR

The scene is copied with its neighbours (particle files) into WORKDIR and shortened there (the
end time and output interval below; the two packings also with fewer particles, so that their
compaction stays short). Then:
  1. the straight run, into A;
  2. into B: run with --stop-at t1 (a third of the samples), restart with --stop-at t2 (two
     thirds), restart to the end: every file of B must be byte-identical to A's (series.csv,
     series.svg, the frames, the .pvd, checkpoint.bin);
  3. the checkpoint at t2 restarted into a fresh directory C: C's series rows are A's rows after
     t2, and C's last frame is A's last frame, byte for byte.
For the scenes with a pour, t1 falls in the pour and t2 after it (checked).
Fails (exit 1) with the first difference.
"""
import filecmp
import os
import re
import shutil
import subprocess
import sys

# scene -> (end time [s], output interval [s], {key: value} set in the copy by section)
SHORT = {
    "conduction_box": (0.06, 0.01, {}),
    "copper_lattice": (300, 50, {}),
    "copper_rve": (20, 4, {}),  # periodic cell: format 15, the cell and the links' images
    "die_press": (0.004, 0.0005, {"particles": {"count": "200"}}),
    "copper_packing": (300, 50, {"particles": {"count": "200", "box_max": "0.000394 0.000394 0.000315"},
                                 "compact": {"box_max": "0.000315 0.000315 0.000252"}}),
    "hot_floor": (1.0, 0.1, {}),
    "laser_bed": (0.006, 0.001, {}),
    "mech": (0.02, 0.002, {}),
    "mech_heat": (0.02, 0.002, {}),
    "powder_bed": (0.006, 0.001, {}),  # restarts while [insert] inserts (its checkpoint state)
    "powder_psd": (2e-6, 5e-7, {}),
    "press": (1.6, 0.02, {}),
    "press_bonded": (1.6, 0.02, {}),
    "press_copper": (0.1, 0.005, {"particles": {"count": "60", "box_max": "0.004 0.004 0.015"},
                                   "wall top": {"point": "0 0 0.016",
                                                "schedule": "0 0 0 0,  0.01 0 0 -0.0075"}}),
    "press_network": (1.6, 0.02, {}),
    "press_staggered": (1.6, 0.02, {}),
    "titanium_packing": (480, 60, {"particles": {"count": "400", "box_max": "0.000468 0.000468 0.000936"},
                                   "compact": {"box_max": "0.00036 0.00036 0.00072"}}),
    "vibrated_bed": (0.1, 0.01, {}),
    "vibrated_bed_12hz": (0.1, 0.01, {}),
}


def fail(message):
    print("FAIL: " + message)
    sys.exit(1)


def set_keys(text, section, values):
    """Set key = value in the [section ...] of a scene's text (added if absent)."""
    lines = text.split("\n")
    start = next((k for k, line in enumerate(lines)
                  if re.match(r"\s*\[%s(\s|\])" % section, line)), None)
    if start is None:
        fail("the scene has no [%s] section" % section)
    end = next((k for k in range(start + 1, len(lines)) if lines[k].lstrip().startswith("[")),
               len(lines))
    for key, value in values.items():
        for k in range(start + 1, end):
            if re.match(r"\s*%s\s*=" % key, lines[k]):
                lines[k] = "%s = %s" % (key, value)
                break
        else:
            lines.insert(start + 1, "%s = %s" % (key, value))
            end += 1
    return "\n".join(lines)


def run(sinter, *args, expect=0):
    result = subprocess.run([sinter, "run"] + list(args), capture_output=True, text=True)
    if result.returncode != expect:
        fail("sinter run %s: exit %d, expected %d\n%s%s" % (" ".join(args), result.returncode,
                                                          expect, result.stdout, result.stderr))
    return result


def rows(path):
    with open(path) as f:
        return f.read().split("\n")[1:-1]


def same_trees(a, b):
    left = sorted(os.path.relpath(os.path.join(d, f), a) for d, _, fs in os.walk(a) for f in fs)
    right = sorted(os.path.relpath(os.path.join(d, f), b) for d, _, fs in os.walk(b) for f in fs)
    if left != right:
        fail("the files differ: %s against %s" % (set(left) ^ set(right), b))
    for name in left:
        if not filecmp.cmp(os.path.join(a, name), os.path.join(b, name), shallow=False):
            fail("%s differs between the straight run and the restarted one" % name)


def main():
    sinter, scene_path, work = sys.argv[1:4]
    name = os.path.splitext(os.path.basename(scene_path))[0]
    end, interval, edits = SHORT[name]
    shutil.rmtree(work, ignore_errors=True)
    shutil.copytree(os.path.dirname(os.path.abspath(scene_path)), os.path.join(work, "scenes"))
    scene = os.path.join(work, "scenes", name + ".scene")
    with open(scene) as f:
        text = f.read()
    text = set_keys(text, "output", {"interval": interval, "checkpoint_interval": interval * 3})
    for section, values in edits.items():
        text = set_keys(text, section, values)
    with open(scene, "w") as f:
        f.write(text)
    a, b, c = (os.path.join(work, x) for x in "ABC")
    end_time = ["--end-time", repr(end)]
    run(sinter, scene, "-o", a, *end_time)
    times = [row.split(",")[0] for row in rows(os.path.join(a, "series.csv"))]
    if len(times) < 4:
        fail("the straight run wrote %d samples; the test needs 4 or more" % len(times))
    t1, t2 = times[len(times) // 3], times[2 * len(times) // 3]
    run(sinter, scene, "-o", b, "--stop-at", t1, *end_time)
    run(sinter, scene, "-o", b, "--restart", os.path.join(b, "checkpoint.bin"), "--stop-at", t2,
        *end_time)
    shutil.copy(os.path.join(b, "checkpoint.bin"), os.path.join(work, "at_t2.bin"))
    if "[pour]" in text:  # the pour's end lies between t1 and t2
        log = run(sinter, scene, "-o", os.path.join(work, "probe"), "--restart",
                  os.path.join(work, "at_t2.bin"), "--stop-at", t2, "--log", "info", *end_time)
        if "(the main run)" not in log.stderr:
            fail("t2 = %s is not after the pour: %s" % (t2, log.stderr))
    run(sinter, scene, "-o", b, "--restart", os.path.join(b, "checkpoint.bin"), *end_time)
    same_trees(a, b)
    run(sinter, scene, "-o", c, "--restart", os.path.join(work, "at_t2.bin"), *end_time)
    straight = rows(os.path.join(a, "series.csv"))
    after = rows(os.path.join(c, "series.csv"))
    if not after or straight[-len(after):] != after or len(after) != len(times) - 1 - times.index(t2):
        fail("the rows after the restart into a fresh directory are not the straight run's")
    frames = sorted(os.listdir(os.path.join(a, "frames"))) if os.path.isdir(os.path.join(a, "frames")) else []
    if frames and not filecmp.cmp(os.path.join(a, "frames", frames[-1]),
                                  os.path.join(c, "frames", frames[-1]), shallow=False):
        fail("the last frame differs after the restart into a fresh directory")
    print("%s: restarted at t = %s and %s s: byte-identical to the straight run (%d samples)"
          % (name, t1, t2, len(times)))


if __name__ == "__main__":
    main()
