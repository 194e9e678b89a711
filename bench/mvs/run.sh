#!/usr/bin/env bash
# hos-mvs speed and accuracy on a hos-synth scene with ground-truth cameras:
# seconds per view per megapixel (at the matching scale), points, and
# accuracy/completeness/F-score against the true surface the cameras see.
# CPU = user + system seconds of hos-mvs: steadier than the wall time when
# other jobs share the cores.
#   bench/mvs/run.sh [--views 24] [--width 640] [--height 480] [--max-image-size 640]
#                    [--scene default|railing|...] [--mvs-bin DIR] [--set mvs.key=value]...
# --mvs-bin: folder of the hos-mvs to measure (e.g. an older build), default this build's.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
bin="${HOS_BUILD_DIR:-$root/build}/bin"
views=24 width=640 height=480 max_size=640 scene=default mvs_bin="" sets=()
while [ $# -gt 0 ]; do
  case "$1" in
    --views) views="$2"; shift 2 ;;
    --width) width="$2"; shift 2 ;;
    --height) height="$2"; shift 2 ;;
    --max-image-size) max_size="$2"; shift 2 ;;
    --scene) scene="$2"; shift 2 ;;
    --mvs-bin) mvs_bin="$2"; shift 2 ;;
    --set) sets+=(--set "$2"); shift 2 ;;
    *) echo "usage: $0 [--views N] [--width W] [--height H] [--max-image-size S] [--scene NAME] [--mvs-bin DIR] [--set K=V]..." >&2; exit 2 ;;
  esac
done
mvs_bin="${mvs_bin:-$bin}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
"$bin/hos-synth" --output "$work/scene" --scene "$scene" --views "$views" --width "$width" --height "$height" \
  --seed 1 --progress none
/usr/bin/time -f "%e %M %U %S" -o "$work/time.txt" "$mvs_bin/hos-mvs" --workspace "$work/scene" \
  --output "$work/points.ply" --max-image-size "$max_size" --progress none "${sets[@]}"
read -r seconds kb user sys < "$work/time.txt"
cpu=$(awk -v u="$user" -v s="$sys" 'BEGIN { printf "%.1f", u + s }')
scale=$(awk -v w="$width" -v h="$height" -v m="$max_size" 'BEGIN { s = m / (w > h ? w : h); if (s > 1) s = 1; printf "%.6f", (w * s) * (h * s) / 1e6 }')
"$bin/hos-eval" mesh --result "$work/points.ply" --truth "$work/scene/gt_mesh.ply" --visible-in "$work/scene/sparse" \
  --json "$work/eval.json" > "$work/eval.txt"
load=$(cut -d' ' -f1 /proc/loadavg)
python3 - "$work" "$views" "$seconds" "$kb" "$scale" "$load" "$cpu" <<'PY'
import json, sys
work, views, seconds, kb, mp, load, cpu = sys.argv[1], int(sys.argv[2]), float(sys.argv[3]), int(sys.argv[4]), float(sys.argv[5]), sys.argv[6], float(sys.argv[7])
d = json.load(open(f"{work}/eval.json"))
t = {round(x["fraction"], 4): x for x in d["thresholds"]}
print("| views | MP per view | total s | s per view per MP | CPU s | CPU s per view per MP | peak MB | accuracy median | P/R/F @0.5% | P/R/F @1% | load avg |")
print("|---|---|---|---|---|---|---|---|---|---|---|")
f = lambda x: f"{x['precision']:.3f}/{x['recall']:.3f}/{x['f_score']:.3f}"
print(f"| {views} | {mp:.3f} | {seconds:.1f} | {seconds / views / mp:.2f} | {cpu:.1f} | {cpu / views / mp:.2f} | {kb / 1024:.0f} | {d['accuracy']['median']:.4g} | {f(t[0.005])} | {f(t[0.01])} | {load} |")
PY
