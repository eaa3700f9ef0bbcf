#!/usr/bin/env bash
# One shard of a sharded run: a task of the Slurm array that scripts/slurm/submit.sh submits.
# taskmatrix takes the shard from SLURM_ARRAY_TASK_ID and SLURM_ARRAY_TASK_COUNT and resumes
# the shard's own run directory, OUT/shard-<task id>, so a resubmitted array runs only what is
# missing. Arguments: TASKMATRIX SUITE OUT JOBS [run options...]
set -euo pipefail
bin=$1 suite=$2 out=$3 jobs=$4
shift 4
exec "$bin" run "$suite" --out "$out/shard-$SLURM_ARRAY_TASK_ID" --resume --jobs "$jobs" \
  --progress off "$@"
