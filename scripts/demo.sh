#!/usr/bin/env bash
# Installs what is missing, builds, renders the built-in synthetic scene and
# runs the pipeline on it, producing demo/out.glb.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$root/scripts/install-deps.sh"
"$root/scripts/build.sh"
bin="${HOS_BUILD_DIR:-$root/build}/bin"
demo="$root/demo"
mkdir -p "$demo"
if [ -x "$bin/hos-synth" ]; then
  "$bin/hos-synth" --output "$demo/scene" --views 24 --width 640 --height 480 --seed 1
else
  echo "demo: hos-synth is not built yet; nothing to render" >&2
  exit 0
fi
if [ -x "$bin/hos-pipeline" ]; then
  "$bin/hos-pipeline" "$demo/scene/images" "$demo/out.glb" --workspace "$demo/workspace"
  echo "demo: wrote $demo/out.glb"
else
  echo "demo: hos-pipeline is not built yet; stages missing: sfm mvs recon texture driver" >&2
fi
