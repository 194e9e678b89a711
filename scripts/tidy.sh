#!/usr/bin/env bash
# Runs clang-tidy (.clang-tidy) over hos sources in the build's
# compile_commands.json; exits non-zero on any finding. Build first
# (scripts/build.sh).
#   scripts/tidy.sh                      # every source (about an hour on 2 cores)
#   scripts/tidy.sh 'energy_operator\.cpp'   # sources matching a regex below the folders
#   scripts/tidy.sh --recent N           # the sources changed by the last N commits
#                                          (at most HOS_TIDY_MAX_FILES, default 12; test.sh: 8)
# Extra arguments after these go to run-clang-tidy.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${HOS_BUILD_DIR:-$root/build}"
jobs="${HOS_JOBS:-$(nproc)}"
runner="$(command -v run-clang-tidy-14 || command -v run-clang-tidy || true)"
tidy="$(command -v clang-tidy-14 || command -v clang-tidy || true)"
if [ -z "$runner" ] || [ -z "$tidy" ]; then
  echo "tidy: clang-tidy is not installed (scripts/install-deps.sh installs it)" >&2
  exit 2
fi
if [ ! -f "$build/compile_commands.json" ]; then
  echo "tidy: $build/compile_commands.json is missing; run scripts/build.sh first" >&2
  exit 2
fi
# A unity build's compile commands name its batches, not the sources: the
# commands come from a file-by-file configuration of the same build type
# (configured under the build folder, nothing is built there).
commands="$build"
if grep -q '^HOS_UNITY_BUILD:BOOL=ON' "$build/CMakeCache.txt"; then
  commands="$build/tidy-commands"
  build_type="$(sed -n 's/^CMAKE_BUILD_TYPE:STRING=//p' "$build/CMakeCache.txt")"
  cmake -S "$root" -B "$commands" -DCMAKE_BUILD_TYPE="${build_type:-Release}" -DHOS_UNITY_BUILD=OFF > /dev/null
fi
# Our folders only (those holding tracked C++ sources): not the build tree's
# generated files nor system headers.
folders="$(cd "$root" && git ls-files '*.cpp' '*.h' | sed -n 's#/.*##p' | sort -u | paste -sd '|')"
files="^$root/($folders)/"
if [ "${1:-}" = "--recent" ]; then
  commits="$2"
  shift 2
  # The .cpp files the last commits touched that still exist, newest first;
  # a changed header brings the source of the same name.
  mapfile -t changed < <(cd "$root" && git log --max-count="$commits" --name-only --format= -- '*.cpp' '*.h' |
    sed 's/\.h$/.cpp/' | awk '!seen[$0]++' | while read -r f; do [ -f "$f" ] && echo "$f"; done |
    grep -E "^($folders)/" | head -n "${HOS_TIDY_MAX_FILES:-12}" || true)
  if [ ${#changed[@]} -eq 0 ]; then
    echo "tidy: no source changed in the last $commits commits"
    exit 0
  fi
  echo "tidy: ${#changed[@]} source(s) changed in the last $commits commits"
  pattern="$(printf '%s|' "${changed[@]}" | sed 's/|$//; s/\./\\./g')"
  files="^$root/($pattern)$"
elif [ $# -gt 0 ]; then
  files="^$root/($folders)/(.*/)?($1)"
  shift
fi
"$runner" -clang-tidy-binary "$tidy" -p "$commands" -j "$jobs" -quiet \
  -header-filter="^$root/($folders)/" "$files" "$@"
