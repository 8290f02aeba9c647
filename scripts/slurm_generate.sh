#!/usr/bin/env bash
# Generate one shard of a blockworld dataset per Slurm array task, then merge.
#
#   sbatch --array=0-7 scripts/slurm_generate.sh DATASET COUNT SEED [more generate options]
#   sbatch --dependency=afterok:<jobid> --wrap "blockworld merge DATASET"
#
# Each task writes the scenes with index % SLURM_ARRAY_TASK_COUNT == its index (its shard is
# taken from SLURM_ARRAY_TASK_ID by `--shards`); a task that fails or is preempted is simply
# resubmitted (`sbatch --array=<i> ...`): it resumes, redoing only missing or damaged scenes.
# DATASET must be on a file system every node sees. Set BLOCKWORLD to the binary's path if it
# is not on PATH.
#SBATCH --job-name=blockworld-generate
#SBATCH --cpus-per-task=2
#SBATCH --mem=1G
#SBATCH --output=blockworld-generate-%A_%a.log
set -euo pipefail

if [ "$#" -lt 3 ]; then
    echo "usage: sbatch --array=0-<N-1> $0 DATASET COUNT SEED [generate options]" >&2
    exit 2
fi
dataset=$1 count=$2 seed=$3
shift 3
: "${SLURM_ARRAY_TASK_COUNT:?submit as an array job: sbatch --array=0-<N-1> ...}"

exec "${BLOCKWORLD:-blockworld}" generate \
    --count "$count" --seed "$seed" -o "$dataset" \
    --shards "$SLURM_ARRAY_TASK_COUNT" --jobs "${SLURM_CPUS_PER_TASK:-0}" "$@"
