"""Shared pieces of the Python tests: a small scene file and array backends."""

import os

import sinter
import sinter.particles

try:
    import numpy
except ImportError:
    numpy = None

# A few spheres dropped on a floor: small enough to run in a fraction of a second.
DROP_SCENE = """\
# a small scene for the Python tests
[scene]
name = drop
units = SI

[material glass]
density = 2500
youngs_modulus = 1e7
damping_ratio = 0.2
friction_static = 0.3
friction_dynamic = 0.3
friction_damping_ratio = 0.2

[particles]
method = lattice
material = glass
box_min = 0 0 0.0002
box_max = 0.0035 0.0035 0.003
radius = 0.0005
spacing = 0.00105

[wall floor]
point = 0 0 0
normal = 0 0 1
material = glass

[force hertz_mindlin]
rolling = 0

[force gravity]

[stepper]
dt = 2e-5
skin = 1e-4
end_time = 0.01

[output]
interval = 0.002
vtu = no
checkpoint_interval = 0
"""


def write_scene(directory, text=DROP_SCENE, name="drop.scene"):
    path = os.path.join(directory, name)
    with open(path, "w") as scene:
        scene.write(text)
    return path


def as_lists(array):
    """A field copy, NumPy array or memoryview as nested lists."""
    return array.tolist() if hasattr(array, "tolist") else list(array)


class ArrayBackend:
    """Mixin: run a TestCase's tests with NumPy arrays (use_numpy True) or memoryviews."""

    use_numpy = None

    def setUp(self):
        if self.use_numpy and sinter.particles.numpy is None:
            self.skipTest("NumPy is not installed for this interpreter")
        saved = sinter.particles.USE_NUMPY
        sinter.particles.USE_NUMPY = self.use_numpy
        self.addCleanup(setattr, sinter.particles, "USE_NUMPY", saved)
        super().setUp()
