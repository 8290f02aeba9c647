#!/usr/bin/env bash
# Generate one shard of a blockworld dataset per Slurm array task, then merge.
#
#   jid=$(sbatch --parsable --array=0-7 scripts/slurm_generate.sh DATASET COUNT SEED 8 [generate options])
#   sbatch --dependency=afterok:$jid --wrap "blockworld merge DATASET"
#
# Array index I writes shard I of SHARDS (`generate --shard I/SHARDS`: the scenes with
# index mod SHARDS = I), so the array must be 0..SHARDS-1. A task that failed, was killed or
# preempted is resubmitted alone with the same arguments (`sbatch --array=I ...`): it resumes,
# redoing only the scenes whose done.json is missing or whose files fail their sha256, and says
# how many it kept. SHARDS is an argument, not SLURM_ARRAY_TASK_COUNT, because a resubmitted
# single task sees a count of 1. DATASET must be on a file system every node sees. Set BLOCKWORLD
# to the binary's path if it is not on PATH. docs/datasets.md "Settling".
#SBATCH --job-name=blockworld-generate
#SBATCH --cpus-per-task=2
#SBATCH --mem=1G
#SBATCH --output=blockworld-generate-%A_%a.log
set -euo pipefail

if [ "$#" -lt 4 ]; then
    echo "usage: sbatch --array=0-<SHARDS-1> $0 DATASET COUNT SEED SHARDS [generate options]" >&2
    exit 2
fi
dataset=$1 count=$2 seed=$3 shards=$4
shift 4
: "${SLURM_ARRAY_TASK_ID:?submit as an array job: sbatch --array=0-<SHARDS-1> ...}"
if ! [ "$SLURM_ARRAY_TASK_ID" -lt "$shards" ] 2>/dev/null; then
    echo "array index $SLURM_ARRAY_TASK_ID is not a shard of $shards; submit with --array=0-$((shards - 1))" >&2
    exit 2
fi

exec "${BLOCKWORLD:-blockworld}" generate \
    --count "$count" --seed "$seed" -o "$dataset" \
    --shard "$SLURM_ARRAY_TASK_ID/$shards" --jobs "${SLURM_CPUS_PER_TASK:-0}" "$@"
