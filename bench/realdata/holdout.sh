#!/usr/bin/env bash
# Leave-one-out hold-out benchmark on a real photo set with true cameras
# (Strecha et al. layout: DATA/images/*.jpg, DATA/gt_dense_cameras/<image>.camera).
# The pipeline (hos-sfm, hos-mvs, hos-recon, hos-refine, hos-texture from BIN) runs on all
# photos but one; the textured result is rendered from the held-out photo's
# camera and compared with the photo (PSNR, SSIM over the rendered pixels,
# coverage = rendered pixels / photo pixels), through two cameras:
#   true        the published camera; the result is mapped onto the true
#               cameras by a similarity over the training camera centres
#               (this also measures COLMAP's self-calibration);
#   registered  the held-out photo's camera from an SfM of all photos, the
#               result mapped into that frame by a similarity over the
#               shared cameras (measures mesh and texture).
# Both SfM runs are made once per WORK folder and reused: run the script
# with several BIN folders (or --set overrides, under different --label) on
# the same WORK to compare them side by side; bench/realdata/compare.sh then
# measures them on the pixels all of them cover (a run's own pixels reward holes).
# A WORK folder holds one held-out photo; run the same labels on a second
# WORK with --holdout NAME and compare.sh averages over both.
#
#   bench/realdata/holdout.sh DATA BIN WORK [--holdout NAME] [--photos N] [--label L]
#                             [--set stage.key=value]... [--keep] [--sfm-only] [--shared-sfm]
#                             [--mesh-from L] [--points-from L]
#
# --holdout   photo to hold out (default: the middle one by name)
# --photos N  use only the N photos nearest the held-out one by name (quick runs)
# --label L   name of this run under WORK/runs/ (default: from BIN and the --set values)
# --keep      keep the run's points and mesh (default: only model.glb and the renders)
# --sfm-only  only make the two SfM workspaces and the camera models
# --shared-sfm  no SfM of the training photos: the run uses the SfM of all
#             photos with the held-out one removed (its images, cameras and
#             observations); quicker, but that photo shaped the cameras
# --mesh-from L  start at refine with the points and mesh of run L (made
#             with --keep; its mvs and recon times are reported): compares
#             refine and texture settings without rerunning mvs and recon
# --points-from L  start at recon with the points of run L (made with --keep;
#             its mvs time is reported): compares recon settings or builds
#             without rerunning mvs
# --set sfm.K=V  applies to both SfM runs, which are made once per WORK: a
#             WORK holds one set of sfm values (another set is refused)
# Prints one markdown row per camera; figures also in WORK/runs/L/summary.json.
set -euo pipefail
usage() { sed -n '19,33p' "$0" | sed 's/^# *//' >&2; exit 2; }
[ $# -ge 3 ] || usage
data="$(cd "$1" && pwd)" bin="$(cd "$2" && pwd)" work="$3"
shift 3
holdout="" photos=0 label="" keep=0 sfm_only=0 shared=0 mesh_from="" points_from="" sets=()
while [ $# -gt 0 ]; do
  case "$1" in
    --holdout) holdout="$2"; shift 2 ;;
    --photos) photos="$2"; shift 2 ;;
    --label) label="$2"; shift 2 ;;
    --set) sets+=(--set "$2"); shift 2 ;;
    --keep) keep=1; shift ;;
    --mesh-from) mesh_from="$2"; shift 2 ;;
    --points-from) points_from="$2"; shift 2 ;;
    --sfm-only) sfm_only=1; shift ;;
    --shared-sfm) shared=1; shift ;;
    *) usage ;;
  esac
done
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
for tool in hos-sfm hos-mvs hos-recon hos-refine hos-texture hos-eval; do
  [ -x "$bin/$tool" ] || { echo "$bin/$tool: missing" >&2; exit 3; }
done
[ -d "$data/images" ] && [ -d "$data/gt_dense_cameras" ] || {
  echo "$data: expected images/ and gt_dense_cameras/" >&2; exit 3; }
mkdir -p "$work"
work="$(cd "$work" && pwd)"

