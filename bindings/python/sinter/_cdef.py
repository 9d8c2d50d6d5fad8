"""The public headers as a cffi cdef: preprocess sinter_submodel.h (which
includes sinter.h) and sinter_domain.h, and parse them.

sinter.h promises that its preprocessed form parses as a cffi cdef. The C
preprocessor runs with -nostdinc and empty stand-ins for <stddef.h> and
<stdint.h> (cffi knows size_t, int32_t, ... itself), so the text holds the
library's own declarations only, and an include of any other system header
fails here, as the header's "only <stddef.h> and <stdint.h>" rule requires.

Environment: SINTER_CC (default "cc"), SINTER_INCLUDE_DIRS (directories
separated by os.pathsep; default: the source tree's include/ and build/include/).
"""

import os
import shlex
import subprocess
import tempfile

_SOURCE_ROOT = os.path.normpath(
    os.path.join(os.path.dirname(os.path.realpath(__file__)), "..", "..", ".."))


def include_dirs(environ=None):
    """Directories searched for sinter.h and the generated sinter_version.h."""
    environ = os.environ if environ is None else environ
    listed = environ.get("SINTER_INCLUDE_DIRS")
    if listed:
        return [d for d in listed.split(os.pathsep) if d]
    return [os.path.join(_SOURCE_ROOT, "include"), os.path.join(_SOURCE_ROOT, "build", "include")]


def find_header(name="sinter.h", dirs=None):
    """Path of a header in the include directories (FileNotFoundError if absent)."""
    dirs = include_dirs() if dirs is None else dirs
    for directory in dirs:
        path = os.path.join(directory, name)
        if os.path.isfile(path):
            return path
    raise FileNotFoundError("%s not found in %s (set SINTER_INCLUDE_DIRS)" % (name, dirs))


def preprocess(header=None, cc=None, dirs=None):
    """Text of the preprocessed header, without '#' lines, ready for FFI.cdef.

    The default is every public header: sinter.h, the host submodel API (sinter_submodel.h)
    and the domain API (sinter_domain.h).
    """
    dirs = include_dirs() if dirs is None else dirs
    compiler = shlex.split(cc or os.environ.get("SINTER_CC") or "cc")
    with tempfile.TemporaryDirectory() as stubs:
        for name in ("stddef.h", "stdint.h"):
            with open(os.path.join(stubs, name), "w") as stub:
                stub.write("/* provided by cffi */\n")
        if header is None:
            header = os.path.join(stubs, "sinter_all.h")
            with open(header, "w") as stub:
                for name in ("sinter_submodel.h", "sinter_domain.h"):
                    stub.write('#include "%s"\n' % os.path.abspath(find_header(name, dirs=dirs)))
        command = compiler + ["-E", "-P", "-x", "c", "-nostdinc", "-I", stubs]
        for directory in dirs:
            command += ["-I", directory]
        result = subprocess.run(command + [header], stdout=subprocess.PIPE,
                                stderr=subprocess.PIPE, universal_newlines=True)
    if result.returncode != 0:
        raise RuntimeError("preprocessing %s failed (%s):\n%s"
                           % (header, " ".join(command), result.stderr))
    lines = result.stdout.splitlines()
    return "\n".join(line for line in lines if not line.lstrip().startswith("#")) + "\n"


def check_cdef(text=None):
    """Parse the preprocessed header with cffi.FFI().cdef; return the FFI (needs cffi)."""
    import cffi

    ffi = cffi.FFI()
    ffi.cdef(preprocess() if text is None else text)
    return ffi
