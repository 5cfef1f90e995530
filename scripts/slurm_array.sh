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
#   <name>.h5                     the merged result (or --output FILE)
#
# Before submitting, the script checks the config, its records and every
# shard file already there (`quakejoint sweep --check`): shards of an
# earlier version of the config are refused, naming exactly their files (to
# delete, if they are to be computed again: never the finished shards of
# this config), or use another config name; so is a merged name that is an
# unsharded sweep's output (it has a journal) and a config whose jobs are
# already queued.
#
# Each task runs `quakejoint sweep <config> --shard K/N --output <shard file>`
# with one worker thread per CPU it gets. A sweep continues its journal, so
# a task that is requeued, preempted, timed out or cancelled and submitted
# again (--tasks) finishes the jobs its shard has not done. SIGTERM (scancel,
# the time limit) makes a task write a final checkpoint and stop within
# seconds. Its log then ends with the command that resubmits it
# (`scripts/slurm_array.sh <config> <N> --tasks K`, run on the login node;
# the script passes it to the tasks and the merge job as
# QUAKEJOINT_RESUBMIT).
#
# The merge job runs when every task has ended, whatever their fate
# (afterany). It refuses to write an incomplete result: its log names the
# missing shards and jobs, prints the command that resubmits them (--tasks;
# a new merge job follows them), and exits non-zero; or accept a partial
# result with --allow-partial. Jobs that failed inside a shard (the solver
# gave up, a per-job limit) are results too: the merge writes them, marked
# failed, prints the command that runs them again (--tasks with
# --retry-failed) and exits with 3; raise the limit in the config first.
#
# Options:
#   --tasks LIST     submit only these shards (e.g. 3,5-6), then a merge
#   --retry-failed   shards run their journalled failed jobs again
#   --allow-partial  the merge writes an incomplete result (complete = 0)
#   --output FILE    the merged file (default <name>.h5)
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
#   SBATCH_ARGS   more sbatch options for both jobs, read as shell words
#                 (quote values with spaces) and placed last so that they
#                 override the script's own (e.g. "--account=abc --qos=long";
#                 a --time or --mem there applies to the merge job too, and a
#                 --job-name renames the logs)
set -euo pipefail

usage() { sed -n '2,/^set -euo/p' "$0" | sed -e 's/^# \{0,1\}//' -e '$d'; exit "${1:-2}"; }
die() { echo "slurm_array.sh: $*" >&2; exit 2; }

tasks="" retry="" partial="" mode=slurm dry="" merged="" args=() argv0=$0
while [ $# -gt 0 ]; do
  case "$1" in
    --tasks) tasks=${2:?--tasks needs a list, e.g. 3,5-6}; shift 2 ;;
    --retry-failed) retry="--retry-failed"; shift ;;
    --allow-partial) partial="--allow-partial"; shift ;;
    --output) merged=${2:?--output needs a file name}; shift 2 ;;
    --local) mode=local; shift ;;
    --dry-run) dry=1; shift ;;
    -h|--help) usage 0 ;;
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
[ -x "$bin" ] || die "no quakejoint binary: install it (cargo install --locked --path crates/cli) or set QUAKEJOINT"
bin=$(cd "$(dirname "$bin")" && pwd)/$(basename "$bin")
config=$(cd "$(dirname "$config")" && pwd)/$(basename "$config")
name=$(basename "${config%.toml}")

