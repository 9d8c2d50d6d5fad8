"""include/sinter.hpp mirrors every enumerator of include/sinter.h and include/sinter_domain.h: each C constant of a typedef'd
enum (and of SINTER_STATUS_LIST) appears in sinter.hpp as the value of a scoped enumerator
(`name = SINTER_...`), so that an enumerator added in C without its C++ twin fails this test."""

import os
import re
import sys

root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
c_header = (open(os.path.join(root, "include", "sinter.h")).read() +
            open(os.path.join(root, "include", "sinter_domain.h")).read())
cpp_header = open(os.path.join(root, "include", "sinter.hpp")).read()

constants = re.findall(r"^\s*X\((SINTER_[A-Z0-9_]+),", c_header, re.M)
enums = re.findall(r"typedef enum (\w+) \{(.*?)\} \1;", c_header, re.S)
for _, body in enums:
    body = re.sub(r"/\*.*?\*/", "", body, flags=re.S)
    constants += [name for name in re.findall(r"^\s*(SINTER_[A-Z0-9_]+)\s*=", body, re.M)
                  if not name.endswith("_")]  # *_COUNT_: not a value
mirrored = set(re.findall(r"^\s*\w+ = (SINTER_[A-Z0-9_]+),", cpp_header, re.M))
missing = [name for name in constants if name not in mirrored]
if len(enums) < 10 or len(constants) < 100:
    sys.exit("cpp_header_enums: found only %d enums and %d constants in sinter.h" % (
        len(enums), len(constants)))
if missing:
    sys.exit("include/sinter.hpp lacks a scoped enumerator for: " + ", ".join(missing))
print("sinter.hpp mirrors all %d constants of %d enums" % (len(constants), len(enums)))
