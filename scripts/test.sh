#!/usr/bin/env bash
# Installs what is missing, builds with warnings as errors, and runs the whole
# test suite with ctest (extra arguments go to ctest, e.g. -LE slow).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$root/scripts/install-deps.sh"
"$root/scripts/check-format.sh"
"$root/scripts/build.sh" -DHOS_WERROR=ON
build="${HOS_BUILD_DIR:-$root/build}"
cd "$build"
ctest --output-on-failure -j "${HOS_TEST_JOBS:-2}" "$@"
