#!/usr/bin/env bash
# Side-by-side: hos-recon (grid 256 / 512) against COLMAP's Screened Poisson
# (poisson_mesher, depth 8 / 9) on the same oriented points, in one run.
# Prints a markdown table: wall time, CPU time (user + sys: steadier than wall
# time when other jobs share the cores), peak memory, triangles, accuracy, and
# the load average before each input. Each pair runs --repeat times (default
# 3), alternating, and the table gives the median times (all of them in
# brackets): on a VM, one run's time can swing by a third. A last table gives
# the ratio of the medians per input.
# COLMAP runs with PoissonMeshing.trim 0: its default density trim (10)
# removed every face of these inputs; hos-recon trims by distance instead.
#   bench/recon/run.sh [--large | --huge] [--data DIR] [--repeat N] [--baseline BIN]
# --large adds grid 512 against depth 9; --huge also grid 1024 against depth 10.
# --inputs "sphere6 bunny" keeps only those inputs (default: all).
# --baseline BIN also runs BIN/hos-recon (an older build) in every repeat,
# before this build's, so that old and new share the machine's load.
# DIR holds stanford_bunny/ (scored against its reference surface) and,
# optionally, stanford_dragon_stand/ (no reference: time and memory only).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
bin="${HOS_BUILD_DIR:-$root/build}/bin"
data=""
pairs=("256 8")
repeat=3
only=""
baseline=""
while [ $# -gt 0 ]; do
  case "$1" in
    --large) pairs=("256 8" "512 9"); shift ;;
    --huge) pairs=("256 8" "512 9" "1024 10"); shift ;;
    --data) data="$2"; shift 2 ;;
    --repeat) repeat="$2"; shift 2 ;;
    --inputs) only="$2"; shift 2 ;;
    --baseline) baseline="$(cd "$2" && pwd)"; shift 2 ;;
    *) echo "usage: $0 [--large | --huge] [--data DIR] [--repeat N] [--inputs NAMES] [--baseline BIN]" >&2; exit 2 ;;
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
if [ -n "$data" ] && [ -f "$data/stanford_dragon_stand/dragonStandRight.conf" ]; then
  "$bin/hos-recon-bench" scans --conf "$data/stanford_dragon_stand/dragonStandRight.conf" --output "$work/dragon.ply"
  inputs+=(dragon)
fi

# Runs a command under /usr/bin/time; prints "seconds cpu_seconds peak_MB".
timed() {
  /usr/bin/time -f "%e %U %S %M" -o "$work/time.txt" "$@" > "$work/cmd.log" 2>&1 || {
    echo "failed: $*" >&2; tail -5 "$work/cmd.log" >&2; echo "fail fail fail"; return; }
  awk '{printf "%s %.1f %.0f\n", $1, $2 + $3, $4/1024}' "$work/time.txt"
}
load() { awk '{print $1}' /proc/loadavg; }

accuracy() {  # mesh input_points name
  if [ "$3" = dragon ]; then
    echo "n/a (no reference)"
  elif [ "$3" = bunny ]; then
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

# Median of numbers on stdin.
median() { sort -g | awk '{v[NR] = $1} END {print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2}'; }
# Ratio of the medians of two space-separated lists.
ratio() { awk -v a="$(tr ' ' '\n' <<< "$1" | grep . | median)" -v b="$(tr ' ' '\n' <<< "$2" | grep . | median)" 'BEGIN {printf "%.2f", a / b}'; }
# "median (all)" of a space-separated list.
summary() { echo "$(tr ' ' '\n' <<< "$1" | grep . | median) ($(echo $1 | tr ' ' '/'))"; }

methods=(hos poisson)
[ -z "$baseline" ] || methods=(baseline hos poisson)
# run_method METHOD INPUT GRID DEPTH: one timed run, its mesh in WORK/METHOD.ply.
run_method() {
  case "$1" in
    hos) timed "$bin/hos-recon" --input "$work/$2.ply" --output "$work/hos.ply" --resolution "$3" --progress none ;;
    baseline) timed "$baseline/hos-recon" --input "$work/$2.ply" --output "$work/baseline.ply" --resolution "$3" --progress none ;;
    poisson) timed env QT_QPA_PLATFORM=offscreen colmap poisson_mesher --input_path "$work/$2.ply" \
      --output_path "$work/poisson.ply" --PoissonMeshing.depth "$4" --PoissonMeshing.trim 0 ;;
  esac
}
method_label() {
  case "$1" in
    hos) echo "hos-recon (energy 4)" ;;
    baseline) echo "hos-recon baseline (energy 4)" ;;
    poisson) echo "COLMAP poisson_mesher" ;;
  esac
}
method_setting() { if [ "$1" = poisson ]; then echo "depth $3"; else echo "grid $2"; fi; }

echo "| input | method | resolution | time (s), median (runs) | CPU (s), median (runs) | peak memory (MB) | triangles | accuracy vs truth | load |"
echo "|---|---|---|---|---|---|---|---|---|"
ratios=()
for name in "${inputs[@]}"; do
  if [ -n "$only" ] && [[ " $only " != *" $name "* ]]; then continue; fi
  for pair in "${pairs[@]}"; do
    set -- $pair
    res=$1 depth=$2
    l=$(load)
    declare -A times=() cpus=() peaks=()
    for ((r = 0; r < repeat; ++r)); do
      for method in "${methods[@]}"; do
        rm -f "$work/$method.ply"
        read -r t c m < <(run_method "$method" "$name" "$res" "$depth")
        [[ $m =~ ^[0-9]+$ ]] || m=0
        times[$method]+="$t " cpus[$method]+="$c " peaks[$method]=$((m > ${peaks[$method]:-0} ? m : ${peaks[$method]:-0}))
      done
    done
    for method in "${methods[@]}"; do
      [ -f "$work/$method.ply" ] || continue
      echo "| $name | $(method_label "$method") | $(method_setting "$method" "$res" "$depth") | $(summary "${times[$method]}") | $(summary "${cpus[$method]}") | ${peaks[$method]} | $(faces "$work/$method.ply") | $(accuracy "$work/$method.ply" "$work/$name.ply" "$name") | $l |"
    done
    if [ -f "$work/poisson.ply" ]; then
      ratios+=("| $name | grid $res / depth $depth | Poisson / hos-recon | $(ratio "${times[poisson]}" "${times[hos]}") |")
    fi
    if [ -f "$work/baseline.ply" ]; then
      ratios+=("| $name | grid $res | hos-recon / baseline | $(ratio "${times[hos]}" "${times[baseline]}") |")
    fi
    unset times cpus peaks
  done
done
echo
echo "| input | resolutions | times | ratio of the medians |"
echo "|---|---|---|---|"
for row in "${ratios[@]}"; do echo "$row"; done
