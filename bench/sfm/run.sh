#!/usr/bin/env bash
# hos-sfm side by side: an old build against a new one on the same photo sets,
# in one run, alternating old/new (the order swaps every repetition). Per run:
# wall time, CPU time (user + sys of hos-sfm and COLMAP: steadier than wall time
# when other jobs share the cores), peak memory (largest resident set of
# hos-sfm or one COLMAP step), photos registered, and the camera accuracy
# against the true cameras after a similarity alignment (examples/
# sfm_pose_accuracy: centre RMSE, median and maximum as % of the diagonal of the
# true centres' bounding box; rotation error median and maximum in degrees).
#
#   bench/sfm/run.sh --old OLD_BIN --data DATA --out OUT [--new NEW_BIN] [--sets "..."] [--repeat N]
#                    [--timeout S] [--sides "old new"] [--new-set KEY=VALUE]...
#   bench/sfm/run.sh --summary OUT
#
# OLD_BIN / NEW_BIN: folders holding hos-sfm (NEW_BIN defaults to build/bin,
# which also provides hos-synth and sfm_pose_accuracy). DATA: the data folder
# (../shared/data), holding strecha_fountain_p11/ and strecha_herz_jesus_p8/.
# Sets: fountain, herz (real photos, 3072x2048), synth36 (hos-synth, 36 views
# 800x600), synth100 (hos-synth, 100 views 640x480). Runs append to
# OUT/runs.tsv, so a long benchmark can be run set by set; --summary prints
# the markdown table (medians; new/old ratios of the medians). --timeout stops
# a run after S seconds (SIGINT: hos-sfm stops COLMAP cleanly); its row keeps
# the time and CPU spent so far with exit code 124, a lower bound. --sides
# runs only one side (e.g. two processes, one per side, at the same time).
# --new-set passes --set KEY=VALUE to the new side's hos-sfm (an option's
# effect against the old side).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
new_bin="${HOS_BUILD_DIR:-$root/build}/bin"
old_bin="" data="" out="" summary="" repeat=1 timeout=0 only_sides=""
new_sets=()
sets="fountain herz synth36 synth100"
usage() { echo "usage: $0 --old OLD_BIN --data DATA --out OUT [--new NEW_BIN] [--sets \"fountain herz synth36 synth100\"] [--repeat N] [--timeout S] [--sides \"old new\"] [--new-set KEY=VALUE]... | --summary OUT" >&2; exit 2; }
while [ $# -gt 0 ]; do
  case "$1" in
    --old) old_bin="$2"; shift 2 ;;
    --new) new_bin="$2"; shift 2 ;;
    --data) data="$2"; shift 2 ;;
    --out) out="$2"; shift 2 ;;
    --sets) sets="$2"; shift 2 ;;
    --repeat) repeat="$2"; shift 2 ;;
    --timeout) timeout="$2"; shift 2 ;;
    --sides) only_sides="$2"; shift 2 ;;
    --new-set) new_sets+=(--set "$2"); shift 2 ;;
    --summary) summary="$2"; shift 2 ;;
    *) usage ;;
  esac
done

summarise() {
  python3 - "$1/runs.tsv" <<'PY'
import csv, statistics, sys
rows = list(csv.DictReader(open(sys.argv[1]), delimiter="\t"))
order = ["fountain", "herz", "synth36", "synth100"]
sets = sorted({r["set"] for r in rows}, key=lambda s: order.index(s) if s in order else 99)
med = lambda xs: statistics.median(xs) if xs else float("nan")
def col(rs, k): return [float(r[k]) for r in rs if r[k] not in ("", "nan")]
print("| set | side | runs | sfm wall s | sfm CPU s | peak MB | registered | centre RMSE % | centre median / max % | rotation median / max deg | load |")
print("|---|---|---|---|---|---|---|---|---|---|---|")
ratios = []
for s in sets:
    meds = {}
    for side in ("old", "new"):
        rs = [r for r in rows if r["set"] == s and r["side"] == side]
        if not rs: continue
        wall, cpu, peak = col(rs, "wall_s"), col(rs, "cpu_s"), col(rs, "peak_mb")
        meds[side] = (med(wall), med(cpu))
        rng = lambda xs, f: f.format(med(xs)) + (" (" + ", ".join(f.format(x) for x in xs) + ")" if len(xs) > 1 else "")
        reg = ", ".join(sorted({f'{r["registered"]}/{r["given"]}' if r.get("exit", "0") in ("0", None) else
                                f'stopped (exit {r["exit"]})' for r in rs}))
        rmse, cmed, cmax = col(rs, "centre_rmse_pct"), col(rs, "centre_median_pct"), col(rs, "centre_max_pct")
        rmed, rmax = col(rs, "rot_median_deg"), col(rs, "rot_max_deg")
        print(f"| {s} | {side} | {len(rs)} | {rng(wall, '{:.0f}')} | {rng(cpu, '{:.0f}')} | {med(peak):.0f} | {reg} | "
              f"{rng(rmse, '{:.3f}')} | {med(cmed):.3f} / {med(cmax):.3f} | {med(rmed):.2f} / {med(rmax):.2f} | "
              f"{', '.join(r['load'] for r in rs)} |")
    if len(meds) == 2:
        stopped = any(r.get("exit", "0") not in ("0", None) for r in rows if r["set"] == s and r["side"] == "old")
        ratios.append((s + (" (old stopped: ratio is an upper bound)" if stopped else ""),
                       meds["new"][0] / meds["old"][0], meds["new"][1] / meds["old"][1]))
print()
print("| set | new/old wall (medians) | new/old CPU (medians) |")
print("|---|---|---|")
for s, w, c in ratios:
    print(f"| {s} | {w:.2f} | {c:.2f} |")
PY
}

