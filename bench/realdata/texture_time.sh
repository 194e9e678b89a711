#!/usr/bin/env bash
# hos-texture time of two builds side by side on real photos: each WORK made
# by bench/realdata/holdout.sh, texturing the refined mesh of one of its runs
# (made with --keep), the builds run alternately (old, new, old, new, ...)
# so both see the same load. Prints one row per run and, per WORK, the
# ratios new / old of the medians of wall and CPU (user + sys) time.
#
#   bench/realdata/texture_time.sh OLD_BIN NEW_BIN WORK[:WORK...] LABEL [--repeat N] [--set texture.key=value]...
#
# LABEL        the run whose refined.ply is textured (WORK/runs/LABEL/refined.ply)
# --repeat N   runs of each build per WORK (default 2)
# --set        applies to the new build only (e.g. a setting being weighed)
set -euo pipefail
usage() { sed -n '8,11p' "$0" | sed 's/^# *//' >&2; exit 2; }
stage=hos-texture
source "$(dirname "$0")/side_by_side.sh"
parse_run_file_arguments "$@"

run_one() {
  local bin="$1"
  shift
  timed "$input" "$bin/hos-texture" --workspace "$undistorted" --mesh "$input" --output "$tmp/model.glb" \
    --progress none --log "$tmp/texture.log" "$@"
}

time_on_run_files "$label" refined.ply run_one "${works[@]}"
