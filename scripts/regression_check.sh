#!/usr/bin/env bash
# The regression check, for CI: runs scenarios/suites/regression.yaml and compares it, trial by
# trial, with the committed baseline results/baselines/regression/ (taskmatrix compare
# --fail-on-regression). Assumes a build (scripts/setup.sh).
#
#   scripts/regression_check.sh [--fast] [--out DIR]   check; exit 0 passed, 1 regression,
#                                                      2 bad input or a broken run
#   scripts/regression_check.sh --record               run the full suite, store it as the baseline
#   --suite FILE --baseline DIR                        your own suite and baseline (defaults:
#                                                      scenarios/suites/regression.yaml and
#                                                      results/baselines/regression)
#
# --fast runs one layout per group (24 of the 48 trials); they pair with the baseline's first.
# Thresholds: taskmatrix compare's defaults (a significant success drop of 5 points, collision
# checks above x1.25), no trial that succeeded in the baseline may now fail, no trial may have
# been decided by a clock safety net (--fail-on-nonreproducible), every trial needs a partner
# (--fast: every new one), and planning time fails only when its 95% interval lies above x2
# (times depend on the machine and its load; the baseline's are this project's 2-core CI
# machine's). Work counts and planned paths must equal the baseline's exactly (--exact-work):
# they depend on the trial's id alone, so any difference is a change of behaviour (record a new
# baseline on purpose when it is intended) or a lost guarantee (README, Reliability).
# Other thresholds: pass taskmatrix compare options after --; they replace these.
# The report (compare.md, report.html with pictures of failed trials) is in DIR/compare.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
suite="$root/scenarios/suites/regression.yaml"
baseline="$root/results/baselines/regression"
out="$root/results/runs/regression-check"
fast=0
record=0
extra=()
value() {  # value OPTION [VALUE...]: the option's value as an absolute path, or exit 2
  [ $# -ge 2 ] && [ -n "$2" ] || { echo "regression_check.sh: $1 needs a value" >&2; exit 2; }
  realpath -m -- "$2"
}
while [ $# -gt 0 ]; do
  case "$1" in
    --fast) fast=1 ;;
    --record) record=1 ;;
    --out) out="$(value "$@")"; shift ;;
    --suite) suite="$(value "$@")"; shift ;;
    --baseline) baseline="$(value "$@")"; shift ;;
    --) shift; extra=("$@"); break ;;
    *) echo "regression_check.sh: unknown option '$1' (see the comment at the top)" >&2; exit 2 ;;
  esac
  shift
done
cd "$root"
build="${TASKMATRIX_BUILD_DIR:-build}"  # relative to the repository, as in the other scripts
taskmatrix="$build/bin/taskmatrix"
[ -x "$taskmatrix" ] || { echo "regression_check.sh: $taskmatrix: not built (run scripts/setup.sh)" >&2; exit 2; }
jobs="${TASKMATRIX_JOBS:-2}"

if [ "$record" = 1 ]; then
  "$taskmatrix" run "$suite" --out "$out" --jobs "$jobs" --progress off > /dev/null
  mkdir -p "$baseline"
  for f in trials.jsonl summary.json summary.md provenance.json; do cp "$out/$f" "$baseline/$f"; done
  echo "regression_check.sh: baseline recorded in $baseline ($(wc -l < "$baseline/trials.jsonl") trials)"
  exit 0
fi

run_args=()
pairing=(--fail-on-unpaired)
if [ "$fast" = 1 ]; then
  run_args=(--trials 1)
  pairing+=(--subset)
fi
"$taskmatrix" run "$suite" --out "$out" --jobs "$jobs" --progress off "${run_args[@]}" > /dev/null
# Later options win, so "-- --max-time-ratio 3" replaces the default below.
exec "$taskmatrix" compare "$baseline" "$out" --report "$out/compare" --fail-on-regression \
  --max-new-failures 0 --max-time-ratio 2 --fail-on-nonreproducible --exact-work \
  "${pairing[@]}" "${extra[@]}"
