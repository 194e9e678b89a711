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
stage=hos-refine
source "$(dirname "$0")/side_by_side.sh"
parse_run_file_arguments "$@"

run_one() {
  local bin="$1"
  shift
  timed "$input" "$bin/hos-refine" --workspace "$undistorted" --mesh "$input" --output "$tmp/refined.ply" \
    --progress none --log "$tmp/refine.log" --set refine.max_seconds=100000 "$@"
}

time_on_run_files "$label" mesh.ply run_one "${works[@]}"
