#!/usr/bin/env bash
# Checks the include rules of docs/developing.md: which room's sources may
# include which room's headers. Exits non-zero and names every include that
# breaks them.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"

# room -> the rooms its sources may include (besides its own). A room is a
# top-level folder, except that pipeline/ holds three: the driver
# (pipeline/driver.*), the Slurm executor (pipeline/slurm/) and the run
# report (pipeline/report/), on the part they share (the rest of pipeline/:
# stage table, config, run record).
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
  [pipeline/slurm]="core pipeline"
  [pipeline/report]="core pipeline"
  [pipeline/driver]="core sfm mvs recon refine texture pipeline pipeline/slurm pipeline/report"
  [apps]="core render synth eval sfm mvs recon refine texture pipeline pipeline/slurm pipeline/report pipeline/driver"
  [examples]="core render synth eval sfm mvs recon refine texture"
)
folders="core|render|synth|eval|sfm|mvs|recon|refine|texture|pipeline|apps|tests|bench|examples"

# Sets `room` to the room of a source file or an included header.
room_of() {
  case "$1" in
    pipeline/slurm/*) room=pipeline/slurm ;;
    pipeline/report/*) room=pipeline/report ;;
    pipeline/driver.*) room=pipeline/driver ;;
    *) room="${1%%/*}" ;;
  esac
}

broken=0
checked=0
for folder in $(printf '%s\n' "${!allowed[@]}" | sed 's#/.*##' | sort -u); do
  [ -d "$folder" ] || continue
  while IFS=: read -r file line include; do
    room_of "$include"
    target="$room"
    room_of "$file"
    checked=$((checked + 1))
    if [ "$target" = "$room" ]; then continue; fi
    if [[ " ${allowed[$room]} " != *" $target "* ]]; then
      echo "check-includes: $file:$line includes $include ($room may include: ${allowed[$room]:-only itself})" >&2
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
