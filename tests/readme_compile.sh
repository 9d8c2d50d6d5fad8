#!/usr/bin/env bash
# The README's "without installing" compile line, taken from README.md itself (so the two cannot
# drift), compiles examples/particles.c and the program runs without LD_LIBRARY_PATH or ldconfig.
# The line is run in a scratch directory laid out like the repository root after the build:
# include/, examples/, build/include (the generated sinter_version.h) and lib/ (this build's
# library directory, SINTER_OUTPUT_DIR) are links to this build's.
# usage: readme_compile.sh SOURCE_DIR BINARY_INCLUDE_DIR LIBRARY_DIR WORK_DIR
set -euo pipefail
src=$1 bin_include=$2 libdir=$3 work=$4
lines=$(grep -o '`[^`]*-Llib -lsinter[^`]*`' "$src/README.md" | tr -d '`')
if [ "$(printf '%s\n' "$lines" | grep -c .)" -ne 1 ]; then
  echo "README.md must have exactly one \`...-Llib -lsinter...\` line; found:"; echo "$lines"; exit 1
fi
case $lines in
  *examples/particles.c*) ;;
  *) echo "the README's line does not compile examples/particles.c: $lines"; exit 1 ;;
esac
rm -rf "$work"
mkdir -p "$work/build"
ln -s "$src/include" "$work/include"
ln -s "$src/examples" "$work/examples"
ln -s "$bin_include" "$work/build/include"
ln -s "$libdir" "$work/lib"
echo "README: $lines"
cd "$work"
env -u LD_LIBRARY_PATH -u LIBRARY_PATH bash -c "$lines"
# the program built runs again from another directory (the run path is absolute)
prog=$(find "$work" -maxdepth 1 -type f -perm -u+x | head -n 1)
test -n "$prog" || { echo "the README's line left no program in $work"; exit 1; }
cd /
env -u LD_LIBRARY_PATH "$prog" >/dev/null
echo "ran $prog from / without LD_LIBRARY_PATH"
