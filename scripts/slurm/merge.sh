#!/usr/bin/env bash
# The merge job of a sharded run (scripts/slurm/submit.sh): runs after every shard succeeded
# and writes OUT/merged from OUT/shard-0 .. OUT/shard-<N-1>.
# Arguments: TASKMATRIX OUT SHARDS
set -euo pipefail
bin=$1 out=$2 shards=$3
dirs=()
for ((i = 0; i < shards; i++)); do dirs+=("$out/shard-$i"); done
exec "$bin" merge "$out/merged" "${dirs[@]}"
