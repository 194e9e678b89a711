# Sourced by the side-by-side time benchmarks of bench/realdata (mvs_time.sh,
# refine_time.sh, texture_time.sh): their shared argument parsing and the
# alternating runs.
#
# The sourcing script sets `usage` (a function) and `stage` (the executable's
# name, e.g. hos-mvs), parses its own leading arguments and then calls
#   parse_side_by_side_options "$@"  -> sets repeat (default 2) and sets (--set ...)
#   check_builds OLD_BIN NEW_BIN     -> sets old_bin and new_bin (absolute)
#   run_alternately ROWS run_one     -> runs `run_one BIN EXTRA...` repeat times
#                                       per build, old first, and appends
#                                       "build run wall user sys load" and
#                                       whatever run_one printed to ROWS
#   medians_row NAME ROWS CELLS      -> prints the table row of ROWS' medians
#   parse_run_file_arguments OLD_BIN NEW_BIN WORK[:WORK...] LABEL OPTIONS...
#                                    -> the above for the scripts that time a
#                                       stage on a kept run's file; sets
#                                       works and label
#   time_on_run_files LABEL FILE run_one WORK...
#                                    -> the table of every WORK: run_one on
#                                       WORK/runs/LABEL/FILE ($input) with
#                                       the WORK's training SfM ($undistorted)
# run_one runs the stage under `timed` (below) and may print extra columns.

parse_side_by_side_options() {
  repeat=2 sets=()
  while [ $# -gt 0 ]; do
    case "$1" in
      --repeat) repeat="$2"; shift 2 ;;
      --set) sets+=(--set "$2"); shift 2 ;;
      *) usage ;;
    esac
  done
}

check_builds() {
  old_bin="$(cd "$1" && pwd)" new_bin="$(cd "$2" && pwd)"
  for b in "$old_bin" "$new_bin"; do [ -x "$b/$stage" ] || { echo "$b/$stage: missing" >&2; exit 3; }; done
  tmp="$(mktemp -d)"
  trap 'rm -rf "$tmp"' EXIT
}

# timed WHAT COMMAND...: runs COMMAND, its wall, user and sys seconds into
# $tmp/time; on failure prints its stderr and exits 4 naming WHAT.
timed() {
  local what="$1"
  shift
  /usr/bin/time -f "%e %U %S" -o "$tmp/time" "$@" >/dev/null 2>"$tmp/stderr" ||
    { cat "$tmp/stderr" >&2; echo "$1 failed on $what (log: above)" >&2; exit 4; }
}

run_alternately() {
  local rows="$1" run_one="$2" r build bin extra extra_columns
  : > "$rows"
  for ((r = 1; r <= repeat; ++r)); do
    for build in old new; do
      if [ "$build" = old ]; then bin="$old_bin" extra=(); else bin="$new_bin" extra=("${sets[@]}"); fi
      extra_columns=$("$run_one" "$bin" "${extra[@]}") || exit 4
      read -r wall user sys < "$tmp/time"
      echo "$build $r $wall $user $sys $(cut -d' ' -f1 /proc/loadavg) $extra_columns" >> "$rows"
    done
  done
}

# medians_row NAME ROWS CELLS: the row "| NAME | new / old (medians) | | WALL
# | CPU |" and CELLS empty cells, WALL and CPU the ratios new / old of the
# medians over ROWS' runs of the wall and CPU (user + sys) seconds.
medians_row() {
  python3 - "$@" <<'PY'
import statistics, sys
name, rows_path, cells = sys.argv[1], sys.argv[2], int(sys.argv[3])
runs = {"old": [], "new": []}
for line in open(rows_path):
    build, _, wall, user, sys_ = line.split()[:5]
    runs[build].append((float(wall), float(user) + float(sys_)))
wall, cpu = (statistics.median(t[k] for t in runs["new"]) / statistics.median(t[k] for t in runs["old"]) for k in (0, 1))
print(f"| {name} | new / old (medians) | | {wall:.2f}x | {cpu:.2f}x |" + " |" * cells)
PY
}

parse_run_file_arguments() {
  [ $# -ge 4 ] || usage
  IFS=: read -r -a works <<<"$3"
  label="$4"
  check_builds "$1" "$2"
  shift 4
  parse_side_by_side_options "$@"
}

# time_on_run_files LABEL FILE run_one WORK...: per WORK, checks its training
# SfM and the kept run's FILE, runs run_one alternately with $undistorted and
# $input set, and prints its runs' rows and their medians.
time_on_run_files() {
  local label="$1" file="$2" run_one="$3" work
  shift 3
  echo "| WORK | build | run | wall s | CPU s | load avg |"
  echo "|---|---|---|---|---|---|"
  for work in "$@"; do
    undistorted="$work/sfm-train/sfm/undistorted" input="$work/runs/$label/$file"
    [ -d "$undistorted/sparse" ] || { echo "$undistorted/sparse: missing (make WORK with holdout.sh)" >&2; exit 3; }
    [ -f "$input" ] || { echo "$input: missing (make run $label with holdout.sh --keep)" >&2; exit 3; }
    run_alternately "$tmp/rows" "$run_one"
    awk -v name="$(basename "$work")" \
      '{ printf "| %s | %s | %s | %.1f | %.1f | %s |\n", name, $1, $2, $3, $4 + $5, $6 }' "$tmp/rows"
    medians_row "$(basename "$work")" "$tmp/rows" 1
  done
}
