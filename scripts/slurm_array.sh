#!/usr/bin/env bash
# Run a quakejoint sweep as a SLURM job array of shards plus a merge job,
# or as local processes.
#
#   scripts/slurm_array.sh [options] <config.toml> <shards>
#
#   scripts/slurm_array.sh configs/paper.toml 16            # 16 array tasks + a merge job
#   scripts/slurm_array.sh configs/paper.toml 16 --tasks 3,7 # resubmit shards 3 and 7 (+ a merge)
#   scripts/slurm_array.sh configs/paper.toml 16 --retry-failed
#   scripts/slurm_array.sh configs/paper.toml 4 --local     # the same, as local processes
#
# Files (in the current directory, which must be visible to the nodes):
#   shards/<name>-<K>-of-<N>.h5   the output of shard K (with .journal, .lock)
#   shards/logs/                  one log per task and for the merge
#   <name>.h5                     the merged result
#
# Each task runs `quakejoint sweep <config> --shard K/N --output <shard file>`
# with one worker thread per CPU it gets. A sweep continues its journal, so
# a task that is requeued, preempted, timed out or cancelled and submitted
# again (--tasks) finishes the jobs its shard has not done. SIGTERM (scancel,
# the time limit) makes a task write a final checkpoint and stop within
# seconds.
#
# The merge job runs when every task has ended, whatever their fate
# (afterany). It refuses to write an incomplete result: its log names the
# missing shards and jobs, and it exits non-zero. Then resubmit those shards
# with --tasks (a new merge job follows them), or accept a partial result
# with --allow-partial. Jobs that failed inside a shard (the solver gave up,
# a per-job limit) are results too: the merge writes them, marked failed,
# and exits with 3; after raising the limit in the config, --retry-failed
# runs only those jobs again.
#
# Options:
#   --tasks LIST     submit only these shards (e.g. 3,5-6), then a merge
#   --retry-failed   shards run their journalled failed jobs again
#   --allow-partial  the merge writes an incomplete result (complete = 0)
#   --local          run the shards as local processes, then merge
#   --dry-run        print what would be submitted, submit nothing
#
# Environment:
#   QUAKEJOINT    the binary (default: `quakejoint` on PATH, else this
#                 checkout's target/release/quakejoint)
#   QJ_CPUS       CPUs (and worker threads) per task, default 1: each job is
#                 single-threaded, so more shards beat more CPUs per shard
#   QJ_MEM        memory per task, e.g. 2G (default: twice the estimate of
#                 `quakejoint plan`, at least 256M)
#   QJ_TIME       time limit per task, e.g. 2:00:00 (default: three times the
#                 estimate of `quakejoint plan` plus 10 minutes)
#   QJ_PARTITION  the partition (default: the cluster's default)
#   SBATCH_ARGS   more sbatch options, placed last so that they override the
#                 script's own (e.g. "--account=abc --qos=long")
set -euo pipefail

usage() { sed -n '2,/^set -euo/p' "$0" | sed -e 's/^# \{0,1\}//' -e '$d'; exit 2; }
die() { echo "slurm_array.sh: $*" >&2; exit 2; }

tasks="" retry="" partial="" mode=slurm dry="" args=()
while [ $# -gt 0 ]; do
  case "$1" in
    --tasks) tasks=${2:?--tasks needs a list, e.g. 3,5-6}; shift 2 ;;
    --retry-failed) retry="--retry-failed"; shift ;;
    --allow-partial) partial="--allow-partial"; shift ;;
    --local) mode=local; shift ;;
    --dry-run) dry=1; shift ;;
    -h|--help) usage ;;
    -*) die "unknown option $1 (see --help)" ;;
    *) args+=("$1"); shift ;;
  esac
