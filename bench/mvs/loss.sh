#!/usr/bin/env bash
# Where the surface is lost, stage by stage, on a hos-synth scene with true
# cameras: the share of the true surface a held-out view sees (hos-eval mesh
# --visible-in its sparse model) that each stage's output covers within 0.5%
# and 1% of the truth's bounding-box diagonal (recall; precision would count
# the surface the held-out view does not see as wrong, so it is not shown):
#   depth      every depth pixel of every view (hos-mvs --depth-maps), unfused
#   fused      hos-mvs's points (geometric consistency)
#   recon      hos-recon's mesh of those points (screening, trimming)
#   refine     hos-refine's mesh
# The drop from one row to the next is the share the stage loses; 1 - depth is
# the share no view matched. A second table (hos-mvs-depth-loss) sorts every
# training view's pixels of the true surface by the angle at which the view
# sees it (pixels near a silhouette in a row of their own): no depth
# (textureless or unmatched), a wrong depth, or a right one, and of those the
# ones a fused point lands on; a third sorts the pixels away from silhouettes
# by how many of the view's source views see their true point.
#   bench/mvs/loss.sh [--views 24] [--width 640] [--height 480] [--scene default] [--hanging-object]
#                     [--ground-plane] [--bin DIR] [--keep DIR] [--set stage.key=value]...
# --bin: folder of the hos-* binaries to measure (default this build's); hos-synth and hos-eval come from
# this build. --set applies to every stage (hos-mvs, hos-recon, hos-refine take their own keys).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
bin="${HOS_BUILD_DIR:-$root/build}/bin"
views=24 width=640 height=480 scene=default run_bin="" keep="" synth_flags=() sets=()
while [ $# -gt 0 ]; do
  case "$1" in
    --views) views="$2"; shift 2 ;;
    --width) width="$2"; shift 2 ;;
    --height) height="$2"; shift 2 ;;
    --scene) scene="$2"; shift 2 ;;
    --hanging-object | --ground-plane) synth_flags+=("$1"); shift ;;
    --bin) run_bin="$2"; shift 2 ;;
    --keep) keep="$2"; shift 2 ;;
    --set) sets+=(--set "$2"); shift 2 ;;
    *) sed -n '16,19p' "$0" | sed 's/^# *//' >&2; exit 2 ;;
  esac
done
run_bin="${run_bin:-$bin}"
if [ -n "$keep" ]; then
  work="$keep"
  mkdir -p "$work"
else
  work="$(mktemp -d)"
  trap 'rm -rf "$work"' EXIT
fi
stage_sets() { # the --set values of one stage
  local s
  for s in "${sets[@]}"; do case "$s" in "$1".*) printf '%s\n' --set "$s" ;; esac; done
}
mapfile -t mvs_sets < <(stage_sets mvs)
mapfile -t recon_sets < <(stage_sets recon)
mapfile -t refine_sets < <(stage_sets refine)
"$bin/hos-synth" --output "$work/scene" --scene "$scene" --views "$views" --width "$width" --height "$height" \
  --seed 1 --holdout 2 --progress none "${synth_flags[@]}"
/usr/bin/time -f "%U %S" -o "$work/mvs.time" "$run_bin/hos-mvs" --workspace "$work/scene" \
  --output "$work/points.ply" --depth-maps "$work/depth" --progress none "${mvs_sets[@]}"
"$run_bin/hos-recon" --input "$work/points.ply" --output "$work/recon.ply" --progress none "${recon_sets[@]}"
"$run_bin/hos-refine" --mesh "$work/recon.ply" --workspace "$work/scene" --output "$work/refine.ply" \
  --progress none "${refine_sets[@]}"

# Every depth pixel as a point (binary PLY), from the .dmap files and the true cameras.
python3 - "$work/scene/sparse" "$work/depth" "$work/depth_points.ply" <<'PY'
import array, math, os, struct, sys
sparse, folder, out = sys.argv[1:4]
cams = {}
for line in open(os.path.join(sparse, "cameras.txt")):
    f = line.split()
    if f and not line.startswith("#"):
        cams[f[0]] = (int(f[2]), int(f[3]), *map(float, f[4:8]))
lines = [l for l in open(os.path.join(sparse, "images.txt")) if l.strip() and not l.startswith("#")]
points = array.array("f")
for line in lines[0::2]:
    f = line.split()
    qw, qx, qy, qz, tx, ty, tz = map(float, f[1:8])
    w, h, fx, fy, cx, cy = cams[f[8]]
    R = [[1 - 2 * (qy * qy + qz * qz), 2 * (qx * qy - qz * qw), 2 * (qx * qz + qy * qw)],
         [2 * (qx * qy + qz * qw), 1 - 2 * (qx * qx + qz * qz), 2 * (qy * qz - qx * qw)],
         [2 * (qx * qz - qy * qw), 2 * (qy * qz + qx * qw), 1 - 2 * (qx * qx + qy * qy)]]
    path = os.path.join(folder, os.path.splitext(f[9])[0] + ".dmap")
    if not os.path.exists(path):
        path = os.path.join(folder, f[9] + ".dmap")
    data = open(path, "rb").read()
    mw, mh = struct.unpack_from("<ii", data, 8)
    depth = array.array("f")
    depth.frombytes(data[16:16 + 4 * mw * mh])
    sx, sy = mw / w, mh / h
    for y in range(mh):
        row = y * mw
        for x in range(mw):
            d = depth[row + x]
            if not d > 0:
                continue
            c = ((x + 0.5) / sx - cx) / fx * d, ((y + 0.5) / sy - cy) / fy * d, d
            c = (c[0] - tx, c[1] - ty, c[2] - tz)  # world = R^T (c - t)
            points.extend(R[0][k] * c[0] + R[1][k] * c[1] + R[2][k] * c[2] for k in range(3))
n = len(points) // 3
with open(out, "wb") as o:
    o.write(f"ply\nformat binary_little_endian 1.0\nelement vertex {n}\n"
            "property float x\nproperty float y\nproperty float z\nend_header\n".encode())
    o.write(points.tobytes())
PY

for stage in depth_points points recon refine; do
  "$bin/hos-eval" mesh --result "$work/$stage.ply" --truth "$work/scene/gt_mesh.ply" \
    --visible-in "$work/scene/holdout/sparse" --min-views 1 --json "$work/$stage.json" > /dev/null
done
read -r user sys < "$work/mvs.time"
python3 - "$work" "$user" "$sys" <<'PY'
import json, sys
work, user, sys_s = sys.argv[1], float(sys.argv[2]), float(sys.argv[3])
print(f"mvs CPU {user + sys_s:.1f} s")
print("| stage output | recall @0.5% | recall @1% | lost here @0.5% |")
print("|---|---|---|---|")
previous = 1.0
for stage, label in [("depth_points", "depth maps (every pixel)"), ("points", "fused points"),
                     ("recon", "recon mesh"), ("refine", "refined mesh")]:
    d = json.load(open(f"{work}/{stage}.json"))
    t = {round(x["fraction"], 4): x for x in d["thresholds"]}
    r = t[0.005]["recall"]
    print(f"| {label} | {r:.3f} | {t[0.01]['recall']:.3f} | {previous - r:.3f} |")
    previous = r
PY
echo
echo "Training views' pixels of the true surface, by incidence angle (shares of each row's pixels):"
"$bin/hos-mvs-depth-loss" --model "$work/scene/sparse" --depth-maps "$work/depth" --truth "$work/scene/gt_mesh.ply" \
  --points "$work/points.ply" "${mvs_sets[@]}"
