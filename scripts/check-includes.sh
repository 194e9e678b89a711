#!/usr/bin/env bash
# Checks the include rules of docs/developing.md: which folder's sources may
# include which folder's headers. Exits non-zero and names every include that
# breaks them.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"

# folder -> the hos folders its sources may include (besides its own).
declare -A allowed=(
  [core]=""
  [render]="core"
  [synth]="core render"
  [eval]="core render"
  [sfm]="core"
  [mvs]="core"
  [recon]="core"
  [refine]="core render"
  [texture]="core render"
  [pipeline]="core sfm mvs recon refine texture"
  [apps]="core render synth eval sfm mvs recon refine texture pipeline"
  [examples]="core render synth eval sfm mvs recon refine texture"
)
folders="core|render|synth|eval|sfm|mvs|recon|refine|texture|pipeline|apps|tests|bench|examples"

broken=0
checked=0
for folder in "${!allowed[@]}"; do
  [ -d "$folder" ] || continue
  while IFS=: read -r file line include; do
    target="${include%%/*}"
    checked=$((checked + 1))
    if [ "$target" = "$folder" ]; then continue; fi
    if [[ " ${allowed[$folder]} " != *" $target "* ]]; then
      echo "check-includes: $file:$line includes $include ($folder/ may include: ${allowed[$folder]:-only itself})" >&2
      broken=$((broken + 1))
    fi
  done < <(grep -rnoE "^#include \"($folders)/[^\"]+\"" "$folder" --include='*.h' --include='*.cpp' --include='*.in' |
    sed -E 's/^([^:]+):([0-9]+):#include "([^"]+)"/\1:\2:\3/')
done
if [ "$broken" -gt 0 ]; then
  echo "check-includes: $broken include(s) break the rules of docs/developing.md" >&2
  exit 1
fi
echo "check-includes: $checked includes follow the rules"
