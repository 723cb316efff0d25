#!/bin/bash
# Submits a plan as an array of SHARDS shards (at most MAX running at once) and the merge
# as a job that starts when every shard has succeeded (docs/batch.md).
#
#   examples/slurm/submit.sh PLAN OUT SHARDS [MAX]
#
# `grimace batch PLAN --dry-run` suggests SHARDS. SBATCH_EXTRA adds sbatch options to both
# jobs (e.g. SBATCH_EXTRA="--cpus-per-task=2 --partition=short"); GRIMACE names the binary.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
plan=${1:?usage: submit.sh PLAN OUT SHARDS [MAX]}
out=${2:?usage: submit.sh PLAN OUT SHARDS [MAX]}
shards=${3:?usage: submit.sh PLAN OUT SHARDS [MAX]}
max=${4:-$shards}
# shellcheck disable=SC2086 # SBATCH_EXTRA is a list of options.
array=$(sbatch --parsable ${SBATCH_EXTRA:-} --array="0-$((shards - 1))%$max" "$here/batch.sbatch" "$plan" "$out")
array=${array%%;*}
# shellcheck disable=SC2086
merge=$(sbatch --parsable ${SBATCH_EXTRA:-} --dependency="afterok:$array" "$here/merge.sbatch" "$out")
merge=${merge%%;*}
echo "array job $array ($shards shards), merge job $merge (runs after all shards succeed)"
