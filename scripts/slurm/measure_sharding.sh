#!/usr/bin/env bash
# What sharding costs, measured on this machine through a real local Slurm cluster
# (scripts/slurm/local_cluster.sh): the suite once locally with --jobs 2, then through
# scripts/slurm/submit.sh with each shard count, and per count:
#   end-to-end    submit.sh --wait, from submission until the merge job ended
#   shard fixed   a shard's wall time minus its trials' wall time / its jobs: start-up (suite,
#                 models, layouts), forks, result files (mean and largest over the shards)
#   merge         `taskmatrix merge` of the same shard directories, timed alone
#   Slurm delays  from the cluster's job completion log (1 s resolution): submission to the
#                 first shard's start, and the last shard's end to the merge job's start
#   identical     merged trials equal to the local run's (ids, success, status, work counts)
#   load          /proc/loadavg's 1-minute load before and after (2 cores: 2 is full)
# Prints a Markdown table. Root only; takes several minutes for the default suite.
# Usage: scripts/slurm/measure_sharding.sh [SUITE] [SHARD COUNTS...]   (default: default 1 2 4)
set -euo pipefail
repo=$(cd "$(dirname "$0")/../.." && pwd)
suite=$(realpath "${1:-$repo/scenarios/suites/default.yaml}")
shift || true
counts=("$@")
[ ${#counts[@]} -gt 0 ] || counts=(1 2 4)
work=$(mktemp -d /tmp/taskmatrix_sharding_XXXXXX)
chmod 0755 "$work"
# A copy, so that a rebuild while this runs cannot give the shards two builds.
cp "$repo/build/bin/taskmatrix" "$work/taskmatrix"
bin=$work/taskmatrix
export TASKMATRIX_BIN=$bin
trap '"$repo/scripts/slurm/local_cluster.sh" stop "$work/cluster"; rm -rf "$work"' EXIT
ms() { echo $(($(date +%s%N) / 1000000)); }
load() { cut -d' ' -f1 /proc/loadavg; }
key='[.trial_id, .success, .status, .failure_reason, .plan_calls, .planner_runs,
      .collision_checks, .ik_calls]'

t0=$(ms)
cluster_env=$("$repo/scripts/slurm/local_cluster.sh" start "$work/cluster")
eval "$cluster_env"
echo "cluster started in $(($(ms) - t0)) ms"

l0=$(load)
t0=$(ms)
"$bin" run "$suite" --out "$work/local" --jobs 2 --progress off >/dev/null 2>&1
local_s=$(echo "$(($(ms) - t0))" | awk '{printf "%.1f", $1 / 1000}')
jq -c "$key" "$work/local/trials.jsonl" | sort >"$work/local.keys"
trials=$(wc -l <"$work/local.keys")
mean=$(jq -s 'map(.wall_time_s) | add / length' "$work/local/trials.jsonl")
echo "local --jobs 2: $trials trials in $local_s s, mean trial wall time $(printf %.2f "$mean") s" \
  "(load $l0 -> $(load))"

echo
# Seconds between two of the job completion log's times (YYYY-MM-DDTHH:MM:SS).
jobcomp=$work/cluster/log/jobcomp.txt
times() { grep -E "$1" "$jobcomp" | grep -o "\b$2=[0-9T:-]*" | cut -d= -f2 | xargs -I{} date -d {} +%s; }
echo "| shards x jobs | end-to-end s | shard fixed s (mean / max) | merge s | Slurm: queue / merge start s | identical | load before -> after |"
echo "|---|---|---|---|---|---|---|"
for n in "${counts[@]}"; do
  jobs=$((n == 1 ? 2 : 1))
  out=$work/run-$n
  l0=$(load)
  t0=$(ms)
  "$repo/scripts/slurm/submit.sh" "$suite" --shards "$n" --jobs "$jobs" --out "$out" --wait \
    >"$work/submit-$n.out"
  e2e=$(($(ms) - t0))
  array=$(sed -n 's/^shards: job \([0-9]*\),.*/\1/p' "$work/submit-$n.out")
  merge_job=$(sed -n 's/^merge: job \([0-9]*\),.*/\1/p' "$work/submit-$n.out")
  submitted=$(times "ArrayJobId=$array " SubmitTime | sort -n | head -1)
  first_start=$(times "ArrayJobId=$array " StartTime | sort -n | head -1)
  last_end=$(times "ArrayJobId=$array " EndTime | sort -n | tail -1)
  merge_start=$(times "^JobId=$merge_job " StartTime)
  l1=$(load)
  # Shard i holds the merged trials at matrix indices i, i + n, ... (trials.jsonl is in
  # matrix order).
  fixed=$(jq -rs --argjson n "$n" --argjson j "$jobs" --slurpfile p "$out/merged/provenance.json" '
      [range(0; $n) as $i
       | ([to_entries[] | select(.key % $n == $i) | .value.wall_time_s] | add // 0) as $t
       | $p[0].shards[$i].wall_s - $t / $j]
      | "\(add / length * 100 | round / 100) / \(max * 100 | round / 100)"' \
    "$out/merged/trials.jsonl")
  dirs=()
  for ((i = 0; i < n; i++)); do dirs+=("$out/shard-$i"); done
  t0=$(ms)
  "$bin" merge "$work/remerge-$n" "${dirs[@]}" >/dev/null 2>&1
  merge_ms=$(($(ms) - t0))
  same=$(jq -c "$key" "$out/merged/trials.jsonl" | sort | comm -12 - "$work/local.keys" | wc -l)
  printf '| %s x %s | %.1f | %s | %.2f | %s / %s | %s of %s | %s -> %s |\n' "$n" "$jobs" \
    "$(echo "$e2e" | awk '{print $1 / 1000}')" "$fixed" \
    "$(echo "$merge_ms" | awk '{print $1 / 1000}')" "$((first_start - submitted))" \
    "$((merge_start - last_end))" "$same" "$trials" "$l0" "$l1"
done
echo
echo "(local --jobs 2: $local_s s)"
