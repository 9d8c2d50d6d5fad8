"""Ctrl-C, progress reports and exceptions of Python callbacks during a run.

A child process receives SIGINT during Stepper.advance() (and Scene.run()) and must end with
KeyboardInterrupt within a second, its last accepted state readable and a later run able to
continue from it.
"""

import os
import signal
import subprocess
import sys
import tempfile
import time
import unittest

import sinter

from _support import write_scene

PACKAGE_ROOT = os.path.dirname(os.path.dirname(os.path.abspath(sinter.__file__)))

# A run that takes far longer than the test waits: 200 spheres falling for 1000 s in steps of
# 1 us. `observer` and `progress` are set by the variants.
CHILD = """\
import math, sys
import sinter
ctx = sinter.Context()
glass = sinter.Material(ctx, "glass", density=2500.0, youngs_modulus=1e7)
ps = sinter.Particles(ctx)
ps.set_material(0, glass)
ps.add([(0.01 * k, 0.0, 0.0) for k in range(200)], [1e-3] * 200)
forces = [sinter.ForceModel(ctx, "hertz_mindlin"), sinter.ForceModel(ctx, "gravity")]
stepper = sinter.Stepper(ctx, ps, dt=1e-6, forces=forces, observer=OBSERVER)
print("advancing", flush=True)
try:
    stepper.advance(1000.0, progress=PROGRESS)
except KeyboardInterrupt:
    t = stepper.time
    z = [p[2] for p in ps.get("position")]
    assert 0.0 < t < 1000.0 and all(math.isfinite(v) for v in z), (t, z[:3])
    assert abs(z[0] + 0.5 * 9.81 * t * t) < 1e-6, (z[0], t)  # free fall to the state's time
    stepper.advance(t + 1e-4)  # continues from the last accepted state
    print("interrupted at t = %r, continued to %r" % (t, stepper.time), flush=True)
    raise
print("returned normally at t = %r" % stepper.time, flush=True)
"""

QUASISTATIC_CHILD = """\
import sinter
ctx = sinter.Context()
copper = sinter.Material(ctx, "copper", density=8960.0, youngs_modulus=72e9)
ps = sinter.Particles(ctx)
ps.set_material(0, copper)
r = 25e-6
ps.add([(2 * r * (k % 3), 2 * r * (k // 3 % 3), 2 * r * (k // 9)) for k in range(27)],
       [r] * 27, temperature=1293.0)
stepper = sinter.Stepper(ctx, ps, kind="quasistatic", dt=1e-6)
print("advancing", flush=True)
try:
    stepper.advance(1e12)
except KeyboardInterrupt:
    stats = stepper.sintering_stats()
    assert stats.links == 54 and stats.shrinkage[0] > 0.0, stats
    print("interrupted at t = %r s, shrinkage %r" % (stepper.time, stats.shrinkage[0]),
          flush=True)
    raise
print("returned normally at t = %r" % stepper.time, flush=True)
"""

SCENE_CHILD = """\
import os, sys
import sinter
ctx = sinter.Context()
scene = sinter.Scene(ctx, sys.argv[1])
scene.end_time = 1e6
print("advancing", flush=True)
try:
    scene.run(sys.argv[2])
except KeyboardInterrupt:
    t = scene.stepper.time
    assert os.path.exists(os.path.join(sys.argv[2], "checkpoint.bin"))
    print("interrupted at t = %r" % t, flush=True)
    raise
"""


def child_env():
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [PACKAGE_ROOT, env.get("PYTHONPATH")]))
    return env


