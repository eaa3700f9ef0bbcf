#!/usr/bin/env bash
# Runs taskmatrix_bench (3 repetitions, medians) and compares it with the committed baseline
# results/baselines/bench.json through `taskmatrix bench-compare`: exact work counters must
# match, times may move within the noise tolerance. Assumes scripts/setup.sh has been run.
#
#   scripts/bench.sh [--record] [--include-runner] [--out FILE] [--fail-on-regression]
#                    [--time-tolerance F]
#
#   --record              write the run to results/baselines/bench.json instead of comparing
#   --include-runner      also run BM_RunSuite (the scenario runner, about 60 s more)
#   --out FILE            where the new run's JSON goes (default results/bench/latest.json;
#                         relative to where you are, like every path you give)
#   --fail-on-regression, --time-tolerance F   passed to bench-compare
#
# Environment: TASKMATRIX_BUILD_DIR (default build), TASKMATRIX_JOBS (build jobs, default 2),
# TASKMATRIX_BENCH_MIN_TIME (seconds per benchmark and repetition, default 0.5).
set -euo pipefail
caller=$(pwd)
cd "$(dirname "$0")/.."

build=${TASKMATRIX_BUILD_DIR:-build}
baseline=results/baselines/bench.json
out=results/bench/latest.json
record=0
filter=-BM_RunSuite
compare_args=()
while (($#)); do
  case "$1" in
    --record) record=1 ;;
    --include-runner) filter=. ;;
    --out)
      [ $# -ge 2 ] && [ -n "$2" ] || { echo "bench.sh: --out needs a file" >&2; exit 2; }
      out=$(cd "$caller" && realpath -m -- "$2")
      shift
      ;;
    --fail-on-regression) compare_args+=(--fail-on-regression) ;;
    --time-tolerance)
      compare_args+=(--time-tolerance "${2:?--time-tolerance needs a number}")
      shift
      ;;
    -h | --help)
      awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "$0"
      exit 0
      ;;
    *)
      echo "bench.sh: unknown option '$1' (see --help)" >&2
      exit 2
      ;;
  esac
  shift
done
((record)) && out=$baseline

cmake --build "$build" -j"${TASKMATRIX_JOBS:-2}" --target taskmatrix taskmatrix_bench
mkdir -p "$(dirname "$out")"
"$build/bin/taskmatrix_bench" --benchmark_filter="$filter" \
  --benchmark_min_time="${TASKMATRIX_BENCH_MIN_TIME:-0.5}" \
  --benchmark_repetitions=3 --benchmark_report_aggregates_only=true \
  --benchmark_out="$out" --benchmark_out_format=json

if ((record)); then
  echo "bench.sh: baseline written to $out"
  exit 0
fi
"$build/bin/taskmatrix" bench-compare "$baseline" "$out" "${compare_args[@]}"
