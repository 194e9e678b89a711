#!/usr/bin/env bash
# Thin structure: how much of a railing's bars hos-mvs keeps. hos-synth's
# railing scene (bars a few pixels wide at 1280x960, under one pixel at
# 640) over a textured ground, 8 views with true cameras; completeness
# (recall) of the railing's surface at 0.5% and 1% of its diagonal. The
# ground is not in the truth, so precision means nothing here.
# Each configuration is one --run LABEL [--mvs-bin DIR] [--set mvs.key=value]...
# group; the groups run one after another on the same scene, so compare
# them side by side in one call:
#   bench/mvs/railing.sh --run old --mvs-bin OLD/bin --run new
#   bench/mvs/railing.sh --run 1024 --run c2f --set mvs.coarse_image_size=640 --set mvs.max_image_size=1280
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
bin="${HOS_BUILD_DIR:-$root/build}/bin"
usage() { echo "usage: $0 --run LABEL [--mvs-bin DIR] [--set mvs.key=value]... [--run ...]" >&2; exit 2; }
labels=() mvs_bins=() run_sets=()
while [ $# -gt 0 ]; do
  case "$1" in
    --run) labels+=("$2"); mvs_bins+=("$bin"); run_sets+=(""); shift 2 ;;
    --mvs-bin) mvs_bins[-1]="$(cd "$2" && pwd)"; shift 2 ;;
    --set) run_sets[-1]+=" --set $2"; shift 2 ;;
    *) usage ;;
  esac
done
[ ${#labels[@]} -gt 0 ] || usage
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
"$bin/hos-synth" --output "$work/scene" --scene railing --ground-plane --views 8 --width 1280 --height 960 \
  --seed 1 --points 3000 --progress none
echo "| run | completeness at 0.5% / 1% of the diagonal | CPU s | peak MB |"
echo "|---|---|---|---|"
for k in "${!labels[@]}"; do
  # shellcheck disable=SC2086  # the --set words split on purpose
  /usr/bin/time -f "%e %M %U %S" -o "$work/time.txt" "${mvs_bins[$k]}/hos-mvs" --workspace "$work/scene" \
    --output "$work/points.ply" --progress none ${run_sets[$k]} > /dev/null 2> "$work/mvs.log" || { cat "$work/mvs.log" >&2; exit 1; }
  read -r _ kb user sys < "$work/time.txt"
  "$bin/hos-eval" mesh --result "$work/points.ply" --truth "$work/scene/gt_objects.ply" --thresholds 0.005,0.01 \
    --json "$work/eval.json" > /dev/null
  python3 - "$work/eval.json" "${labels[$k]}" "$user" "$sys" "$kb" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
r = {round(x["fraction"], 4): x["recall"] for x in d["thresholds"]}
print(f"| {sys.argv[2]} | {r[0.005]:.3f} / {r[0.01]:.3f} | {float(sys.argv[3]) + float(sys.argv[4]):.1f} | {int(sys.argv[5]) / 1024:.0f} |")
PY
done
