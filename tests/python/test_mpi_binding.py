"""sinter.mpi against the headers of libsinter_mpi (sinter_mpi.h, sinter_mpi_decomp.h), without
MPI: every function of the headers is declared in sinter.mpi's table and called by the module,
the structs passed by pointer have the headers' members in the headers' order, the enum and
the flag have the headers' values, and the public signatures carry type hints. (The module
imports without MPI; tests/mpi/test_mpi_python.py runs it under mpiexec.)"""

import inspect
import os
import re
import unittest

from sinter import _cdef, mpi

HEADERS = ("sinter_mpi.h", "sinter_mpi_decomp.h")


def header_code():
    code = ""
    for name in HEADERS:
        with open(_cdef.find_header(name)) as header:
            code += re.sub(r"/\*.*?\*/", " ", header.read(), flags=re.S)
    return code


def struct_members(code, name):
    body = re.search(r"typedef struct %s \{(.*?)\}" % name, code, re.S).group(1)
    return re.findall(r"(\w+)\s*(?:\[\d+\])?\s*;", body)


class MpiBindingTest(unittest.TestCase):
    def setUp(self):
        try:
            self.code = header_code()
        except FileNotFoundError as error:
            self.skipTest(str(error))

    def test_every_header_function_is_declared_and_called(self):
        in_header = re.findall(r"SINTER_API\s+[\w\s*]*?\b(sinter_mpi_\w+)\s*\(", self.code)
        self.assertGreaterEqual(len(in_header), 25)
        self.assertEqual(sorted(set(in_header) ^ set(mpi.FUNCTIONS)), [],
                         "sinter/mpi.py's _signatures and the headers differ")
        with open(mpi.__file__) as source:
            text = source.read()
        uncalled = [name for name in in_header
                    if not re.search(r"\.%s\b(?!\")" % name, text)]
        self.assertEqual(uncalled, [], "functions sinter.mpi declares but never calls")

    def test_structs_match_the_header(self):
        for c_name, python in (("sinter_mpi_options", mpi.MpiOptions),
                               ("sinter_mpi_stats", mpi._CStats),
                               ("sinter_mpi_exchange_stats", mpi._CExchangeStats)):
            self.assertEqual([f[0] for f in python._fields_], struct_members(self.code, c_name),
                             c_name)
        # the dataclasses returned carry every counter
        self.assertEqual([f.name for f in mpi.dataclasses.fields(mpi.ExchangeStats)],
                         struct_members(self.code, "sinter_mpi_exchange_stats")[1:])
        self.assertEqual([f.name for f in mpi.dataclasses.fields(mpi.MpiStats)],
                         struct_members(self.code, "sinter_mpi_stats")[1:])

    def test_enum_and_flag(self):
        body = re.search(r"typedef enum sinter_mpi_decomp_kind \{(.*?)\}", self.code, re.S)
        values = {name: int(value) for name, value in
                  re.findall(r"SINTER_MPI_DECOMP_(\w+) = (-?\d+)", body.group(1))}
        self.assertEqual({m.name: int(m) for m in mpi.DecompKind}, values)
        self.assertEqual(set(re.findall(r"typedef enum (\w+) \{", self.code)),
                         {"sinter_mpi_decomp_kind"}, "give new C enums a Python enum")
        flag = re.search(r"#define SINTER_MPI_ATTACH_BALANCE (\d+)", self.code).group(1)
        self.assertEqual(mpi.ATTACH_BALANCE, int(flag))

    def test_public_signatures_are_typed(self):
        problems = []
        for name in mpi.__all__:
            obj = getattr(mpi, name)
            if inspect.isclass(obj):
                if issubclass(obj, BaseException) or not obj.__module__.startswith("sinter"):
                    continue
                members = [("%s.%s" % (name, attr), m) for attr, m in vars(obj).items()
                           if not attr.startswith("_") or attr == "__init__"]
            elif inspect.isfunction(obj):
                members = [(name, obj)]
            else:
                continue
            for qualified, member in members:
                if isinstance(member, property):
                    member = member.fget
                elif isinstance(member, (staticmethod, classmethod)):
                    member = member.__func__
                if not inspect.isfunction(member):
                    continue
                signature = inspect.signature(member)
                for parameter in signature.parameters.values():
                    if (parameter.name not in ("self", "cls")
                            and parameter.annotation is inspect.Parameter.empty):
                        problems.append("%s: %s has no type" % (qualified, parameter.name))
                if (signature.return_annotation is inspect.Signature.empty
                        and not qualified.endswith("__init__")):
                    problems.append("%s: no return type" % qualified)
        self.assertEqual(problems, [])

    def test_clear_error_without_the_library(self):
        if mpi._loaded:
            self.skipTest("libsinter_mpi is loaded in this process")
        environ = {"SINTER_MPI_LIBRARY": os.path.join(os.sep, "nonexistent", "libsinter_mpi.so")}
        self.assertEqual(mpi.library_candidates(environ), [environ["SINTER_MPI_LIBRARY"]])
        saved = os.environ.get("SINTER_MPI_LIBRARY")
        os.environ["SINTER_MPI_LIBRARY"] = environ["SINTER_MPI_LIBRARY"]
        try:
            with self.assertRaises(mpi.MpiUnavailable) as caught:
                mpi.Decomposition.brick(1, (0, 0, 0), (1, 1, 1))
            self.assertIn("mpi", str(caught.exception).lower())
            self.assertFalse(mpi.available())
        finally:
            if saved is None:
                del os.environ["SINTER_MPI_LIBRARY"]
            else:
                os.environ["SINTER_MPI_LIBRARY"] = saved
            mpi._loaded.clear()


if __name__ == "__main__":
    unittest.main()
