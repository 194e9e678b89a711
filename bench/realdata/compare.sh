#!/usr/bin/env bash
# Compares runs of bench/realdata/holdout.sh on the same WORK folder over the
# pixels of the held-out photo that every run covers. holdout.sh measures each
# run over its own rendered pixels, which rewards holes: a run that trims
# uncertain surface away is not measured there. Here every run is measured
# on the same pixels; the table also gives each run's own coverage.
#
#   bench/realdata/compare.sh BIN WORK LABEL LABEL...
#
# BIN holds hos-eval; the runs' renders must come from a hos-eval that saves
# the render's mask (this commit or later).
set -euo pipefail
[ $# -ge 4 ] || { sed -n '8p' "$0" | sed 's/^# *//' >&2; exit 2; }
bin="$1" work="$2"
shift 2
labels=("$@")
echo "| camera | run | PSNR dB (common pixels) | SSIM (common pixels) | own coverage | common coverage |"
echo "|---|---|---|---|---|---|"
for camera in true registered; do
  saved=()
  for label in "${labels[@]}"; do
    view=$(ls "$work/runs/$label/$camera/"*.png | head -n 1)
    saved+=(--saved "$view")
  done
  "$bin/hos-eval" common "${saved[@]}" --json "$work/common-$camera.json" >/dev/null
  python3 - "$work/common-$camera.json" "$camera" "${labels[@]}" <<'PY'
import json, sys
path, camera, labels = sys.argv[1], sys.argv[2], sys.argv[3:]
d = json.load(open(path))
for label, run in zip(labels, d["runs"]):
    print(f"| {camera} | {label} | {run['psnr']:.2f} | {run['ssim']:.3f} | {run['coverage']:.3f} | {d['common_coverage']:.3f} |")
PY
done
