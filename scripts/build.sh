#!/usr/bin/env bash
# Configures and builds hos in build/ (Release, warnings as errors: the one
# configuration scripts/demo.sh and scripts/test.sh share, so the tests reuse
# the demo's build).
#   scripts/build.sh [CMAKE_ARG...] [--target TARGET...]
# CMAKE_ARGs (e.g. -DHOS_SANITIZE=address) go to cmake, also on an existing
# build folder; without --target everything is built.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${HOS_BUILD_DIR:-$root/build}"
jobs="${HOS_JOBS:-$(nproc)}"
cmake_args=(-DHOS_WERROR=ON)
targets=()
while [ $# -gt 0 ]; do
  if [ "$1" = "--target" ]; then
    shift
    targets=(--target "$@")
    break
  else
    cmake_args+=("$1")
    shift
  fi
done
if [ ! -f "$build/CMakeCache.txt" ]; then
  generator=()
  if command -v ninja > /dev/null; then generator=(-G Ninja); fi
  cmake -S "$root" -B "$build" "${generator[@]}" -DCMAKE_BUILD_TYPE=Release "${cmake_args[@]}"
else
  # Configuring again is cheap and finds packages installed since (GoogleTest
  # after install-deps.sh --test); unchanged flags rebuild nothing.
  cmake -S "$root" -B "$build" "${cmake_args[@]}" > /dev/null
fi
cmake --build "$build" -j "$jobs" "${targets[@]}"
