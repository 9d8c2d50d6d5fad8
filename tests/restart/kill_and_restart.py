#!/usr/bin/env python3
"""Output that survives a crash, and Ctrl-C (issue 35).

    kill_and_restart.py SINTER SCENE WORKDIR

The scene (press_network: pour, press, release, with checkpoints every 0.5 s) runs straight
into A. Then, at moments drawn from a seeded generator over the straight run's wall time:
  - SIGKILL: the complete lines of series.csv must be a prefix of A's (a last line without its
    newline is allowed: the kill may fall inside a write); the run is then continued from its
    last checkpoint (or run again where it was killed before the first) into the same
    directory, and the directory must equal A byte for byte;
  - SIGINT and SIGTERM: exit status 130 and 143, a message saying where it stopped and how to
    continue, the plot written; continued, the directory equals A byte for byte.
"""
import filecmp
import os
import random
import shutil
import signal
import subprocess
import sys
import time


def fail(message):
    print("FAIL: " + message)
    sys.exit(1)


def tree(d):
    return sorted(os.path.relpath(os.path.join(r, f), d) for r, _, fs in os.walk(d) for f in fs)


def same_as(a, b, what):
    if tree(a) != tree(b):
        fail("%s: the files differ: %s" % (what, set(tree(a)) ^ set(tree(b))))
    for name in tree(a):
        if not filecmp.cmp(os.path.join(a, name), os.path.join(b, name), shallow=False):
            fail("%s: %s differs from the straight run's" % (what, name))


def complete_lines(path):
    with open(path, "rb") as f:
        data = f.read()
    return data[:data.rfind(b"\n") + 1].split(b"\n")[:-1]


def continue_run(sinter, scene, out):
    checkpoint = os.path.join(out, "checkpoint.bin")
    args = [sinter, "run", scene, "-o", out]
    if os.path.exists(checkpoint):
        args += ["--restart", checkpoint]
    result = subprocess.run(args, capture_output=True, text=True)
    if result.returncode != 0:
        fail("the continued run failed: %s%s" % (result.stdout, result.stderr))


def main():
    sinter, scene, work = sys.argv[1:4]
    shutil.rmtree(work, ignore_errors=True)
    a = os.path.join(work, "A")
    started = time.monotonic()
    subprocess.run([sinter, "run", scene, "-o", a], check=True, capture_output=True)
    wall = time.monotonic() - started
    straight = complete_lines(os.path.join(a, "series.csv"))
    draw = random.Random(35)
    trials = [("kill", signal.SIGKILL)] * 4 + [("int", signal.SIGINT), ("term", signal.SIGTERM)]
    for k, (name, sig) in enumerate(trials):
        out = os.path.join(work, "%s%d" % (name, k))
        process = subprocess.Popen([sinter, "run", scene, "-o", out], stdout=subprocess.PIPE,
                                   stderr=subprocess.PIPE, text=True)
        time.sleep(draw.uniform(0.15, 0.85) * wall)
        process.send_signal(sig)
        stdout, stderr = process.communicate()
        if process.returncode == 0:
            print("%s: the run ended before the signal; trial skipped" % name)
            continue
        lines = complete_lines(os.path.join(out, "series.csv"))
        if not lines or lines != straight[:len(lines)]:
            fail("%s: the series written before the signal is not a prefix of the straight "
                 "run's" % name)
        if sig != signal.SIGKILL:
            if process.returncode != 128 + sig:
                fail("%s: exit status %d, expected %d" % (name, process.returncode, 128 + sig))
            if "interrupted at t = " not in stdout or "--restart" not in stdout:
                fail("%s: no message saying where the run stopped: %r" % (name, stdout))
            if not os.path.exists(os.path.join(out, "series.svg")):
                fail("%s: no plot was drawn" % name)
        continue_run(sinter, scene, out)
        same_as(a, out, name)
        print("%s after %d of %d samples: continued to the straight run's bytes"
              % (name, len(lines) - 1, len(straight) - 1))
    # sinter plot redraws a run's plot from its CSV alone
    os.remove(os.path.join(a, "series.svg"))
    redraw = subprocess.run([sinter, "plot", a, "--title", "press_network"], capture_output=True)
    if redraw.returncode != 0 or not filecmp.cmp(os.path.join(a, "series.svg"),
                                                 os.path.join(work, "kill0", "series.svg"),
                                                 shallow=False):
        fail("sinter plot did not redraw the run's own plot")


if __name__ == "__main__":
    main()