# the shard numbers to run: all, or the --tasks list (sorted, each once)
if [ -n "$tasks" ]; then
  [[ "$tasks" =~ ^[0-9]+(-[0-9]+)?(,[0-9]+(-[0-9]+)?)*$ ]] || die "--tasks $tasks: expected e.g. 3,5-6"
  for range in ${tasks//,/ }; do
    IFS=- read -r a b <<< "$range"
    [ "${b:-$a}" -ge "$a" ] || die "--tasks: $range runs backwards"
  done
  list=$(echo "$tasks" | tr ',' '\n' | while IFS=- read -r a b; do seq "$a" "${b:-$a}"; done | sort -un)
  for k in $list; do [ "$k" -ge 1 ] && [ "$k" -le "$shards" ] || die "--tasks: shard $k is not in 1..$shards"; done
  tasks=$(echo $list | tr ' ' ',')
else
  list=$(seq 1 "$shards")
  tasks="1-$shards"
fi
given_output=$merged
merged=${merged:-${name}.h5}

# checks the config and its records, and sizes the requests (exit 2 on bad input)
resources=$("$bin" plan "$config" --shards "$shards" --threads "$cpus" --sbatch) || exit $?
mkdir -p shards/logs
shard_file() { echo "shards/${name}-$1-of-${shards}.h5"; }
files=()
for k in $(seq 1 "$shards"); do files+=("$(shard_file "$k")"); done
q() { printf '%q ' "$@"; }   # quoted words, each followed by a space
q1() { printf '%q' "$1"; }    # one quoted word

# every shard already there must be of this config (or its task would stop
# at once, and a merge of old shards would give old results); only the
# shards that cannot run are named, never the finished ones
bad=() stale=""
for k in $list; do
  f=$(shard_file "$k")
  if ! "$bin" sweep "$config" --shard "$k/$shards" --output "$f" --check > /dev/null; then
    bad+=("$k")
    for g in "$f" "$f.journal" "$f.json"; do [ ! -e "$g" ] || stale+=" $(q1 "$g")"; done
  fi
done
if [ ${#bad[@]} -gt 0 ]; then
  list_bad=$(IFS=,; echo "${bad[*]}")
  other="use another config name (a copy of the config under a new name starts new shards)"
  hint="Remove the cause, or $other."
  [ -z "$stale" ] || hint="If they hold the results of an earlier version of the config, delete only their files (the other shards' files hold finished work: keep them):
  rm -f$stale
or $other."
  die "shard(s) $list_bad of $shards cannot run (the reason is above); nothing was submitted.
$hint"
fi
[ ! -e "${merged}.journal" ] || die "$merged is the output of an unsharded sweep (it has a journal): name the merged file with --output"

# the command that resubmits shards of this sweep with the same settings,
# for the advice in the logs of the tasks and of the merge (quakejoint
# appends --tasks K and --retry-failed where they apply)
resubmit=""
for v in QUAKEJOINT QJ_CPUS QJ_MEM QJ_TIME QJ_PARTITION SBATCH_ARGS; do
  [ -z "${!v:-}" ] || resubmit+="$v=$(q1 "${!v}") "
done
resubmit+="$(q1 "$argv0") $(q1 "${args[0]}") $shards"
[ -z "$given_output" ] || resubmit+=" --output $(q1 "$given_output")"
[ -z "$partial" ] || resubmit+=" $partial"
[ "$mode" = slurm ] || resubmit+=" --local"

if [ "$mode" = local ]; then
  pids=()
  for k in $list; do
    cmd=("$bin" sweep "$config" --shard "$k/$shards" --threads "$cpus" --output "$(shard_file "$k")" --progress lines --json)
    [ -z "$retry" ] || cmd+=("$retry")
    if [ -n "$dry" ]; then q "${cmd[@]}"; echo; continue; fi
    QUAKEJOINT_RESUBMIT=$resubmit "${cmd[@]}" > "$(shard_file "$k").json" 2> "shards/logs/${name}-$k.log" &
    pids+=($!)
  done
  merge=("$bin" merge "${files[@]}" --config "$config" --output "$merged")
  [ -z "$partial" ] || merge+=("$partial")
  if [ -n "$dry" ]; then q "${merge[@]}"; echo; exit 0; fi
  status=0
  for p in "${pids[@]}"; do wait "$p" || status=$?; done
  [ "$status" -eq 0 ] || echo "slurm_array.sh: a shard ended with exit code $status (logs in shards/logs)" >&2
  QUAKEJOINT_RESUBMIT=$resubmit "${merge[@]}" || status=$?
  exit "$status"
fi

command -v sbatch > /dev/null || die "sbatch not found: is this a SLURM login node? (--local runs without SLURM)"
queued=$(squeue -h -u "$(id -un)" -n "qj-$name,qj-$name-merge" -o %i 2> /dev/null | tr '\n' ' ')
[ -z "$queued" ] || die "jobs of this config are queued or running ($queued): wait for them, or scancel them first"
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
eval "extra=(${SBATCH_ARGS:-})" || die "SBATCH_ARGS: not shell words: ${SBATCH_ARGS:-}"

task_cmd="export QUAKEJOINT_RESUBMIT=$(q1 "$resubmit"); exec $(q1 "$bin") sweep $(q1 "$config") --shard \${SLURM_ARRAY_TASK_ID}/$shards --threads \${SLURM_CPUS_PER_TASK:-$cpus} --output shards/$(q1 "$name")-\${SLURM_ARRAY_TASK_ID}-of-$shards.h5 --progress lines $retry"
array_cmd=(sbatch --parsable --job-name="qj-$name" --array="$tasks" "${opts[@]}"
  --output="shards/logs/%x_%A_%a.log" "${extra[@]}" --wrap "$task_cmd")
merge_cmd="export QUAKEJOINT_RESUBMIT=$(q1 "$resubmit"); exec $(q1 "$bin") merge $(q "${files[@]}")--config $(q1 "$config") --output $(q1 "$merged") $partial"
merge_opts=(--job-name="qj-$name-merge" --cpus-per-task=1 --mem=1G --time=0:30:00
  --output="shards/logs/%x_%j.log")
[ -z "${QJ_PARTITION:-}" ] || merge_opts+=("--partition=$QJ_PARTITION")

if [ -n "$dry" ]; then
  q "${array_cmd[@]}"; echo
  q sbatch --parsable --dependency=afterany:ARRAY "${merge_opts[@]}" "${extra[@]}" --wrap "$merge_cmd"; echo
  exit 0
fi

array=$("${array_cmd[@]}") || die "sbatch refused the array (see above); adjust --tasks, QJ_CPUS, QJ_MEM, QJ_TIME, QJ_PARTITION or SBATCH_ARGS"
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
echo "  each task: ${opts[*]} ${extra[*]}; logs in shards/logs/; follow with: squeue -j $array,$merge"
echo "  result: $merged (the merge's log names any missing shard and the command that resubmits it)"
