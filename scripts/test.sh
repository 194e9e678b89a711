#!/usr/bin/env bash
# Installs what is missing (with what the tests need), builds everything in
# the configuration scripts/demo.sh uses (so after the demo only the tests and
# tools are left to build) and runs the whole test suite with ctest (extra
# arguments go to ctest, e.g. -LE slow).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$root/scripts/install-deps.sh" --test
"$root/scripts/check-format.sh"
"$root/scripts/check-includes.sh"
"$root/scripts/check-docs.sh"
"$root/scripts/build.sh"
# clang-tidy on the sources the last commits changed (the whole tree takes
# about an hour on 2 cores: scripts/tidy.sh without arguments).
HOS_TIDY_MAX_FILES="${HOS_TIDY_MAX_FILES:-8}" "$root/scripts/tidy.sh" --recent 3
build="${HOS_BUILD_DIR:-$root/build}"
cd "$build"
# Two tests at a time on two cores, each with an OpenMP thread per core:
# threads that wait at a barrier sleep instead of spinning on the core the
# other test needs (docs/developing.md).
OMP_WAIT_POLICY="${OMP_WAIT_POLICY:-PASSIVE}" ctest --output-on-failure -j "${HOS_TEST_JOBS:-2}" "$@"