done
[ ${#args[@]} -eq 2 ] || usage
config=${args[0]}
shards=${args[1]}
[ -f "$config" ] || die "$config: no such config file"
[[ "$shards" =~ ^[1-9][0-9]*$ ]] || die "$shards: the number of shards must be a whole number >= 1"
cpus=${QJ_CPUS:-1}
[[ "$cpus" =~ ^[1-9][0-9]*$ ]] || die "QJ_CPUS=$cpus: must be a whole number >= 1"

here=$(cd "$(dirname "$0")/.." && pwd)
bin=${QUAKEJOINT:-}
if [ -z "$bin" ]; then
  bin=$(command -v quakejoint || true)
  [ -n "$bin" ] || bin="$here/target/release/quakejoint"
fi
[ -x "$bin" ] || die "no quakejoint binary: install it (cargo install --path crates/cli) or set QUAKEJOINT"
bin=$(cd "$(dirname "$bin")" && pwd)/$(basename "$bin")
config=$(cd "$(dirname "$config")" && pwd)/$(basename "$config")
name=$(basename "${config%.toml}")

# the shard numbers to run: all, or the --tasks list
if [ -n "$tasks" ]; then
  [[ "$tasks" =~ ^[0-9]+(-[0-9]+)?(,[0-9]+(-[0-9]+)?)*$ ]] || die "--tasks $tasks: expected e.g. 3,5-6"
  list=$(echo "$tasks" | tr ',' '\n' | while IFS=- read -r a b; do seq "$a" "${b:-$a}"; done)
  for k in $list; do [ "$k" -ge 1 ] && [ "$k" -le "$shards" ] || die "--tasks: shard $k is not in 1..$shards"; done
else
  list=$(seq 1 "$shards")
  tasks="1-$shards"
fi

# checks the config and its records, and sizes the requests (exit 2 on bad input)
resources=$("$bin" plan "$config" --shards "$shards" --threads "$cpus" --sbatch) || exit $?
mkdir -p shards/logs
shard_file() { echo "shards/${name}-$1-of-${shards}.h5"; }
files=()
for k in $(seq 1 "$shards"); do files+=("$(shard_file "$k")"); done
q() { printf '%q ' "$@"; }   # quoted words, each followed by a space
q1() { printf '%q' "$1"; }    # one quoted word

if [ "$mode" = local ]; then
  pids=()
  for k in $list; do
    cmd=("$bin" sweep "$config" --shard "$k/$shards" --threads "$cpus" --output "$(shard_file "$k")" --progress lines --json)
    [ -z "$retry" ] || cmd+=("$retry")
    if [ -n "$dry" ]; then q "${cmd[@]}"; echo; continue; fi
    "${cmd[@]}" > "$(shard_file "$k").json" 2> "shards/logs/${name}-$k.log" &
    pids+=($!)
  done
  merge=("$bin" merge "${files[@]}" --output "${name}.h5")
  [ -z "$partial" ] || merge+=("$partial")
  if [ -n "$dry" ]; then q "${merge[@]}"; echo; exit 0; fi
  status=0
  for p in "${pids[@]}"; do wait "$p" || status=$?; done
  [ "$status" -eq 0 ] || echo "slurm_array.sh: a shard ended with exit code $status (logs in shards/logs)" >&2
  "${merge[@]}"
  exit "$status"
fi

command -v sbatch > /dev/null || die "sbatch not found: is this a SLURM login node? (--local runs without SLURM)"
opts=()
read -r -a req <<< "$resources"
for r in "${req[@]}"; do
  case "$r" in
    --mem=*) [ -z "${QJ_MEM:-}" ] || r="--mem=$QJ_MEM" ;;
    --time=*) [ -z "${QJ_TIME:-}" ] || r="--time=$QJ_TIME" ;;
  esac
  opts+=("$r")
done
[ -z "${QJ_PARTITION:-}" ] || opts+=("--partition=$QJ_PARTITION")
read -r -a extra <<< "${SBATCH_ARGS:-}"

task_cmd="exec $(q1 "$bin") sweep $(q1 "$config") --shard \${SLURM_ARRAY_TASK_ID}/$shards --threads \${SLURM_CPUS_PER_TASK:-$cpus} --output shards/$(q1 "$name")-\${SLURM_ARRAY_TASK_ID}-of-$shards.h5 --progress lines $retry"
array_cmd=(sbatch --parsable --job-name="qj-$name" --array="$tasks" "${opts[@]}"
  --output="shards/logs/%x_%A_%a.log" "${extra[@]}" --wrap "$task_cmd")
merge_cmd="exec $(q1 "$bin") merge $(q "${files[@]}")--output $(q1 "$name.h5") $partial"
merge_opts=(--job-name="qj-$name-merge" --cpus-per-task=1 --mem=1G --time=0:30:00
  --output="shards/logs/%x_%j.log")
[ -z "${QJ_PARTITION:-}" ] || merge_opts+=("--partition=$QJ_PARTITION")

if [ -n "$dry" ]; then
  q "${array_cmd[@]}"; echo
  q sbatch --parsable --dependency=afterany:ARRAY "${merge_opts[@]}" "${extra[@]}" --wrap "$merge_cmd"; echo
  exit 0
fi

array=$("${array_cmd[@]}") || die "sbatch refused the array (see above); adjust QJ_CPUS, QJ_MEM, QJ_TIME or SBATCH_ARGS"
array=${array%%;*}
merge=$(sbatch --parsable --dependency="afterany:$array" "${merge_opts[@]}" "${extra[@]}" --wrap "$merge_cmd") || {
  scancel "$array"; die "sbatch refused the merge job; the array $array was cancelled"; }
merge=${merge%%;*}

# a task the cluster can never run stays pending for ever: catch it now
for _ in 1 2 3 4 5; do
  sleep 1
  stuck=$(squeue -h -j "$array" -t PD -o '%r' 2>/dev/null | grep -E -m1 \
    'PartitionConfig|PartitionNodeLimit|PartitionTimeLimit|BadConstraints|Invalid|MaxCpu|MaxMem|MaxWall|DependencyNeverSatisfied' || true)
  if [ -n "$stuck" ]; then
    scancel "$array" "$merge" || true
    die "the array's tasks can never start here (pending with reason $stuck): both jobs were cancelled; request less (QJ_CPUS=$cpus, ${opts[*]}) or choose another partition (QJ_PARTITION)"
  fi
done
echo "submitted shards $tasks of $shards as job array $array and the merge as job $merge"
echo "  each task: ${opts[*]}; logs in shards/logs/; follow with: squeue -j $array,$merge"
echo "  result: ${name}.h5 (the merge's log names any missing shard: resubmit it with --tasks K)"
