#!/bin/sh
# Times hos-eval mesh on a 1M-face result against a 1M-face truth (two tori,
# minor radii 1.0 and 1.01, different tessellations).
# CPU time (user + system) is steadier than wall time when other jobs share the cores.
# Usage: bench/eval/run.sh BUILD_DIR
set -eu
build=${1:?usage: run.sh BUILD_DIR}
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
here=$(dirname "$0")
python3 "$here/make_torus.py" "$dir/truth.ply" 1000 500 1.0
python3 "$here/make_torus.py" "$dir/result.ply" 1001 499 1.01
for samples in 200000 1000000; do
  echo "samples per surface: $samples"
  /usr/bin/time -f "wall %e s, CPU %U s user + %S s system, peak RSS %M KB" "$build/bin/hos-eval" mesh --samples "$samples" \
    --result "$dir/result.ply" --truth "$dir/truth.ply"
done
