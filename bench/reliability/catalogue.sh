#!/usr/bin/env bash
# The bad-input catalogue of docs/reliability.md, run against one build: each
# case with the exit code and the error (or warning) hos gives. Run it on two
# builds to compare them. Stage executables stand in for COLMAP where the
# case does not need it (fake stages next to a copy of hos-pipeline).
#   bench/reliability/catalogue.sh [BIN_DIR]     # default build/bin
set -uo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
bin="$(cd "${1:-$root/build/bin}" && pwd)"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
cd "$work"

# sphere N RADIUS CX OUT [EXTRA]: ASCII PLY of N points on a sphere (golden
# spiral) with outward normals; EXTRA lines ("x y z nx ny nz") are appended.
sphere() {
  awk -v n="$1" -v r="$2" -v cx="$3" -v extra="${5:-}" 'BEGIN {
    m = split(extra, e, ";"); if (extra == "") m = 0
    printf "ply\nformat ascii 1.0\nelement vertex %d\n", n + m
    printf "property float x\nproperty float y\nproperty float z\n"
    printf "property float nx\nproperty float ny\nproperty float nz\nend_header\n"
    for (i = 0; i < n; i++) {
      z = 1 - 2 * (i + 0.5) / n; s = sqrt(1 - z * z); t = i * 2.399963229728653
      x = s * cos(t); y = s * sin(t)
      printf "%.9g %.9g %.9g %.6f %.6f %.6f\n", cx + r * x, r * y, r * z, x, y, z
    }
    for (k = 1; k <= m; k++) print e[k]
  }' > "$4"
}

# row NAME CODE LOG: one table row with the last error or warning line.
row() {
  local message
  message="$(grep -E 'error|warn' "$3" | tail -1 | sed -e "s|$work/||g" -e 's/|/\\|/g' | cut -c1-220)"
  printf '| %s | %s | %s |\n' "$1" "$2" "${message:--}"
}

recon() { "$bin/hos-recon" --progress none "$@" > log.txt 2>&1; echo $?; }

echo "| case | exit | message |"
echo "|---|---|---|"
sphere 4000 1 0 sphere.ply
sphere 4000 1000 0 sphere1000.ply
code=$(recon --input sphere1000.ply --output m.ply --set recon.voxel_size=2e-7)
row "recon.voxel_size=2e-7 on a sphere of radius 1000" "$code" log.txt
printf 'ply\nformat ascii 1.0\nelement vertex 50\nproperty float x\nproperty float y\nproperty float z\nproperty float nx\nproperty float ny\nproperty float nz\nend_header\n' > same.ply
for i in $(seq 50); do echo "1 2 3 0 0 1" >> same.ply; done
code=$(recon --input same.ply --output m.ply --resolution 32); row "all points identical" "$code" log.txt
sphere 4000 1e-30 0 tiny.ply
code=$(recon --input tiny.ply --output tiny_mesh.ply --resolution 32 --ascii)
size=$(awk '/end_header/ {h = 1; next} h && NF == 3 + 0 || (h && NF >= 3 && $1 != 3) {v = ($1 < 0 ? -$1 : $1); if (v > m) m = v} END {print m + 0}' tiny_mesh.ply 2>/dev/null)
row "sphere of radius 1e-30 (largest mesh coordinate: ${size:-none})" "$code" log.txt
sphere 4000 1 0 outlier.ply "1e6 0 0 1 0 0"
code=$(recon --input outlier.ply --output m.ply --resolution 32)
row "one point at 1e6 ($(grep -o '[0-9]* vertices' log.txt | tail -1))" "$code" log.txt
awk '/end_header/ {print; h = 1; next} !h {print; next} {printf "%s %s %s %g %g %g\n", $1, $2, $3, $4 * 1e38, $5 * 1e38, $6 * 1e38}' sphere.ply > long_normals.ply
code=$(recon --input long_normals.ply --output m.ply --resolution 32); row "normals of length 1e38" "$code" log.txt
awk '/property float nz/ {print; print "property float confidence"; next} /end_header/ {print; h = 1; next} !h {print; next} {c = (NR % 3 == 0) ? "nan" : (NR % 3 == 1 ? "-1" : "0"); print $0, c}' sphere.ply > bad_conf.ply
code=$(recon --input bad_conf.ply --output m.ply --resolution 32); row "confidence NaN, -1 or 0 everywhere" "$code" log.txt
mkdir -p folder.ply
start=$(date +%s.%N)
code=$(recon --input sphere.ply --output folder.ply --resolution 128)
row "recon output is a folder ($(awk -v s="$start" -v e="$(date +%s.%N)" 'BEGIN {printf "%.1f s", e - s}'))" "$code" log.txt
printf 'recon:\n  lambda: [1, 2\n' > bad.yaml
code=$(recon --input sphere.ply --output m.ply --config bad.yaml); row "malformed YAML" "$code" log.txt
printf 'recon:\n  lambda: 0.5\n  lambda: 0.7\n' > twice.yaml
code=$(recon --input sphere.ply --output m.ply --config twice.yaml --resolution 32); row "a key given twice" "$code" log.txt

