#!/usr/bin/env bash
# Sharded runs on a real Slurm cluster, end to end: starts a single-node cluster
# (scripts/slurm/local_cluster.sh), runs tests/slurm/cluster_suite.yaml locally with --jobs 2,
# then through scripts/slurm/submit.sh as an array of 3 shards plus the merge job, and checks
#   1. the merged trials equal the local run's trial for trial (ids, successes, statuses,
#      failure reasons, work counts), each shard ran as its array task, `compare` accepts it;
#   2. submitting the same command again resumes every shard (no trial runs again);
#   3. a shard that fails (its directory cannot be written) cancels the merge job, and
#      `submit.sh --wait` exits non-zero without a merged directory.
# It stops the daemons it started (by their recorded PIDs) whatever happens. Root only.
# Usage: tests/slurm/cluster_test.sh [TASKMATRIX_BINARY]
set -euo pipefail
repo=$(cd "$(dirname "$0")/../.." && pwd)
TASKMATRIX_BIN=$(realpath "${1:-$repo/build/bin/taskmatrix}")
export TASKMATRIX_BIN
# A Slurm array task running this test must not shard the local run.
unset SLURM_ARRAY_TASK_ID SLURM_ARRAY_TASK_COUNT SLURM_ARRAY_TASK_MIN SLURM_ARRAY_TASK_MAX \
  SLURM_ARRAY_TASK_STEP SLURM_ARRAY_JOB_ID
suite=$repo/tests/slurm/cluster_suite.yaml
work=$(mktemp -d /tmp/taskmatrix_slurm_XXXXXX)
chmod 0755 "$work"  # munged needs every directory above its socket searchable

failed=0
fail() {
  echo "FAIL: $*" >&2
  failed=$((failed + 1))
}
# Prints a check's result line only when no check failed since `mark`.
mark() { failed_before=$failed; }
passed() { [ "$failed" -ne "$failed_before" ] || echo "cluster_test: $*"; }
finish() {
  local rc=$?
  "$repo/scripts/slurm/local_cluster.sh" stop "$work/cluster" || rc=1
  [ "$failed" -eq 0 ] || rc=1
  if [ "$rc" -eq 0 ]; then
    rm -rf "$work"
    echo "cluster_test: passed"
  else
    echo "cluster_test: failed (rc $rc); files kept in $work" >&2
    tail -n 5 "$work"/*/logs/*.out "$work"/cluster/log/*.log 2>/dev/null >&2 || true
  fi
  exit "$rc"
}
trap finish EXIT
trap 'exit 130' INT TERM

t0=$(date +%s%N)
cluster_env=$("$repo/scripts/slurm/local_cluster.sh" start "$work/cluster")
eval "$cluster_env"
echo "cluster_test: cluster up in $((($(date +%s%N) - t0) / 1000000)) ms"

"$TASKMATRIX_BIN" run "$suite" --out "$work/local" --jobs 2 --progress off >/dev/null 2>&1

# 1. Three shards and the merge, through Slurm.
# Every wait is bounded, so that the daemons are stopped by this script, not left behind by a
# test runner's kill.
submit() { timeout 240 "$repo/scripts/slurm/submit.sh" "$@"; }
mark
submit "$suite" --shards 3 --out "$work/run" --wait >"$work/submit.out"
cat "$work/submit.out"
array=$(sed -n 's/^shards: job \([0-9]*\),.*/\1/p' "$work/submit.out")
[ -n "$array" ] || fail "submit.sh printed no array job id"
merged=$work/run/merged
key='[.trial_id, .success, .status, .failure_reason, .plan_calls, .planner_runs,
      .collision_checks, .ik_calls]'
jq -c "$key" "$work/local/trials.jsonl" | sort >"$work/local.keys"
jq -c "$key" "$merged/trials.jsonl" | sort >"$work/merged.keys"
[ "$(wc -l <"$work/local.keys")" -eq 12 ] || fail "the local run has $(wc -l <"$work/local.keys") trials, not 12"
if ! diff "$work/local.keys" "$work/merged.keys" >&2; then
  fail "the merged trials differ from the local run's (< local, > merged)"
  # Path simplification is bounded by the clock: a bound hit under load changes paths and counts.
  echo "longest path simplification per trial (s), local then merged:" >&2
  for f in "$work/local/trials.jsonl" "$merged/trials.jsonl"; do
    jq -r '"  \(.trial_id) \([.plans[]?.simplification_time_s // 0] | max)"' "$f" | sort >&2
  done
  uptime >&2
fi
prov=$merged/provenance.json
[ "$(jq '.shards | length' "$prov")" -eq 3 ] || fail "provenance lists $(jq '.shards | length' "$prov") shards"
[ "$(jq --arg a "$array" '[.shards[] | select(.from == "SLURM_ARRAY_TASK_ID" and
      .slurm.array_job_id == $a and .trials_merged == 4)] | length' "$prov")" -eq 3 ] ||
  fail "not every shard ran as a task of array job $array with 4 trials"
[ "$(jq '.trials.missing + .trials.duplicated' "$prov")" -eq 0 ] || fail "trials missing or duplicated"
"$TASKMATRIX_BIN" compare "$work/local" "$merged" --fail-on-unpaired --max-new-failures 0 \
  >"$work/compare.out" || fail "compare does not accept the merged directory"
grep -q "^12 trials paired" "$work/compare.out" || fail "compare did not pair 12 trials"
passed "12 merged trials equal the local --jobs 2 run"

# 2. The same command again: every shard resumes, nothing runs twice.
mark
submit "$suite" --shards 3 --out "$work/run" --wait >/dev/null
for i in 0 1 2; do
  ran=$(jq '.trials.ran_now' "$work/run/shard-$i/provenance.json")
  [ "$ran" -eq 0 ] || fail "resubmitted shard $i ran $ran trials again"
done
jq -c "$key" "$merged/trials.jsonl" | sort | diff "$work/merged.keys" - >&2 ||
  fail "the merge after resubmitting differs from the first"
passed "resubmitting resumed every shard"

# 3. A shard that fails: the merge job is cancelled and --wait exits non-zero.
mark
mkdir -p "$work/broken"
echo "not a directory" >"$work/broken/shard-1"
set +e
submit "$suite" --shards 3 --out "$work/broken" --wait -- --trials 1 >"$work/broken.out" \
  2>"$work/broken.err"
rc=$?
set -e
cat "$work/broken.out" "$work/broken.err"
[ "$rc" -ne 0 ] || fail "submit.sh --wait exited 0 although shard 1 failed"
merge_job=$(sed -n 's/^merge: job \([0-9]*\),.*/\1/p' "$work/broken.out")
state=$(scontrol -o show job "$merge_job" | grep -o 'JobState=[A-Z_]*' | cut -d= -f2)
[ "$state" = CANCELLED ] || fail "the merge job after a failed shard is $state, not CANCELLED"
[ ! -e "$work/broken/merged" ] || fail "a merged directory exists although a shard failed"
grep -q "shard 1: FAILED" "$work/broken.err" || fail "submit.sh did not name the failed shard"
passed "a failed shard cancelled the merge (submit.sh exit $rc)"