# The photo set: all photos (or N around the held-out one), and the training set.
mapfile -t all < <(cd "$data/images" && ls | grep -iE '\.(jpe?g|png|tiff?)$' | sort)
[ "${#all[@]}" -ge 4 ] || { echo "$data/images: fewer than 4 photos" >&2; exit 3; }
[ -n "$holdout" ] || holdout="${all[$(( ${#all[@]} / 2 ))]}"
centre=-1
for i in "${!all[@]}"; do [ "${all[$i]}" = "$holdout" ] && centre=$i; done
[ "$centre" -ge 0 ] || { echo "$data/images/$holdout: no such photo" >&2; exit 3; }
if [ "$photos" -gt 0 ] && [ "$photos" -lt "${#all[@]}" ]; then
  first=$(( centre - photos / 2 )); [ "$first" -ge 0 ] || first=0
  [ $(( first + photos )) -le "${#all[@]}" ] || first=$(( ${#all[@]} - photos ))
  all=("${all[@]:$first:$photos}")
fi
# The --set values of one stage (each stage refuses another stage's keys).
stage_sets() { local i; for ((i = 1; i < ${#sets[@]}; i += 2)); do
  case "${sets[$i]}" in "$1".*) printf '%s\0' --set "${sets[$i]}" ;; esac; done; }
for stage in sfm mvs recon refine texture; do mapfile -d '' -t "sets_$stage" < <(stage_sets "$stage"); done
signature="$(printf '%s\n' "${all[@]}" "holdout $holdout" "shared sfm $shared" "sfm ${sets_sfm[*]:-}")"
if [ -f "$work/photos.txt" ] && [ "$(cat "$work/photos.txt")" != "$signature" ]; then
  echo "$work: made for another photo set or held-out photo (see $work/photos.txt); use another WORK" >&2
  exit 2
fi
printf '%s\n' "$signature" > "$work/photos.txt"
for set_name in all train; do
  mkdir -p "$work/photos-$set_name"
  for p in "${all[@]}"; do
    [ "$set_name" = train ] && [ "$p" = "$holdout" ] && continue
    ln -sf "$data/images/$p" "$work/photos-$set_name/$p"
  done
done

# SfM once per WORK (whichever BIN comes first), and the models the renders use.
sfm() {
  if [ ! -f "$work/sfm-$1/sfm/undistorted/sparse/images.bin" ] &&
     [ ! -f "$work/sfm-$1/sfm/undistorted/sparse/images.txt" ]; then
    echo "sfm of $1 photos (once per WORK) ..." >&2
    "$bin/hos-sfm" --images "$work/photos-$1" --workspace "$work/sfm-$1" --progress none \
      --log "$work/sfm-$1.log" "${sets_sfm[@]}" >/dev/null
  fi
}
sfm all
if [ ! -f "$work/models/registered/images.txt" ]; then
  mkdir -p "$work/models/all-txt"
  colmap model_converter --input_path "$work/sfm-all/sfm/undistorted/sparse" \
    --output_path "$work/models/all-txt" --output_type TXT >/dev/null
  python3 "$here/models.py" subset "$work/models/all-txt" "$work/models/registered" "$holdout"
  python3 "$here/models.py" strecha "$data/gt_dense_cameras" "$work/models/truth"
  python3 "$here/models.py" subset "$work/models/truth" "$work/models/true" "$holdout"
fi
if [ "$shared" = 1 ]; then
  if [ ! -f "$work/sfm-train/sfm/undistorted/sparse/images.txt" ]; then
    mkdir -p "$work/sfm-train/sfm/undistorted/images"
    for p in "${all[@]}"; do
      [ "$p" = "$holdout" ] || ln -sf "$work/sfm-all/sfm/undistorted/images/$p" "$work/sfm-train/sfm/undistorted/images/$p"
    done
    python3 "$here/models.py" without "$work/models/all-txt" "$work/sfm-train/sfm/undistorted/sparse" "$holdout"
  fi
else
  sfm train
fi

[ "$sfm_only" = 0 ] || exit 0

# The run: stage executables on the training set's SfM workspace.
if [ -z "$label" ]; then
  label="$(printf '%s' "$bin ${sets[*]:-}" | tr -c 'A-Za-z0-9._=-' '_' | sed 's/^_*//')"
fi
run="$work/runs/$label"
rm -rf "$run"
mkdir -p "$run"
undistorted="$work/sfm-train/sfm/undistorted"
# Wall s, CPU s (user + sys: steadier than wall on a shared machine), peak KB.
timed() { /usr/bin/time -f "%e %U %S %M" -o "$run/$1.time" "${@:2}"; }
if [ -n "$mesh_from" ]; then
  from="$work/runs/$mesh_from"
  [ -f "$from/mesh.ply" ] || { echo "$from/mesh.ply: missing (make run $mesh_from with --keep)" >&2; exit 3; }
  cp "$from/points.ply" "$from/mesh.ply" "$from/mvs.time" "$from/recon.time" "$run/"
else
  if [ -n "$points_from" ]; then
    from="$work/runs/$points_from"
    [ -f "$from/points.ply" ] || { echo "$from/points.ply: missing (make run $points_from with --keep)" >&2; exit 3; }
    cp "$from/points.ply" "$from/mvs.time" "$run/"
  else
    timed mvs "$bin/hos-mvs" --workspace "$undistorted" --output "$run/points.ply" --progress none \
      --log "$run/mvs.log" "${sets_mvs[@]}" >/dev/null
  fi
  timed recon "$bin/hos-recon" --input "$run/points.ply" --output "$run/mesh.ply" --progress none \
    --log "$run/recon.log" "${sets_recon[@]}" >/dev/null
fi
# hos-refine passes the mesh through unchanged with --set refine.enabled=false.
timed refine "$bin/hos-refine" --workspace "$undistorted" --mesh "$run/mesh.ply" --output "$run/refined.ply" \
  --progress none --log "$run/refine.log" "${sets_refine[@]}" >/dev/null
timed texture "$bin/hos-texture" --workspace "$undistorted" --mesh "$run/refined.ply" --output "$run/model.glb" \
  --progress none --log "$run/texture.log" "${sets_texture[@]}" >/dev/null
"$bin/hos-eval" render --glb "$run/model.glb" --model "$work/models/true" --images "$data/images" \
  --align-model "$undistorted/sparse" --truth-model "$work/models/truth" --save "$run/true" \
  --json "$run/true.json" >/dev/null
"$bin/hos-eval" render --glb "$run/model.glb" --model "$work/models/registered" \
  --images "$work/sfm-all/sfm/undistorted/images" --align-model "$undistorted/sparse" \
  --truth-model "$work/sfm-all/sfm/undistorted/sparse" --save "$run/registered" \
  --json "$run/registered.json" >/dev/null
points=$(grep -a -m1 '^element vertex' "$run/points.ply" | cut -d' ' -f3)
[ "$keep" = 1 ] || rm -f "$run/points.ply" "$run/mesh.ply" "$run/refined.ply"

python3 - "$run" "$label" "$holdout" "$points" "$work/models" <<'PY'
import json, sys
run, label, holdout, points, models = sys.argv[1:6]
def size(model):
    fields = next(l.split() for l in open(f"{models}/{model}/cameras.txt") if l.strip() and not l.startswith("#"))
    return int(fields[2]) * int(fields[3])
def timing(stage):
    wall, user, system, kb = open(f"{run}/{stage}.time").read().split()[-4:]
    return {"seconds": float(wall), "cpu_seconds": float(user) + float(system), "peak_mb": int(kb) / 1024}
summary = {"label": label, "holdout": holdout, "points": int(points)}
for stage in ("mvs", "recon", "refine", "texture"):
    summary[stage] = timing(stage)
print("| run | camera | PSNR dB | SSIM | coverage | mvs s | mvs CPU s | mvs peak MB | points | recon s | refine s | refine CPU s | texture s |")
print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
for camera, model in (("true", "true"), ("registered", "registered")):
    d = json.load(open(f"{run}/{camera}.json"))
    views = d.get("views", [])
    v = views[0] if views else {"psnr": float("nan"), "ssim": float("nan"), "mask_pixels": 0}
    coverage = v["mask_pixels"] / size(model)
    summary[camera] = {"psnr": v["psnr"], "ssim": v["ssim"], "coverage": coverage,
                       "alignment_rms": d.get("alignment", {}).get("rms_residual")}
    print(f"| {label} | {camera} | {v['psnr']:.2f} | {v['ssim']:.3f} | {coverage:.3f} | {summary['mvs']['seconds']:.1f} "
          f"| {summary['mvs']['cpu_seconds']:.1f} | {summary['mvs']['peak_mb']:.0f} | {points} | {summary['recon']['seconds']:.1f} "
          f"| {summary['refine']['seconds']:.1f} | {summary['refine']['cpu_seconds']:.1f} | {summary['texture']['seconds']:.1f} |")
json.dump(summary, open(f"{run}/summary.json", "w"), indent=1)
PY