if [ -n "$summary" ]; then summarise "$summary"; exit 0; fi
[ -n "$old_bin" ] && [ -n "$out" ] || usage
for tool in "$old_bin/hos-sfm" "$new_bin/hos-sfm" "$new_bin/hos-synth" "$new_bin/sfm_pose_accuracy"; do
  [ -x "$tool" ] || { echo "$tool is missing (build it first)" >&2; exit 2; }
done
mkdir -p "$out/ws"
out="$(cd "$out" && pwd)"
tsv="$out/runs.tsv"
[ -f "$tsv" ] || printf 'set\tside\trep\twall_s\tcpu_s\tpeak_mb\tregistered\tgiven\tcentre_rmse_pct\tcentre_median_pct\tcentre_max_pct\trot_median_deg\trot_max_deg\tload\texit\n' > "$tsv"

# prepare_set NAME: sets photos, truth_format, truth.
prepare_set() {
  case "$1" in
    fountain|herz)
      local dir="$data/strecha_fountain_p11"
      [ "$1" = herz ] && dir="$data/strecha_herz_jesus_p8"
      [ -d "$dir/images" ] || { echo "missing $dir (pass --data)" >&2; exit 3; }
      # Only the photos (the folder also holds K.txt).
      photos="$out/sets/$1"
      mkdir -p "$photos"
      for f in "$dir"/images/*.jpg; do ln -sf "$f" "$photos/"; done
      truth_format=strecha truth="$dir/gt_dense_cameras" ;;
    synth36|synth100)
      local scene="$out/sets/$1" views=36 width=800 height=600
      [ "$1" = synth100 ] && views=100 width=640 height=480
      [ -f "$scene/scene.json" ] || "$new_bin/hos-synth" --output "$scene" --views "$views" --width "$width" \
        --height "$height" --seed 1 --progress none
      photos="$scene/images" truth_format=colmap truth="$scene/sparse" ;;
    *) echo "unknown set $1" >&2; exit 2 ;;
  esac
}

# run_side SET SIDE BIN REP: one hos-sfm run, one row of runs.tsv.
run_side() {
  local set="$1" side="$2" bin="$3" rep="$4" ws="$out/ws/$1-$2-$4"
  rm -rf "$ws"
  local load
  load=$(cut -d' ' -f1 /proc/loadavg)
  local code=0
  local limit=() sets=()
  [ "$timeout" != 0 ] && limit=(timeout -s INT "$timeout")
  [ "$side" = new ] && sets=("${new_sets[@]}")
  /usr/bin/time -f "%e %U %S %M" -o "$ws.time" "${limit[@]}" "$bin/hos-sfm" --images "$photos" --workspace "$ws" \
    --progress none "${sets[@]}" > "$ws.out" 2>&1 || code=$?
  # GNU time notes a non-zero exit on a line of its own before the figures.
  tail -1 "$ws.time" > "$ws.time1" && mv "$ws.time1" "$ws.time"
  read -r wall user sys kb < "$ws.time"
  local reg=0 given=0 acc=""
  if [ "$code" = 0 ]; then
    reg=$(python3 -c "import json,sys; r=json.load(open(sys.argv[1])); print(r['images_registered'], r['images_given'])" "$ws/sfm/report.json")
    given=${reg#* } reg=${reg% *}
    acc=$("$new_bin/sfm_pose_accuracy" "$ws/sfm/undistorted/sparse" "$truth_format" "$truth" | tail -4)
    cp "$ws/sfm/report.json" "$ws.report.json"
    cp -r "$ws/sfm/undistorted/sparse" "$ws.sparse"
  fi
  cp "$ws/logs/sfm.log" "$ws.log" 2>/dev/null || true
  rm -rf "$ws"  # the photos and undistorted images are large; the figures are kept
  python3 - "$set" "$side" "$rep" "$wall" "$user" "$sys" "$kb" "$reg" "$given" "$load" "$acc" "$code" >> "$tsv" <<'PY'
import re, sys
s, side, rep, wall, user, sys_s, kb, reg, given, load, acc, code = sys.argv[1:]
num = lambda pat: (re.search(pat, acc).groups() if re.search(pat, acc) else ("nan",) * pat.count("("))
rmse, = num(r"centre RMSE \(%[^)]*\): ([\d.e+-]+)")
cmed, cmax = num(r"centre error \(%[^)]*\): median ([\d.e+-]+), max ([\d.e+-]+)")
rmed, rmax = num(r"rotation error \(deg\): median ([\d.e+-]+), max ([\d.e+-]+)")
print("\t".join([s, side, rep, wall, f"{float(user) + float(sys_s):.1f}", f"{int(kb) / 1024:.0f}", reg, given,
                 rmse, cmed, cmax, rmed, rmax, load, code]))
PY
  echo "$set $side rep $rep: exit $code, wall $wall s, registered $reg/$given" >&2
}

for set in $sets; do
  prepare_set "$set"
  done_before=$(awk -F'\t' -v s="$set" -v side="${only_sides%% *}" '$1 == s && $2 == (side ? side : "old")' "$tsv" | wc -l)
  for rep in $(seq $((done_before + 1)) $((done_before + repeat))); do
    if [ $((rep % 2)) = 1 ]; then sides="old new"; else sides="new old"; fi
    [ -n "$only_sides" ] && sides="$only_sides"
    for side in $sides; do
      bin="$new_bin"
      [ "$side" = old ] && bin="$old_bin"
      run_side "$set" "$side" "$bin" "$rep"
    done
  done
done
summarise "$out"
