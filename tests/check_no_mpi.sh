#!/usr/bin/env bash
# libsinter.so stays free of MPI (issue 44): no MPI library among the libraries it needs
# (readelf's NEEDED entries, and ldd's whole chain) and no MPI symbol among those it defines or takes from others.
# MPI belongs to the companion libsinter_mpi only. Run: bash tests/check_no_mpi.sh lib/libsinter.so
set -euo pipefail
lib=${1:?usage: check_no_mpi.sh path/to/libsinter.so}
needed=$(readelf -d "$lib" | grep NEEDED || true)
if grep -i -E 'mpi|open-rte|open-pal' <<<"$needed"; then
  echo "$lib needs an MPI library"
  exit 1
fi
# nor through the libraries it needs (ldd: the whole chain, SUNDIALS included)
if ldd "$lib" | grep -i -E 'libmpi|open-rte|open-pal'; then
  echo "$lib loads an MPI library through its dependencies"
  exit 1
fi
symbols=$(nm -D "$lib" | awk '{print $NF}' | grep -E '^(P?MPI_|ompi_|sinter_mpi_)' || true)
if [ -n "$symbols" ]; then
  echo "$lib refers to MPI symbols:"
  echo "$symbols"
  exit 1
fi
echo "$lib: no MPI library needed, no MPI symbol ($(wc -l <<<"$needed") needed libraries)"
