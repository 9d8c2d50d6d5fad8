"""Build libsinter.so from this repository with its CMake and put it inside the package.

The metadata is in pyproject.toml; this file only adds the library. `pip install
./bindings/python` (online) or, without any package index,
`pip install --no-build-isolation --no-index ./bindings/python` with Debian's
python3-setuptools, python3-wheel and cmake builds a wheel whose sinter/ holds
libsinter.so, which sinter._lib loads before anything else. The wheel is tagged for
this platform (py3-none-linux_x86_64, say): the library is loaded through ctypes,
so any Python 3 will do, but only on a system like the one that built it (its
SUNDIALS and OpenMP libraries are the system's).

Environment: SINTER_SOURCE_DIR, the repository root (default: two directories up);
SINTER_CMAKE_ARGS, extra CMake arguments (split on spaces); SINTER_BUILD_JOBS (default 2).
"""

import os
import shutil
import subprocess

from setuptools import Distribution, setup
from setuptools.command.build_py import build_py

try:  # setuptools >= 70.1 has its own; before, the wheel package (Debian 12: python3-wheel)
    from setuptools.command.bdist_wheel import bdist_wheel
except ImportError:
    try:
        from wheel.bdist_wheel import bdist_wheel
    except ImportError:  # no wheel package: pip's legacy path still builds the library
        bdist_wheel = None

HERE = os.path.dirname(os.path.abspath(__file__))
LIBRARY_NAME = "libsinter.so"  # the file name sinter._lib looks for inside the package


def source_dir():
    root = os.environ.get("SINTER_SOURCE_DIR") or os.path.join(HERE, "..", "..")
    root = os.path.abspath(root)
    if not os.path.isfile(os.path.join(root, "CMakeLists.txt")) or not os.path.isfile(
            os.path.join(root, "include", "sinter.h")):
        raise RuntimeError(
            "libsinter's sources are not at %s: build from the repository "
            "(pip install ./bindings/python from its root) or set SINTER_SOURCE_DIR" % root)
    return root


class build_py_with_library(build_py):
    """build_py, then the shared library with CMake into the build's sinter/."""

    def run(self):
        super().run()
        if self.dry_run:
            return
        build_temp = os.path.abspath(os.path.join(self.get_finalized_command("build").build_base,
                                                  "cmake"))
        out_dir = os.path.join(build_temp, "lib")
        configure = ["cmake", "-S", source_dir(), "-B", build_temp,
                     "-DCMAKE_BUILD_TYPE=Release", "-DBUILD_TESTING=OFF",
                     "-DSINTER_PYTHON_TESTS=OFF", "-DSINTER_OUTPUT_DIR=" + out_dir]
        configure += os.environ.get("SINTER_CMAKE_ARGS", "").split()
        jobs = os.environ.get("SINTER_BUILD_JOBS", "2")
        self.announce("building libsinter with CMake in " + build_temp, level=2)
        subprocess.check_call(configure)
        subprocess.check_call(["cmake", "--build", build_temp, "--target", "sinter",
                               "-j", jobs])
        built = os.path.realpath(os.path.join(out_dir, LIBRARY_NAME))  # libsinter.so.X.Y.Z
        target = os.path.join(os.path.abspath(self.build_lib), "sinter", LIBRARY_NAME)
        os.makedirs(os.path.dirname(target), exist_ok=True)
        shutil.copyfile(built, target)  # one real file (the wheel keeps no symbolic links)
        os.chmod(target, 0o755)


commands = {"build_py": build_py_with_library}

if bdist_wheel is not None:
    class bdist_wheel_platform(bdist_wheel):
        """A platform wheel (it holds a shared library) for any Python 3 (ctypes, no extension)."""

        def get_tag(self):
            _, _, plat = super().get_tag()
            return "py3", "none", plat

    commands["bdist_wheel"] = bdist_wheel_platform


class platform_distribution(Distribution):
    """Not pure Python: the package goes to platlib and the wheel is a platform wheel."""

    def has_ext_modules(self):
        return True


setup(cmdclass=commands, distclass=platform_distribution)
