#!/usr/bin/env bash
# The obstacle density curve (README, "Obstacles that matter"): runs
# scenarios/suites/obstacle_density.yaml (reach, pickup and putdown on every robot in the
# kitchen with 0, 4, 8 and 12 obstacles around the cup) and prints its table: per program and
# density, successes per robot and in all, and the medians over all the group's trials of the
# collision checks (an exact count) and of the planning time (wall seconds, load-dependent).
# Assumes a build (scripts/setup.sh). Long: not part of ctest or .ci/run.
#
#   scripts/obstacle_density.sh [--trials N] [--out DIR]   run (N layouts per group, default the
#                                                          suite's 20) and print the table
#   scripts/obstacle_density.sh --table DIR                print the table of a finished run
#
# A run that was stopped continues where it stopped (taskmatrix run --resume); a larger
# --trials adds layouts to a finished run.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
suite="$root/scenarios/suites/obstacle_density.yaml"
out="$root/results/runs/obstacle_density"
trials=()
table_only=0
value() {  # value OPTION [VALUE...]: the option's value, or exit 2
  [ $# -ge 2 ] && [ -n "$2" ] || { echo "obstacle_density.sh: $1 needs a value" >&2; exit 2; }
  printf '%s\n' "$2"
}
while [ $# -gt 0 ]; do
  case "$1" in
    --trials) trials=(--trials "$(value "$@")"); shift ;;
    --out) out="$(realpath -m -- "$(value "$@")")"; shift ;;
    --table) out="$(realpath -m -- "$(value "$@")")"; table_only=1; shift ;;
    *) echo "obstacle_density.sh: unknown option '$1' (see the comment at the top)" >&2; exit 2 ;;
  esac
  shift
done
cd "$root"
command -v jq > /dev/null || { echo "obstacle_density.sh: jq is not installed (scripts/setup.sh)" >&2; exit 2; }

if [ "$table_only" = 0 ]; then
  build="${TASKMATRIX_BUILD_DIR:-build}"
  taskmatrix="$build/bin/taskmatrix"
  [ -x "$taskmatrix" ] || { echo "obstacle_density.sh: $taskmatrix: not built (run scripts/setup.sh)" >&2; exit 2; }
  resume=()
  [ -s "$out/trials.jsonl" ] && resume=(--resume)
  start=$(date +%s)
  # Status 1 means some trials failed, which is what the curve measures.
  "$taskmatrix" run "$suite" --out "$out" --jobs "${TASKMATRIX_JOBS:-2}" --progress off \
    --record-hz 0 "${trials[@]}" "${resume[@]}" > /dev/null || [ $? -eq 1 ]
  echo "obstacle_density.sh: run in $out, $(( $(date +%s) - start )) s of wall time"
fi
[ -s "$out/trials.jsonl" ] || { echo "obstacle_density.sh: no $out/trials.jsonl" >&2; exit 2; }

# Scenario names are <program>_n<obstacles> (scenarios/density/).
jq -r -s '
  def median: sort | if length == 0 then null
                     elif length % 2 == 1 then .[length / 2 | floor]
                     else (.[length / 2 - 1] + .[length / 2]) / 2 end;
  def ok(r): map(select(.robot == r)) | "\(map(select(.success)) | length)/\(length)";
  (map(.layout_seed) | unique | length) as $layouts
  | "\(length) trials, \($layouts) layouts per group",
    "",
    "| program | obstacles | tallbot | minibot | atlas | all | median collision checks | median planning time |",
    "|---|---|---|---|---|---|---|---|",
    (group_by(.scenario)
     | map({program: .[0].program, n: (.[0].scenario | sub(".*_n"; "") | tonumber), t: .})
     | sort_by(({reach: 0, pickup: 1, putdown: 2}[.program] // 3), .n)[]
     | "| \(.program) | \(.n) | \(.t | ok("tallbot")) | \(.t | ok("minibot")) | \(.t | ok("atlas")) | \(.t | map(select(.success)) | length)/\(.t | length) | \(.t | map(.collision_checks) | median) | \(.t | map(.planning_time_s) | median * 1000 | round) ms |")
' "$out/trials.jsonl"
