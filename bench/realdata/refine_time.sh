#!/usr/bin/env bash
# hos-refine time of two builds side by side on real photos: each WORK made
# by bench/realdata/holdout.sh, refining the recon mesh of one of its runs
# (made with --keep), the builds run alternately (old, new, old, new, ...)
# so both see the same load. Prints one row per run and, per WORK, the
# ratios new / old of the medians of wall and CPU (user + sys) time.
#
#   bench/realdata/refine_time.sh OLD_BIN NEW_BIN WORK[:WORK...] LABEL [--repeat N] [--set refine.key=value]...
#
# LABEL        the run whose mesh.ply is refined (WORK/runs/LABEL/mesh.ply)
# --repeat N   runs of each build per WORK (default 2)
# --set        applies to the new build only (e.g. a setting being weighed)
# refine.max_seconds is raised for both, so that no run is cut by the load.
set -euo pipefail
usage() { sed -n '8,12p' "$0" | sed 's/^# *//' >&2; exit 2; }
[ $# -ge 4 ] || usage
stage=hos-refine
source "$(dirname "$0")/side_by_side.sh"
IFS=: read -r -a works <<<"$3"
label="$4"
check_builds "$1" "$2"
shift 4
parse_side_by_side_options "$@"

run_one() {
  local bin="$1"
  shift
  timed "$mesh" "$bin/hos-refine" --workspace "$undistorted" --mesh "$mesh" --output "$tmp/refined.ply" \
    --progress none --log "$tmp/refine.log" --set refine.max_seconds=100000 "$@"
}

echo "| WORK | build | run | wall s | CPU s | load avg |"
echo "|---|---|---|---|---|---|"
for work in "${works[@]}"; do
  undistorted="$work/sfm-train/sfm/undistorted" mesh="$work/runs/$label/mesh.ply"
  [ -d "$undistorted/sparse" ] || { echo "$undistorted/sparse: missing (make WORK with holdout.sh)" >&2; exit 3; }
  [ -f "$mesh" ] || { echo "$mesh: missing (make run $label with holdout.sh --keep)" >&2; exit 3; }
  run_alternately "$tmp/rows" run_one
  python3 - "$work" "$tmp/rows" <<'PY'
import os, statistics, sys
work, rows_path = sys.argv[1:3]
name = os.path.basename(os.path.normpath(work))
runs = {"old": [], "new": []}
for line in open(rows_path):
    build, r, wall, user, sys_, load = line.split()
    cpu = float(user) + float(sys_)
    runs[build].append((float(wall), cpu))
    print(f"| {name} | {build} | {r} | {float(wall):.1f} | {cpu:.1f} | {load} |")
med = {b: (statistics.median(x[0] for x in v), statistics.median(x[1] for x in v)) for b, v in runs.items()}
print(f"| {name} | new / old (medians) | | {med['new'][0] / med['old'][0]:.2f}x | {med['new'][1] / med['old'][1]:.2f}x | |")
PY
done
