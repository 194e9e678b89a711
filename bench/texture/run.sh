#!/bin/sh
# Runs the texture benchmark for the sizes of docs/benchmarks-texture.md.
# Usage: bench/texture/run.sh <build folder>
set -e
build=${1:-build}
for faces in 100000 1000000; do
  for views in 24 50; do
    echo "== faces $faces views $views"
    /usr/bin/time -f "wall %e s, max RSS %M KB (since the last step's reset)" \
      "$build/bin/hos-texture-bench" --faces "$faces" --views "$views" --output "${TMPDIR:-/tmp}/hos-texture-bench.glb" 2>&1 || true
  done
done
rm -f "${TMPDIR:-/tmp}/hos-texture-bench.glb"
