#!/bin/bash
# Submits a plan as an array of SHARDS shards (at most MAX running at once) and the merge
# as a job that starts when every shard has succeeded (docs/batch.md).
#
#   examples/slurm/submit.sh PLAN OUT SHARDS [MAX]
#
# `grimace batch PLAN --dry-run` suggests SHARDS.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
plan=${1:?usage: submit.sh PLAN OUT SHARDS [MAX]}
out=${2:?usage: submit.sh PLAN OUT SHARDS [MAX]}
shards=${3:?usage: submit.sh PLAN OUT SHARDS [MAX]}
max=${4:-$shards}
array=$(sbatch --parsable --array="0-$((shards - 1))%$max" "$here/batch.sbatch" "$plan" "$out")
array=${array%%;*}
merge=$(sbatch --parsable --dependency="afterok:$array" "$here/merge.sbatch" "$out")
merge=${merge%%;*}
echo "array job $array ($shards shards), merge job $merge (runs after all shards succeed)"
