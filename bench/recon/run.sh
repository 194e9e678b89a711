#!/usr/bin/env bash
# Side-by-side: hos-recon (grid 256 / 512) against COLMAP's Screened Poisson
# (poisson_mesher, depth 8 / 9) on the same oriented points, in one run.
# Prints a markdown table: wall time, CPU time (user + sys: steadier than wall
# time when other jobs share the cores), peak memory, triangles, accuracy, and
# the load average before each input.
# COLMAP runs with PoissonMeshing.trim 0: its default density trim (10)
# removed every face of these inputs; hos-recon trims by distance instead.
#   bench/recon/run.sh [--large] [--data DIR]   (DIR holds stanford_bunny/)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
bin="${HOS_BUILD_DIR:-$root/build}/bin"
data=""
pairs=("256 8")
while [ $# -gt 0 ]; do
  case "$1" in
    --large) pairs=("256 8" "512 9"); shift ;;
    --data) data="$2"; shift 2 ;;
    *) echo "usage: $0 [--large] [--data DIR]" >&2; exit 2 ;;
  esac
done
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

"$bin/hos-recon-bench" points --shape sphere --count 240000 --output "$work/sphere.ply"
"$bin/hos-recon-bench" points --shape sphere6 --count 240000 --output "$work/sphere6.ply"
inputs=(sphere sphere6)
if [ -n "$data" ] && [ -f "$data/stanford_bunny/data/bun.conf" ]; then
  "$bin/hos-recon-bench" scans --conf "$data/stanford_bunny/data/bun.conf" --output "$work/bunny.ply"
  inputs+=(bunny)
fi

# Runs a command under /usr/bin/time; prints "seconds cpu_seconds peak_MB".
timed() {
  /usr/bin/time -f "%e %U %S %M" -o "$work/time.txt" "$@" > "$work/cmd.log" 2>&1 || {
    echo "failed: $*" >&2; tail -5 "$work/cmd.log" >&2; echo "fail fail fail"; return; }
  awk '{printf "%s %.1f %.0f\n", $1, $2 + $3, $4/1024}' "$work/time.txt"
}
load() { awk '{print $1}' /proc/loadavg; }

accuracy() {  # mesh input_points name
  if [ "$3" = bunny ]; then
    if [ -x "$bin/hos-eval" ]; then
      "$bin/hos-eval" mesh --result "$1" --truth "$data/stanford_bunny/reconstruction/bun_zipper.ply" --json "$work/acc.json" > /dev/null 2>&1 \
        && python3 -c "import json;d=json.load(open('$work/acc.json'));a=d.get('accuracy',{});print('truth mean %.2e' % a.get('mean',float('nan')))" 2>/dev/null \
        || echo "n/a"
    else
      echo "n/a (hos-eval not built)"
    fi
  else
    "$bin/hos-recon-bench" sphere-error --mesh "$1" | awk '{printf "rms %.2e max %.2e", $2, $4}'
  fi
}

faces() { "$bin/hos-recon-bench" sphere-error --mesh "$1" | awk '{print $6}'; }

echo "| input | method | resolution | time (s) | CPU (s) | peak memory (MB) | triangles | accuracy vs truth | load |"
echo "|---|---|---|---|---|---|---|---|---|"
for name in "${inputs[@]}"; do
  for pair in "${pairs[@]}"; do
    set -- $pair
    res=$1 depth=$2
    l=$(load)
    read -r t c m < <(timed "$bin/hos-recon" --input "$work/$name.ply" --output "$work/hos.ply" --resolution "$res" --progress none)
    echo "| $name | hos-recon (energy 4) | grid $res | $t | $c | $m | $(faces "$work/hos.ply") | $(accuracy "$work/hos.ply" "$work/$name.ply" "$name") | $l |"
    l=$(load)
    read -r t c m < <(timed env QT_QPA_PLATFORM=offscreen colmap poisson_mesher --input_path "$work/$name.ply" --output_path "$work/poisson.ply" --PoissonMeshing.depth "$depth" --PoissonMeshing.trim 0)
    if [ -f "$work/poisson.ply" ]; then
      echo "| $name | COLMAP poisson_mesher | depth $depth | $t | $c | $m | $(faces "$work/poisson.ply") | $(accuracy "$work/poisson.ply" "$work/$name.ply" "$name") | $l |"
      rm -f "$work/poisson.ply"
    fi
  done
done