# hos-sfm's photo check (before COLMAP).
mkdir -p loop_photos && ln -s loop.jpg loop_photos/loop.jpg
"$bin/hos-sfm" --images loop_photos --workspace sfm_ws --progress none > log.txt 2>&1
row "symlink loop in the photo folder" "$?" log.txt

# hos-pipeline with stand-in stages.
mkdir -p fake photos
cp "$bin/hos-pipeline" fake/
for s in sfm mvs recon texture; do
  cat > "fake/hos-$s" << FAKE
#!/bin/sh
stage=$s
FAKE
  cat >> "fake/hos-$s" << 'FAKE'
out=""; ws=""
while [ $# -gt 0 ]; do case "$1" in --output) out="$2"; shift ;; --workspace) ws="$2"; shift ;; esac; shift; done
[ -n "$FAKE_SLEEP" ] && [ "$FAKE_SLEEP" = "$stage" ] && exec sleep 20
[ -n "$FAKE_FAIL" ] && [ "$FAKE_FAIL" = "$stage" ] && { echo "bad input" >&2; exit 3; }
case "$stage" in
  sfm) mkdir -p "$ws/sfm/undistorted/sparse" "$ws/sfm/undistorted/images"; echo c > "$ws/sfm/undistorted/sparse/cameras.txt"; echo '{}' > "$ws/sfm/report.json" ;;
  *) echo "$stage" > "$out" ;;
esac
FAKE
  chmod +x "fake/hos-$s"
done
for p in a b c; do echo "$p" > "photos/$p.jpg"; done
pipeline() { "$work/fake/hos-pipeline" --progress none "$@" > log.txt 2>&1; echo $?; }
FAKE_SLEEP=sfm "$work/fake/hos-pipeline" --progress none photos first.glb > first.txt 2>&1 &
first=$!
sleep 1
code=$(pipeline photos first.glb); row "a second hos-pipeline on the same workspace" "$code" log.txt
kill -9 $first; wait $first 2> /dev/null
sleep 0.5
row "... the first one killed with kill -9 (stage processes left: $(pgrep -fc 'sleep 20'))" "-" /dev/null
code=$(pipeline photos first.glb); row "... and run again" "$code" log.txt
code=$(pipeline photos /proc/out.glb --workspace ws2); row "output folder not writable (/proc)" "$code" log.txt
pipeline photos photos/model.glb > /dev/null
code=$(pipeline photos photos/model.glb)
row "output inside the photo folder, second run ($(grep -c 'up to date, skipped' log.txt) of 4 stages skipped)" "$code" log.txt
code=$(pipeline photos fresh.glb --from recon)
row "--from recon without a workspace (workspace created: $([ -d fresh_workspace ] && echo yes || echo no))" "$code" log.txt
echo damaged > first_workspace/mvs/points.ply
code=$(FAKE_FAIL=recon pipeline photos first.glb); row "damaged intermediate (mvs/points.ply)" "$code" log.txt
