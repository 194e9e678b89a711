#!/usr/bin/env bash
# Cost of the reliability checks on a normal run: hos-recon of two builds on
# the same oriented points (the Stanford bunny's scans, grid 256), alternating,
# REPEAT runs each. Prints the median CPU time (user + sys: steadier than wall
# time on a shared machine) and wall time of each build, their ratio, and the
# faces of each mesh (the unit frame changes rounding only).
#   bench/reliability/overhead.sh OLD_BIN_DIR NEW_BIN_DIR DATA_DIR [REPEAT]
# DATA_DIR holds stanford_bunny/data/bun.conf (e.g. ../shared/data).
set -euo pipefail
old="$1"; new="$2"; data="$3"; repeat="${4:-5}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
"$new/hos-recon-bench" scans --conf "$data/stanford_bunny/data/bun.conf" --output "$work/bunny.ply" > /dev/null
run() {  # prints "cpu wall faces"
  /usr/bin/time -f "%U %S %e" -o "$work/time.txt" "$1/hos-recon" --input "$work/bunny.ply" \
    --output "$work/mesh.ply" --resolution 256 --progress none > "$work/log.txt" 2>&1
  read -r user sys wall < "$work/time.txt"
  faces=$(grep -o '[0-9]* faces' "$work/log.txt" | tail -1 | cut -d' ' -f1)
  echo "$(awk -v u="$user" -v s="$sys" 'BEGIN {print u + s}') $wall $faces"
}
: > "$work/old.txt"; : > "$work/new.txt"
for i in $(seq "$repeat"); do
  run "$old" >> "$work/old.txt"
  run "$new" >> "$work/new.txt"
done
median() { sort -n | awk '{v[NR] = $1} END {print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2}'; }
for b in old new; do
  cpu=$(cut -d' ' -f1 "$work/$b.txt" | median); wall=$(cut -d' ' -f2 "$work/$b.txt" | median)
  faces=$(cut -d' ' -f3 "$work/$b.txt" | sort -u | tr '\n' ' ')
  echo "$b: cpu $cpu s, wall $wall s, faces $faces(runs: $(cut -d' ' -f1 "$work/$b.txt" | tr '\n' ' '))"
  eval "${b}_cpu=$cpu; ${b}_wall=$wall"
done
awk -v nc="$new_cpu" -v oc="$old_cpu" -v nw="$new_wall" -v ow="$old_wall" \
  'BEGIN {printf "new/old: cpu %.3f, wall %.3f\n", nc / oc, nw / ow}'
