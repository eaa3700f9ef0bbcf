#!/usr/bin/env bash
# Runs a suite on a Slurm cluster as N shards and merges them into one run directory.
#
#   scripts/slurm/submit.sh SUITE --shards N [--partition P] [--time T] [--jobs J] [--out DIR]
#                           [--wait] [-- RUN OPTIONS]
#
# Submits one array job (sbatch --array=0-(N-1)), whose task I runs `taskmatrix run SUITE
# --resume` into DIR/shard-I (the shard comes from SLURM_ARRAY_TASK_ID), and one merge job
# (--dependency=afterok:ARRAY --kill-on-invalid-dep=yes) that writes DIR/merged with
# `taskmatrix merge`; if a shard fails, Slurm cancels the merge instead of leaving it pending.
# Prints both job ids and where the result will be. With --wait it blocks until the merge job
# ends and exits with its status (non-zero when a shard failed). Submitting the same command
# again resumes every shard directory, so only missing trials run.
#
# DIR (default results/runs/<suite>-slurm) and the checkout must be on a file system that
# every node sees at the same path. RUN OPTIONS go to every shard (--trials, --seed,
# --planners, --record-hz); --jobs J sets the worker processes per shard and the CPUs each
# array task asks for (default 1). Job logs: DIR/logs/. The taskmatrix binary is
# build/bin/taskmatrix unless TASKMATRIX_BIN names another. Exit status: 0, 1 (a failed
# submission, or with --wait a failed run), 2 (bad arguments or a suite that does not
# validate; nothing is submitted).
set -euo pipefail

repo=$(cd "$(dirname "$0")/../.." && pwd)
die() {
  echo "submit: $1" >&2
  exit "${2:-1}"
}
usage() {
  die "usage: $0 SUITE --shards N [--partition P] [--time T] [--jobs J] [--out DIR] [--wait] [-- RUN OPTIONS]" 2
}

suite="" shards="" partition="" time_limit="" jobs=1 out="" wait=0
run_options=()
while [ $# -gt 0 ]; do
  case "$1" in
    --shards) [ $# -ge 2 ] || usage; shards=$2; shift 2 ;;
    --partition) [ $# -ge 2 ] || usage; partition=$2; shift 2 ;;
    --time) [ $# -ge 2 ] || usage; time_limit=$2; shift 2 ;;
    --jobs) [ $# -ge 2 ] || usage; jobs=$2; shift 2 ;;
    --out) [ $# -ge 2 ] || usage; out=$2; shift 2 ;;
    --wait) wait=1; shift ;;
    --) shift; run_options=("$@"); break ;;
    -*) echo "submit: unknown option $1" >&2; usage ;;
    *) [ -z "$suite" ] || usage; suite=$1; shift ;;
  esac
done
if [ -z "$suite" ] || [ -z "$shards" ]; then usage; fi
[[ "$shards" =~ ^[1-9][0-9]{0,5}$ ]] || die "--shards: expected a number from 1, not '$shards'" 2
[[ "$jobs" =~ ^[1-9][0-9]{0,2}$ ]] || die "--jobs: expected a number from 1, not '$jobs'" 2
for option in "${run_options[@]}"; do
  case "$option" in
    --out | --out=* | --resume | --shard | --shard=* | --only | --only=* | --jobs | --jobs=* | \
      --progress | --progress=*)
      die "run option $option: submit.sh sets it for each shard" 2 ;;
  esac
done
[ -f "$suite" ] || die "$suite: no such suite or scenario file" 2
suite=$(realpath "$suite")
name=$(basename "${suite%.*}")
out=$(realpath -m "${out:-$repo/results/runs/$name-slurm}")
bin=${TASKMATRIX_BIN:-$repo/build/bin/taskmatrix}
[ -x "$bin" ] || die "$bin: not built (scripts/setup.sh builds it)"
for command in sbatch scontrol squeue scancel; do
  command -v "$command" >/dev/null || die "$command not found: submit.sh needs a Slurm client"
done

# Bad input stops here, before anything is queued.
"$bin" validate "$suite" >/dev/null || exit 2
mkdir -p "$out/logs"

common=(--chdir="$repo" --parsable)
[ -z "$partition" ] || common+=(--partition="$partition")
[ -z "$time_limit" ] || common+=(--time="$time_limit")
array=$(sbatch "${common[@]}" --job-name="taskmatrix-$name" --array="0-$((shards - 1))" \
  --ntasks=1 --cpus-per-task="$jobs" --output="$out/logs/shard-%a.out" \
  "$repo/scripts/slurm/shard.sh" "$bin" "$suite" "$out" "$jobs" "${run_options[@]}") ||
  die "sbatch refused the shards' array job"
array=${array%%;*}
if ! merge=$(sbatch "${common[@]}" --job-name="taskmatrix-$name-merge" \
  --dependency="afterok:$array" --kill-on-invalid-dep=yes --ntasks=1 --cpus-per-task=1 \
  --output="$out/logs/merge.out" "$repo/scripts/slurm/merge.sh" "$bin" "$out" "$shards"); then
  scancel "$array" || true
  die "sbatch refused the merge job; the shards' job $array is cancelled"
fi
merge=${merge%%;*}
echo "shards: job $array, array 0-$((shards - 1)), into $out/shard-0 .. $out/shard-$((shards - 1))"
echo "merge: job $merge, after every shard succeeded (cancelled if one fails)"
echo "result: $out/merged (job logs: $out/logs)"
[ "$wait" -eq 1 ] || exit 0

# --wait: poll the controller (faster than sbatch --wait) until the merge job has ended.
field() { grep -o "\b$1=[^ ]*" <<<"$2" | head -1 | cut -d= -f2; }
report_shards() {
  local line state
  while read -r line; do
    state=$(field JobState "$line")
    [ "$state" = COMPLETED ] && continue
    echo "submit: shard $(field ArrayTaskId "$line"): $state ($(field Reason "$line"), exit" \
      "$(field ExitCode "$line")); log: $out/logs/shard-$(field ArrayTaskId "$line").out" >&2
  done < <(scontrol -o show job "$array" 2>/dev/null || true)
}
while :; do
  line=$(scontrol -o show job "$merge" 2>/dev/null || true)
  [ -n "$line" ] || die "the controller no longer knows merge job $merge; see $out/logs/merge.out"
  state=$(field JobState "$line")
  reason=$(field Reason "$line")
  case "$state" in
    PENDING)
      if [ "$reason" = DependencyNeverSatisfied ]; then
        scancel "$merge" || true
        report_shards
        die "a shard failed: merge job $merge cancelled"
      fi ;;
    RUNNING | CONFIGURING | COMPLETING | SUSPENDED | REQUEUED | RESIZING | SIGNALING | STAGE_OUT) ;;
    COMPLETED)
      echo "submit: merged into $out/merged"
      exit 0 ;;
    *)
      report_shards
      code=$(field ExitCode "$line")
      code=${code%%:*}
      echo "submit: merge job $merge ended $state ($reason); log: $out/logs/merge.out" >&2
      [[ "$code" =~ ^[1-9][0-9]*$ ]] && exit "$code"
      exit 1 ;;
  esac
  sleep 1
done
