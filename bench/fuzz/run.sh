#!/usr/bin/env bash
# The reader fuzz tests (tests/fuzz) for a long run: new seeds until the time
# is up, each with HOS_FUZZ_ITERATIONS mutants per reader. Result line for
# docs/reliability.md; failing mutants are kept in BUILD/fuzz-failures/.
#   bench/fuzz/run.sh [SECONDS]        # default 3600
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build="${HOS_BUILD_DIR:-$root/build}"
seconds="${1:-3600}"
iterations="${HOS_FUZZ_ITERATIONS:-3000}"
binary="$build/tests/fuzz/fuzz_tests"
[ -x "$binary" ] || { echo "build first: $binary is missing" >&2; exit 1; }
log="$build/fuzz-long.log"
: > "$log"
seed=1000
runs=0
failed=0
start=$SECONDS
while [ $((SECONDS - start)) -lt "$seconds" ]; do
  seed=$((seed + 1))
  # A hang is a failure too: no seed may take longer than 30 minutes.
  if ! (cd "$build" && HOS_SOURCE_DIR="$root" HOS_FUZZ_SEED=$seed HOS_FUZZ_ITERATIONS=$iterations \
        timeout 1800 "$binary" --gtest_brief=1 >> "$log" 2>&1); then
    failed=$((failed + 1))
    echo "seed $seed failed (see $log)"
  fi
  runs=$((runs + 1))
done
echo "fuzz: $runs seeds x $iterations mutants per reader in $((SECONDS - start)) s, $failed failed seeds" \
  "(commit $(git -C "$root" rev-parse --short HEAD))"
[ "$failed" -eq 0 ]
