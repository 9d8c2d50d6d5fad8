#!/usr/bin/env bash
# Build the libFuzzer harnesses with clang and run each for a bounded time.
#
#   tests/fuzz/run.sh                      # build, then fuzz each target for FUZZ_SECONDS (30)
#   FUZZ_SECONDS=600 tests/fuzz/run.sh     # a longer local session
#   FUZZ_TARGETS=fuzz_scene tests/fuzz/run.sh
#   tests/fuzz/run.sh build                # only build
#   build/fuzz/fuzz_scene CRASH_FILE       # replay one input (after a build)
#
# The library sources are compiled into the fuzzers with
# -fsanitize=fuzzer,address,undefined (UB aborts). Inputs the fuzzers find go to
# build/fuzz/new_<target>/ (the committed corpora are only read); a crash, leak,
# UB or timeout is written to build/fuzz/artifacts/ and fails the script.
# Regenerate the checkpoint seed corpus after a format change with
#   SINTER_FUZZ_MAKE_CORPUS=tests/fuzz/corpus_checkpoint build/fuzz/fuzz_checkpoint
# Needs clang and libclang-rt-14-dev (Debian), and libsundials-dev.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(cd "$here/../.." && pwd)"
out="${FUZZ_BUILD_DIR:-$root/build/fuzz}"
seconds="${FUZZ_SECONDS:-30}"
targets="${FUZZ_TARGETS:-fuzz_scene fuzz_checkpoint}"
jobs="${FUZZ_JOBS:-2}"
cc="${FUZZ_CC:-clang}"
mkdir -p "$out/obj" "$out/include" "$out/artifacts"

# sinter_version.h from project(VERSION) in CMakeLists.txt
version=$(sed -n 's/^project(libsinter VERSION \([0-9.]*\).*/\1/p' "$root/CMakeLists.txt")
IFS=. read -r major minor patch <<<"$version"
sed -e "s/@PROJECT_VERSION_MAJOR@/$major/g" -e "s/@PROJECT_VERSION_MINOR@/$minor/g" \
    -e "s/@PROJECT_VERSION_PATCH@/$patch/g" -e "s/@PROJECT_VERSION@/$version/g" \
    "$root/include/sinter_version.h.in" >"$out/include/sinter_version.h.new"
cmp -s "$out/include/sinter_version.h.new" "$out/include/sinter_version.h" ||
  mv "$out/include/sinter_version.h.new" "$out/include/sinter_version.h"
rm -f "$out/include/sinter_version.h.new"

flags=(-std=c11 -g -O1 -fno-omit-frame-pointer -fsanitize=address,undefined
       -fno-sanitize-recover=undefined -I"$root/include" -I"$out/include" -I"$root/src")
libs=(-lsundials_cvode -lsundials_sunlinsolpcg -lsundials_nvecserial -lsundials_sunlinsoldense
      -lsundials_sunmatrixdense -lm)

# Library objects (rebuilt when their source, a header or the flags changed), in parallel; src/mpi/
# is libsinter_mpi's (it needs mpi.h), not the library's.
mapfile -t sources < <(find "$root/src" -name '*.c' -not -path '*/src/cli/*' -not -path '*/src/mpi/*' | sort)
objects=()
for src in "${sources[@]}"; do
  rel=${src#"$root"/src/}
  objects+=("$out/obj/${rel//\//_}.o")
done
printf '%s\n' "${flags[@]}" >"$out/flags.new"
cmp -s "$out/flags.new" "$out/flags" || mv "$out/flags.new" "$out/flags"
rm -f "$out/flags.new"
export cc out root
printf '%s\n' "${sources[@]}" | xargs -P "$jobs" -I{} bash -c '
  set -e
  src={}; rel=${src#"$root"/src/}; obj="$out/obj/${rel//\//_}.o"
  if [ -f "$obj" ] && [ ! "$src" -nt "$obj" ] && [ ! "$out/flags" -nt "$obj" ] &&
     [ -z "$(find "$root/src" "$root/include" -name "*.h" -newer "$obj" -print -quit)" ]; then
    exit 0
  fi
  mapfile -t f <"$out/flags"
  "$cc" "${f[@]}" -fsanitize=fuzzer-no-link -c "$src" -o "$obj"'

for t in $targets; do
  "$cc" "${flags[@]}" -fsanitize=fuzzer "$here/$t.c" "${objects[@]}" "${libs[@]}" -o "$out/$t"
done
echo "fuzz: built $targets in $out"
[ "${1:-}" = build ] && exit 0

# Fresh valid checkpoints of this build's format join the committed seeds (which go stale
# when the format changes).
rm -rf "$out/seed_checkpoint"
mkdir -p "$out/seed_checkpoint"
case " $targets " in
  *" fuzz_checkpoint "*) SINTER_FUZZ_MAKE_CORPUS="$out/seed_checkpoint" "$out/fuzz_checkpoint" ;;
esac

# Run the targets side by side (one per core), each for $seconds.
pids=()
for t in $targets; do
  corpus="$here/corpus_${t#fuzz_}"
  new="$out/new_${t#fuzz_}"
  extra=()
  [ "$t" = fuzz_checkpoint ] && extra=("$out/seed_checkpoint")
  mkdir -p "$new"
  dict=()
  [ -f "$here/${t#fuzz_}.dict" ] && dict=(-dict="$here/${t#fuzz_}.dict")
  ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
    "$out/$t" "$new" "$corpus" "${extra[@]}" "${dict[@]}" -max_total_time="$seconds" -timeout=10 \
      -rss_limit_mb=2048 -max_len=8192 -print_final_stats=1 \
      -artifact_prefix="$out/artifacts/$t-" >"$out/$t.log" 2>&1 &
  pids+=("$!")
done
status=0
i=0
for t in $targets; do
  if wait "${pids[$i]}"; then
    echo "fuzz: $t: $(grep -E '^stat::number_of_executed_units' "$out/$t.log" | awk '{print $2}') inputs, no finding"
  else
    status=1
    echo "fuzz: $t FAILED; the last lines of $out/$t.log:"
    tail -n 60 "$out/$t.log"
  fi
  i=$((i + 1))
done
exit $status
