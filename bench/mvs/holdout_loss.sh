#!/usr/bin/env bash
# Where a real set's held-out photo loses its surface, stage by stage: the
# share of the held-out photo's pixels (cells of 8x8) each stage's output
# covers through the held-out camera (hos-mvs-holdout-loss):
#   depth maps     every depth pixel of every training view, unfused (and of
#                  two views or more: what fusion can confirm)
#   fused points   hos-mvs's points (geometric consistency)
#   recon, untrimmed   hos-recon --no-trim --keep-debris
#   recon, trimmed     hos-recon --keep-debris (trimming only)
#   recon mesh         hos-recon's default (trimming and debris removal)
#   refined mesh       hos-refine's mesh of the recon mesh
# WORK is a bench/realdata/holdout.sh folder made with --shared-sfm (the
# training photos' SfM is the SfM of all photos without the held-out one, so
# the held-out camera is in the training frame).
#   bench/mvs/holdout_loss.sh WORK BIN [--label L] [--keep] [--set stage.key=value]...
# The run goes to WORK/loss/L (default label: loss).
set -euo pipefail
usage() { sed -n '15,16p' "$0" | sed 's/^# *//' >&2; exit 2; }
[ $# -ge 2 ] || usage
work="$(cd "$1" && pwd)" bin="$(cd "$2" && pwd)"
shift 2
label=loss keep=0 sets=()
while [ $# -gt 0 ]; do
  case "$1" in
    --label) label="$2"; shift 2 ;;
    --keep) keep=1; shift ;;
    --set) sets+=(--set "$2"); shift 2 ;;
    *) usage ;;
  esac
done
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
tool="${HOS_BUILD_DIR:-$root/build}/bin/hos-mvs-holdout-loss"
grep -qx 'shared sfm 1' "$work/photos.txt" 2>/dev/null || {
  echo "$work: not a holdout.sh WORK made with --shared-sfm" >&2; exit 3; }
holdout="$(sed -n 's/^holdout //p' "$work/photos.txt")"
undistorted="$work/sfm-train/sfm/undistorted"
run="$work/loss/$label"
rm -rf "$run"
mkdir -p "$run"
stage_sets() { local s; for s in "${sets[@]}"; do case "$s" in "$1".*) printf '%s\n' --set "$s" ;; esac; done; }
mapfile -t mvs_sets < <(stage_sets mvs)
mapfile -t recon_sets < <(stage_sets recon)
mapfile -t refine_sets < <(stage_sets refine)
/usr/bin/time -f "%U %S" -o "$run/mvs.time" "$bin/hos-mvs" --workspace "$undistorted" --output "$run/points.ply" \
  --depth-maps "$run/depth" --progress none "${mvs_sets[@]}" > /dev/null
"$bin/hos-recon" --input "$run/points.ply" --output "$run/untrimmed.ply" --no-trim --keep-debris --progress none \
  "${recon_sets[@]}" > /dev/null
"$bin/hos-recon" --input "$run/points.ply" --output "$run/trimmed.ply" --keep-debris --progress none \
  "${recon_sets[@]}" > /dev/null
"$bin/hos-recon" --input "$run/points.ply" --output "$run/recon.ply" --progress none "${recon_sets[@]}" > /dev/null
"$bin/hos-refine" --mesh "$run/recon.ply" --workspace "$undistorted" --output "$run/refine.ply" --progress none \
  "${refine_sets[@]}" > /dev/null
read -r user sys < "$run/mvs.time"
echo "mvs CPU $(python3 -c "print(f'{$user + $sys:.1f}')") s, held-out photo $holdout"
"$tool" --view-model "$work/models/all-txt" --view "$holdout" --model "$undistorted/sparse" --depth-maps "$run/depth" \
  --stage "fused points=$run/points.ply" --stage "recon, untrimmed, debris kept=$run/untrimmed.ply" \
  --stage "recon, trimmed, debris kept=$run/trimmed.ply" --stage "recon mesh=$run/recon.ply" \
  --stage "refined mesh=$run/refine.ply" | tee "$run/loss.md"
[ "$keep" = 1 ] || rm -rf "$run/depth" "$run"/*.ply
