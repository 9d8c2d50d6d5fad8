"""Run by .ci/run from outside the repository with the interpreter of a fresh virtual environment
into which the wheel of bindings/python was installed offline: the package loads the library
bundled in it (not the source tree's, not SINTER_LIBRARY, not LD_LIBRARY_PATH) and runs a small
simulation, a particle settling on a floor under gravity (the static wall force is its weight)."""

import math
import os
import sys

for variable in ("SINTER_LIBRARY", "LD_LIBRARY_PATH", "PYTHONPATH"):
    if os.environ.get(variable):
        sys.exit("check_installed: unset %s first" % variable)

import sinter  # noqa: E402

package_dir = os.path.dirname(os.path.realpath(sinter.__file__))
library = os.path.realpath(sinter.library_path)
if os.path.dirname(library) != package_dir:
    sys.exit("check_installed: loaded %s, not the library bundled in %s" % (library, package_dir))
print("sinter %s from %s" % (sinter.version_string(), library))

radius, density, g = 1e-3, 3000.0, 9.81
with sinter.Context() as ctx:
    grain = sinter.Material(ctx, "grain", density=density, youngs_modulus=1e6)
    grain["damping_ratio"] = 1.0
    ps = sinter.Particles(ctx)
    ps.set_material(0, grain)
    ps.add([(0.0, 0.0, radius)], [radius], temperature=300.0)
    walls = sinter.Walls(ctx)
    floor = walls.add_plane((0, 0, 0), (0, 0, 1), grain)
    st = sinter.Stepper(ctx, ps, walls, dt=2e-5, domain=((-0.01,) * 3, (0.01,) * 3),
                        forces=[sinter.ForceModel(ctx, "hertz_mindlin"),
                                sinter.ForceModel(ctx, "gravity")])
    st.advance(0.2)
    weight = density * 4.0 / 3.0 * math.pi * radius ** 3 * g
    force = abs(walls.force(floor)[2])
    print("t = %.3f s, %d steps, floor force %.4e N, weight %.4e N" % (
        st.time, st.stats.steps, force, weight))
    if abs(force - weight) > 1e-3 * weight:
        sys.exit("check_installed: the floor force is not the weight")
