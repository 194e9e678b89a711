#!/usr/bin/env bash
# Tiled reconstruction on the Stanford bunny's range scans (docs/scale.md):
# the whole run, the tiled run in one process and the same tiles as separate
# processes joined (the same bytes?), each with its wall time, CPU time and
# peak memory (/usr/bin/time -v), then hos-tile-sim's seam table.
#   bench/recon/tiles.sh --data DIR [--resolution 256] [--tiles 8] [--overlap 16]
# DIR holds stanford_bunny/data/bun.conf.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
bin="${HOS_BUILD_DIR:-$root/build}/bin"
data=""
resolution=256
tiles=8
overlap=16
while [ $# -gt 0 ]; do
  case "$1" in
    --data) data="$2"; shift 2 ;;
    --resolution) resolution="$2"; shift 2 ;;
    --tiles) tiles="$2"; shift 2 ;;
    --overlap) overlap="$2"; shift 2 ;;
    *) echo "usage: $0 --data DIR [--resolution R] [--tiles N] [--overlap VOXELS]" >&2; exit 2 ;;
  esac
done
[ -f "$data/stanford_bunny/data/bun.conf" ] || { echo "tiles.sh: give --data DIR with stanford_bunny/" >&2; exit 2; }
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

"$bin/hos-recon-bench" scans --conf "$data/stanford_bunny/data/bun.conf" --output "$work/bunny.ply" > /dev/null
common=(--input "$work/bunny.ply" --resolution "$resolution" --progress none
        --set recon.tile_overlap_voxels="$overlap")

# One line per run: wall s, CPU s (user + sys), peak MB.
measure() {
  local label="$1"
  shift
  /usr/bin/time -v "$@" > "$work/run.log" 2> "$work/time.txt" || { cat "$work/run.log" "$work/time.txt" >&2; exit 1; }
  awk -v label="$label" -F': ' '
    /User time/ {user = $2} /System time/ {sys = $2}
    /Elapsed \(wall clock\)/ {n = split($2, t, ":"); wall = (n == 3 ? t[1] * 3600 + t[2] * 60 + t[3] : t[1] * 60 + t[2])}
    /Maximum resident/ {mb = $2 / 1024}
    END {printf "| %s | %.1f | %.1f | %.0f |\n", label, wall, user + sys, mb}' "$work/time.txt"
}

echo "load average before: $(cut -d' ' -f1-3 /proc/loadavg)"
echo "| run | wall s | CPU s | peak MB |"
echo "|---|---|---|---|"
measure "whole" "$bin/hos-recon" "${common[@]}" --set recon.tiles=1 --output "$work/whole.ply"
measure "$tiles tiles, one process" "$bin/hos-recon" "${common[@]}" --set recon.tiles="$tiles" --output "$work/tiled.ply"
for ((k = 0; k < tiles; k++)); do
  measure "tile $k" "$bin/hos-recon" "${common[@]}" --set recon.tiles="$tiles" --tile "$k" --tile-dir "$work/tiles"
done
measure "join" "$bin/hos-recon" "${common[@]}" --set recon.tiles="$tiles" --join-tiles "$work/tiles" --output "$work/split.ply"
if cmp -s "$work/tiled.ply" "$work/split.ply"; then
  echo "split run: the same bytes as the one-process tiled run"
else
  echo "split run: DIFFERENT bytes from the one-process tiled run"
fi
echo
"$bin/hos-tile-sim" --input "$work/bunny.ply" --resolution "$resolution" --tiles "$tiles" --overlap-voxels "$overlap"
