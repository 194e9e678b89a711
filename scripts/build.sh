#!/usr/bin/env bash
# Configures and builds hos in build/ (Release). Extra arguments go to cmake
# (also on an existing build folder, e.g. -DHOS_WERROR=ON).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${HOS_BUILD_DIR:-$root/build}"
jobs="${HOS_JOBS:-$(nproc)}"
if [ ! -f "$build/CMakeCache.txt" ]; then
  generator=()
  if command -v ninja > /dev/null; then generator=(-G Ninja); fi
  cmake -S "$root" -B "$build" "${generator[@]}" -DCMAKE_BUILD_TYPE=Release "$@"
elif [ $# -gt 0 ]; then
  cmake -S "$root" -B "$build" "$@"
fi
cmake --build "$build" -j "$jobs"
