#!/usr/bin/env bash
# Installs what is missing, builds the programs the demo runs, renders the
# built-in synthetic scene and runs the pipeline on it (sfm, mvs, recon,
# refine, texture), producing demo/out.glb and its run report.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$root/scripts/install-deps.sh"
# Only what the demo runs (hos-pipeline brings the report's model viewer);
# scripts/test.sh builds the rest in the same build folder.
"$root/scripts/build.sh" --target hos-synth hos-pipeline hos-sfm hos-mvs hos-recon hos-refine hos-texture
bin="${HOS_BUILD_DIR:-$root/build}/bin"
demo="$root/demo"
mkdir -p "$demo"
"$bin/hos-synth" --output "$demo/scene" --views 24 --width 640 --height 480 --seed 1
"$bin/hos-pipeline" "$demo/scene/images" "$demo/out.glb" --workspace "$demo/workspace"
echo "demo: wrote $demo/out.glb and the run report $demo/workspace/report.html"
