#!/usr/bin/env bash
# Run a quakejoint sweep as a SLURM job array of shards, then merge.
#
#   scripts/slurm_array.sh configs/paper.toml 16          # submit 16 shards + a merge job
#   scripts/slurm_array.sh configs/paper.toml 4 --local   # same, as local processes (for testing)
#
# Each array task runs `quakejoint sweep --shard K/N --resume` into
# shards/<name>-K-of-N.h5 on all the CPUs SLURM gives it: a requeued or
# preempted task picks up from its journal. Shards are cost-balanced and
# deterministic, so the merged file is identical to an unsharded run. The
# merge job starts when every shard has succeeded (afterok); tasks whose
# sweeps had failed jobs exit with 3, so the merge waits: rerun them (they
# resume) or merge by hand with `quakejoint merge`.
#
# Environment: QUAKEJOINT (the binary, default `quakejoint` on PATH),
# SBATCH_ARGS (extra sbatch options, e.g. "--partition=short --time=04:00:00").
set -euo pipefail

config=${1:?usage: slurm_array.sh <config.toml> <shards> [--local]}
shards=${2:?usage: slurm_array.sh <config.toml> <shards> [--local]}
mode=${3:-slurm}
bin=${QUAKEJOINT:-quakejoint}
name=$(basename "${config%.toml}")
mkdir -p shards
out() { echo "shards/${name}-$1-of-${shards}.h5"; }

if [ "$mode" = "--local" ]; then
  pids=()
  for k in $(seq 1 "$shards"); do
    "$bin" sweep "$config" --shard "$k/$shards" --threads 1 --resume --json --output "$(out "$k")" > "$(out "$k").json" &
    pids+=($!)
  done
  status=0
  for p in "${pids[@]}"; do wait "$p" || status=$?; done
  files=()
  for k in $(seq 1 "$shards"); do files+=("$(out "$k")"); done
  "$bin" merge "${files[@]}" --output "${name}.h5"
  exit "$status"
fi

array=$(sbatch --parsable ${SBATCH_ARGS:-} --job-name="qj-${name}" --array="1-${shards}" --cpus-per-task="${CPUS:-8}" \
  --wrap "$bin sweep $config --shard \${SLURM_ARRAY_TASK_ID}/${shards} --threads \${SLURM_CPUS_PER_TASK} --resume --output shards/${name}-\${SLURM_ARRAY_TASK_ID}-of-${shards}.h5")
files=$(for k in $(seq 1 "$shards"); do printf '%s ' "$(out "$k")"; done)
merge=$(sbatch --parsable ${SBATCH_ARGS:-} --job-name="qj-${name}-merge" --dependency="afterok:${array}" \
  --wrap "$bin merge $files --output ${name}.h5")
echo "submitted shards as job ${array}, merge as job ${merge}: output ${name}.h5"
