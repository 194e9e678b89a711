#!/usr/bin/env bash
# Runs clang-tidy (.clang-tidy) over every hos source in the build's
# compile_commands.json; exits non-zero on any finding. Build first
# (scripts/build.sh). Extra arguments go to run-clang-tidy, e.g. a regex that
# selects files below the folders: scripts/tidy.sh 'energy_operator\.cpp'.
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
# Our folders only: not the build tree's generated files nor system headers.
folders="core|render|synth|eval|recon|mvs|texture|sfm|pipeline|apps|tests|bench|examples"
files="^$root/($folders)/"
if [ $# -gt 0 ]; then files="^$root/($folders)/(.*/)?($1)"; shift; fi
"$runner" -clang-tidy-binary "$tidy" -p "$build" -j "$jobs" -quiet \
  -header-filter="^$root/($folders)/" "$files" "$@"