class CtrlCTest(unittest.TestCase):
    def interrupt(self, code, args=(), delay=0.3):
        """Run `code` in a child, send SIGINT `delay` s after it says "advancing"; return
        (seconds from SIGINT to exit, return code, stdout, stderr)."""
        child = subprocess.Popen([sys.executable, "-c", code] + list(args), env=child_env(),
                                 stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                 universal_newlines=True)
        try:
            first = child.stdout.readline()
            self.assertEqual(first.strip(), "advancing", child.stderr.read() if not first else "")
            time.sleep(delay)
            start = time.monotonic()
            child.send_signal(signal.SIGINT)
            out, err = child.communicate(timeout=20)
            return time.monotonic() - start, child.returncode, out, err
        finally:
            if child.poll() is None:
                child.kill()
                child.communicate()

    def check_interrupted(self, seconds, returncode, out, err):
        self.assertIn("KeyboardInterrupt", err)
        self.assertNotIn("returned normally", out)
        self.assertIn("interrupted at t = ", out, err)
        self.assertIn(returncode, (-signal.SIGINT, 130, 1))  # Python re-raises SIGINT: -2
        # Under a second on an idle machine (issue 36's figure; the runs would take far longer
        # than the test waits); CI runs this beside other tests on two cores, where a child's
        # exit (the checkpoint, the plot, the interpreter's shutdown) can take a second more:
        # the bound is set for that, a time, not the physics, is what is loose here.
        self.assertLess(seconds, 5.0, "Ctrl-C took %.3f s to end the child" % seconds)

    def test_advance(self):
        code = CHILD.replace("OBSERVER", "None").replace("PROGRESS", "None")
        self.check_interrupted(*self.interrupt(code))

    def test_advance_with_an_observer(self):
        # the case: with an observer, advance(0.5) used to return normally
        code = CHILD.replace("OBSERVER", "lambda st, t: None").replace("PROGRESS", "None")
        self.check_interrupted(*self.interrupt(code))

    def test_advance_with_a_progress_bar(self):
        code = ("import sys; sys.modules['tqdm'] = None  # the plain line\n"
                + CHILD.replace("OBSERVER", "None").replace("PROGRESS", "True"))
        seconds, returncode, out, err = self.interrupt(code)
        self.check_interrupted(seconds, returncode, out, err)
        self.assertIn("sinter: t = ", err)
        self.assertIn("of 1000 s", err)

    def test_quasistatic_advance(self):
        self.check_interrupted(*self.interrupt(QUASISTATIC_CHILD))

    def test_scene_run_writes_its_checkpoint(self):
        with tempfile.TemporaryDirectory() as directory:
            scene = write_scene(directory)
            out = os.path.join(directory, "out")
            self.check_interrupted(*self.interrupt(SCENE_CHILD, [scene, out]))
            self.assertTrue(os.path.exists(os.path.join(out, "checkpoint.bin")))
            with sinter.Context() as ctx, sinter.Scene(ctx, scene) as again:
                again.restart(os.path.join(out, "checkpoint.bin"))
                self.assertGreater(again.stepper.time, 0.0)
                again.end_time = again.stepper.time + 1e-3
                self.assertTrue(again.run(out))


class CallbackExceptionTest(unittest.TestCase):
    def setUp(self):
        self.ctx = sinter.Context()
        self.addCleanup(self.ctx.close)
        glass = sinter.Material(self.ctx, "glass", density=2500.0, youngs_modulus=1e7)
        self.particles = sinter.Particles(self.ctx)
        self.particles.set_material(0, glass)
        self.particles.add([(0.0, 0.0, 0.0)], [1e-3])
        self.stepper = sinter.Stepper(self.ctx, self.particles, dt=1e-4,
                                      forces=[sinter.ForceModel(self.ctx, "gravity")])
        self.addCleanup(self.stepper.close)

    def test_keyboard_interrupt_in_an_observer_propagates(self):
        def observer(stepper, t):
            if t >= 0.01:
                raise KeyboardInterrupt

        self.stepper.observer = observer
        with self.assertRaises(KeyboardInterrupt):
            self.stepper.advance(0.5)
        self.assertAlmostEqual(self.stepper.time, 0.01, delta=1e-4)
        self.stepper.observer = None
        self.assertEqual(self.stepper.advance(0.02), 0.02)

    def test_exception_in_progress_propagates(self):
        def progress(t, t_end):
            raise RuntimeError("from progress")

        with self.assertRaisesRegex(RuntimeError, "from progress"):
            self.stepper.advance(0.1, progress=progress)
        self.assertLess(self.stepper.time, 0.1)

    def test_progress_reports_times_up_to_the_end(self):
        seen = []
        calls = []
        self.stepper.observer = lambda st, t: calls.append(t)
        self.assertEqual(self.stepper.advance(0.05, progress=lambda t, end: seen.append((t, end))),
                         0.05)
        self.assertEqual(seen[-1], (0.05, 0.05))
        self.assertEqual([t for t, _ in seen], sorted(t for t, _ in seen))
        self.assertEqual(len(calls), 500)  # the stepper's own observer still ran every step
        calls.clear()
        self.stepper.advance(0.06)  # and stays installed afterwards
        self.assertEqual(len(calls), 100)
        with self.assertRaises(TypeError):
            self.stepper.advance(0.07, progress="yes")

    def test_request_stop_from_python(self):
        self.ctx.request_stop()
        with self.assertRaises(sinter.Interrupted) as caught:
            self.stepper.advance(0.1)
        self.assertIs(caught.exception.status, sinter.Status.ERR_INTERRUPTED)
        self.assertEqual(self.stepper.time, 0.0)
        self.assertEqual(self.stepper.advance(0.01), 0.01)  # the request was withdrawn


if __name__ == "__main__":
    unittest.main()
