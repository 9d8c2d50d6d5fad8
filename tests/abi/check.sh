#!/usr/bin/env bash
# ABI check of libsinter against the baseline tests/abi/libsinter.abi (see README.md here).
#
#   tests/abi/check.sh [LIBRARY]            check LIBRARY (default: a Debug build in build-abi/)
#   tests/abi/check.sh --update [LIBRARY]   rewrite the baseline from LIBRARY
#
# LIBRARY must carry debug information (a Debug build); only the types of the
# public headers in include/ count. The check fails on removed or changed
# functions and types; added functions, added enumerators and fields appended to
# struct_size structs pass (they are listed for information).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(cd "$here/../.." && pwd)"
baseline="$here/libsinter.abi"
update=0
if [ "${1:-}" = --update ]; then
  update=1
  shift
fi
lib="${1:-}"
if [ -z "$lib" ]; then
  cmake -S "$root" -B "$root/build-abi" -DCMAKE_BUILD_TYPE=Debug -DBUILD_TESTING=OFF \
        -DSINTER_PYTHON_TESTS=OFF -DSINTER_OUTPUT_DIR="$root/build-abi/lib" >/dev/null
  cmake --build "$root/build-abi" -j2 --target sinter >/dev/null
  lib="$root/build-abi/lib/libsinter.so"
fi
if ((update)); then
  abidw --headers-dir "$root/include" --drop-private-types --exported-interfaces-only \
        --no-corpus-path --no-comp-dir-path --no-show-locs --no-elf-needed --out-file "$baseline" "$lib"
  echo "abi: baseline $baseline rewritten from $lib"
  exit 0
fi
report="$(mktemp)"
trap 'rm -f "$report"' EXIT
set +e
abidiff --exported-interfaces-only --no-added-syms --suppressions "$here/suppressions.abignore" \
        "$baseline" "$lib" >"$report" 2>&1
rc=$?
set -e
# abidiff's status bits: 1 error, 2 usage error, 4 ABI change, 8 incompatible change.
# Added symbols are left out (--no-added-syms), so any bit here is a real problem.
if ((rc != 0)); then
  cat "$report"
  echo "abi: $lib is not compatible with $baseline (abidiff status $rc)."
  echo "abi: if the change is intended, refresh the baseline in the same commit: tests/abi/check.sh --update"
  exit 1
fi
added=$(abidiff --exported-interfaces-only "$baseline" "$lib" 2>/dev/null |
        sed -n 's/^Functions changes summary:.* \([0-9]*\) Added.*/\1/p' || true)
echo "abi: compatible with the baseline (${added:-0} function(s) added since it was written)"
