#!/usr/bin/env bash
# hos-mvs time of two builds side by side on real photos: each WORK made by
# bench/realdata/holdout.sh (its training photos' SfM), the builds run
# alternately (old, new, old, new, ...) so both see the same load. Prints
# one row per run and, per WORK, the ratios new / old of the medians of wall
# and CPU (user + sys) time, and the seconds per view per megapixel of the
# finest matching level.
#
#   bench/realdata/mvs_time.sh OLD_BIN NEW_BIN WORK[:WORK...] [--repeat N] [--set mvs.key=value]...
#
# --repeat N   runs of each build per WORK (default 2)
# --set        applies to the new build only (e.g. a setting being weighed)
set -euo pipefail
usage() { sed -n '9,12p' "$0" | sed 's/^# *//' >&2; exit 2; }
[ $# -ge 3 ] || usage
stage=hos-mvs
source "$(dirname "$0")/side_by_side.sh"
IFS=: read -r -a works <<<"$3"
check_builds "$1" "$2"
shift 3
parse_side_by_side_options "$@"

# One run; prints the finest level's size as this run had it.
run_one() {
  local bin="$1"
  shift
  timed "$undistorted" "$bin/hos-mvs" --workspace "$undistorted" --output "$tmp/points.ply" --progress none \
    --log "$tmp/mvs.log" "$@"
  # awk reads to the end: leaving early would end hos-mvs by SIGPIPE (and the run under pipefail).
  "$bin/hos-mvs" "$@" --print-config | awk '/^ *max_image_size:/ && !found { print $2; found = 1 }'
}

echo "| WORK | build | run | wall s | CPU s | views | finest level MP | s per view per MP (wall / CPU) | load avg |"
echo "|---|---|---|---|---|---|---|---|---|"
for work in "${works[@]}"; do
  undistorted="$work/sfm-train/sfm/undistorted"
  [ -d "$undistorted/sparse" ] || { echo "$undistorted/sparse: missing (make WORK with holdout.sh)" >&2; exit 3; }
  run_alternately "$tmp/rows" run_one
  python3 - "$work" "$undistorted" "$tmp/rows" <<'PY'
import os, struct, sys
work, undistorted, rows_path = sys.argv[1:4]
# The first camera's image size from the COLMAP model (text or binary; a
# binary camera record starts with id, model, width, height).
sparse = os.path.join(undistorted, "sparse")
if os.path.exists(os.path.join(sparse, "cameras.txt")):
    first = next(line.split() for line in open(os.path.join(sparse, "cameras.txt"))
                 if line.strip() and not line.startswith("#"))
    w, h = int(first[2]), int(first[3])
else:
    with open(os.path.join(sparse, "cameras.bin"), "rb") as f:
        _, _, _, w, h = struct.unpack("<QiiQQ", f.read(32))
views = len(os.listdir(os.path.join(undistorted, "images")))  # the registered photos, undistorted
for line in open(rows_path):
    build, r, wall, user, sys_, load, size = line.split()
    s = min(1.0, float(size) / max(w, h))
    mp = (w * s) * (h * s) / 1e6
    cpu = float(user) + float(sys_)
    print(f"| {os.path.basename(os.path.normpath(work))} | {build} | {r} | {float(wall):.1f} | {cpu:.1f} | {views} | "
          f"{mp:.2f} | {float(wall) / views / mp:.1f} / {cpu / views / mp:.1f} | {load} |")
PY
  medians_row "$(basename "$work")" "$tmp/rows" 4
done
