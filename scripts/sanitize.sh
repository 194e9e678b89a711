#!/usr/bin/env bash
# Builds hos with AddressSanitizer and UndefinedBehaviorSanitizer in
# build-sanitize/ and runs the fast tests (ctest -LE slow) under them.
# Any memory error, leak or undefined behaviour (signed overflow, misaligned
# load, out-of-range conversion) fails the test that meets it.
#   scripts/sanitize.sh                 # every fast test
#   scripts/sanitize.sh -R 'Fuzz|Ply'   # extra arguments go to ctest
# HOS_SANITIZE (default address,undefined), HOS_JOBS (default nproc) and
# HOS_MODULES (default all, e.g. "core;render;synth;recon") apply.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${HOS_SANITIZE_BUILD_DIR:-$root/build-sanitize}"
jobs="${HOS_JOBS:-$(nproc)}"
generator=()
if command -v ninja > /dev/null; then generator=(-G Ninja); fi
launcher=()
if command -v ccache > /dev/null; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
if [ ! -f "$build/CMakeCache.txt" ]; then
  cmake -S "$root" -B "$build" "${generator[@]}" "${launcher[@]}" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DHOS_SANITIZE="${HOS_SANITIZE:-address,undefined}" ${HOS_MODULES:+-DHOS_MODULES="$HOS_MODULES"}
fi
cmake --build "$build" -j "$jobs"
# halt_on_error: a report fails the test; leaks are reported at exit.
export ASAN_OPTIONS="${ASAN_OPTIONS:-halt_on_error=1:detect_leaks=1:abort_on_error=0}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-halt_on_error=1:print_stacktrace=1}"
cd "$build"
ctest -LE slow --output-on-failure -j "$jobs" "$@"
