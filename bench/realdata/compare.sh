#!/usr/bin/env bash
# Compares runs of bench/realdata/holdout.sh on the same WORK folder over the
# pixels of the held-out photo that every run covers. holdout.sh measures each
# run over its own rendered pixels, which rewards holes: a run that trims
# uncertain surface away is not measured there. Here every run is measured
# on the same pixels; the table also gives each run's own coverage.
#
#   bench/realdata/compare.sh BIN WORK[:WORK...] LABEL LABEL...
#
# Several WORK folders (colon-separated, one per held-out photo, each made by
# holdout.sh --holdout NAME with the same labels) add a row per label with
# the mean over the photos: one photo's figure moves by a few tenths of a dB
# with small changes of the surface, so a mean over photos is steadier.
# "exposure matched" is the PSNR after fitting each run's render to the photo
# by a gain and offset per colour channel (hos-eval common): the held-out
# photo's exposure is unknown to the pipeline, and on some photos it, not the
# surface, decides most of the plain PSNR.
# BIN holds hos-eval; the runs' renders must come from a hos-eval that saves
# the render's mask (this commit or later).
set -euo pipefail
[ $# -ge 4 ] || { sed -n '8p' "$0" | sed 's/^# *//' >&2; exit 2; }
bin="$1"
IFS=: read -r -a works <<<"$2"
shift 2
labels=("$@")
for work in "${works[@]}"; do
  for camera in true registered; do
    saved=()
    for label in "${labels[@]}"; do
      view=$(ls "$work/runs/$label/$camera/"*.png | head -n 1)
      saved+=(--saved "$view")
    done
    "$bin/hos-eval" common "${saved[@]}" --json "$work/common-$camera.json" >/dev/null
  done
done
python3 - "${#labels[@]}" "${labels[@]}" "${works[@]}" <<'PY'
import json, os, sys
count = int(sys.argv[1])
labels, works = sys.argv[2:2 + count], sys.argv[2 + count:]
print("| camera | held out | run | PSNR dB (common pixels) | exposure matched | SSIM (common pixels) | own coverage "
      "| common coverage |")
print("|---|---|---|---|---|---|---|---|")
sums = {}
for camera in ("true", "registered"):
    for work in works:
        d = json.load(open(os.path.join(work, f"common-{camera}.json")))
        held_out = next((line.split(" ", 1)[1].strip() for line in open(os.path.join(work, "photos.txt"))
                         if line.startswith("holdout ")), os.path.basename(os.path.normpath(work)))
        for label, run in zip(labels, d["runs"]):
            print(f"| {camera} | {held_out} | {label} | {run['psnr']:.2f} | {run['psnr_exposure_matched']:.2f} | "
                  f"{run['ssim']:.3f} | {run['coverage']:.3f} | {d['common_coverage']:.3f} |")
            s = sums.setdefault((camera, label), [0.0, 0.0, 0.0])
            s[0] += run["psnr"]
            s[1] += run["psnr_exposure_matched"]
            s[2] += run["ssim"]
    if len(works) > 1:
        for label in labels:
            psnr, matched, ssim = (v / len(works) for v in sums[(camera, label)])
            print(f"| {camera} | mean of {len(works)} | {label} | {psnr:.2f} | {matched:.2f} | {ssim:.3f} | | |")
PY
