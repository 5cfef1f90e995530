#!/usr/bin/env bash
# The cluster mode on a real SLURM: scripts/slurm_array.sh submits a sweep as
# a job array plus a merge job, exactly as a user would.
#
#   tests/slurm/test_array.sh [quakejoint binary]
#
# Needs a running SLURM whose node sees this machine's /tmp (tests/slurm/
# start.sh starts a one-node cluster on localhost). Checks:
#  1. a job asking for more CPUs than any node has is refused at once, and
#     one that is accepted but can never start (after a failed job) is
#     cancelled by the script; nothing is left in the queue;
#  2. four shards on a two-CPU node (two tasks wait for the others), the
#     merge after them: the merged file equals an unsharded run bit for bit
#     (`quakejoint compare`: wall times, creation times and shard labels
#     aside);
#  3. one task cancelled while running (scancel: SIGTERM): the merge still
#     runs (afterany) and refuses the incomplete set, naming the shard; the
#     shard resubmitted (--tasks) continues its journal, and the new merge
#     equals the unsharded run.
set -euo pipefail

repo=$(cd "$(dirname "$0")/../.." && pwd)
bin=${1:-${QUAKEJOINT:-$repo/target/release/quakejoint}}
[ -x "$bin" ] || { echo "test_array.sh: no binary at $bin" >&2; exit 2; }
bin=$(cd "$(dirname "$bin")" && pwd)/$(basename "$bin")  # the test runs elsewhere
export QUAKEJOINT=$bin
work=$(mktemp -d /tmp/qj-slurm-test.XXXXXX)
cd "$work"
t0=$SECONDS
say() { echo "[slurm-test +$((SECONDS - t0))s] $*"; }
fail() { echo "[slurm-test] FAILED: $*" >&2; squeue -t all 2>&1 | tail -n 20 >&2; tail -n 20 shards/logs/* >&2 2>/dev/null; exit 1; }

# waits until job $1 has left the queue (at most $2 s), then prints its
# state and exit code from `scontrol` (finished jobs stay for MinJobAge)
finish() {
  local deadline=$((SECONDS + $2))
  while [ -n "$(squeue -h -j "$1" -t PD,R,CG,CF,S 2>/dev/null)" ]; do
    [ $SECONDS -lt $deadline ] || fail "job $1 still queued after $2 s"
    sleep 1
  done
  scontrol -o show job "$1" | grep -o 'JobState=[A-Z_]* .*ExitCode=[0-9:]*' | sed -E 's/JobState=([A-Z_]+).*ExitCode=([0-9:]+)/\1 \2/' | head -n 1
}

# submits and prints the ids "array merge"
submit() {
  local out
  out=$(bash "$repo/scripts/slurm_array.sh" "$@") || fail "slurm_array.sh $*: exit $?"
  echo "$out" >&2
  echo "$out" | sed -nE 's/^submitted .* job array ([0-9]+) and the merge as job ([0-9]+).*/\1 \2/p'
}

record="$repo/ground_motions/RSN753_LOMAP_CLS090-hor2.AT2"
# the medium model (9 center beams, 49 bodies) under Corralitos 090: 64 jobs
# of about 0.8 s, so that a shard of 16 runs for about 12 s
sed -e "s#^file = .*#file = \"$record\"#" "$repo/configs/medium.toml" > job.toml
cat >> job.toml <<EOF
[sweep]
periods = { from = 0.2, to = 3.0, count = 32, spacing = "log" }
damping = [0.02, 0.05]
EOF
say "reference: the sweep unsharded"
"$bin" sweep job.toml --output reference.h5 --threads 2 --progress none > /dev/null

say "1. more CPUs than a node has: refused at submission"
if QJ_CPUS=64 bash "$repo/scripts/slurm_array.sh" job.toml 4 > refused.log 2>&1; then
  fail "a 64-CPU task was accepted on a node without 64 CPUs"
fi
grep -q "cancelled\|refused" refused.log || fail "no clear message: $(cat refused.log)"
[ -z "$(squeue -h -n qj-job,qj-job-merge)" ] || fail "jobs left in the queue after a refusal"
# accepted but never runnable (here: after a job that failed): cancelled
failed=$(sbatch --parsable --job-name=qj-fails --wrap false)
[ "$(finish "$failed" 60)" = "FAILED 1:0" ] || fail "the failing job did not fail"
if SBATCH_ARGS="--dependency=afterok:$failed" bash "$repo/scripts/slurm_array.sh" job.toml 4 > stuck.log 2>&1; then
  fail "an array that can never start was left pending"
fi
grep -q "can never start here (pending with reason DependencyNeverSatisfied)" stuck.log || fail "$(cat stuck.log)"
[ -z "$(squeue -h -n qj-job,qj-job-merge)" ] || fail "jobs left in the queue after a stuck submission"

say "2. four shards and a merge"
read -r array merge <<< "$(submit job.toml 4)"
[ -n "$merge" ] || fail "no job ids from slurm_array.sh"
state=$(finish "$merge" 240)
[ "$state" = "COMPLETED 0:0" ] || fail "merge job $merge: $state"
for k in 1 2 3 4; do
  [ "$(scontrol -o show job "${array}_$k" | grep -o 'ExitCode=[0-9:]*')" = "ExitCode=0:0" ] || fail "task $k did not end with 0"
done
"$bin" compare job.h5 reference.h5 || fail "the merged file differs from the unsharded run"

say "3. a task cancelled while it runs, its shard resubmitted"
cp job.toml again.toml
read -r array merge <<< "$(submit again.toml 4)"
# tasks 1 and 2 run for about 12 s; slurm_array.sh returns after 5 s
[ "$(squeue -h -j "${array}_2" -o %T)" = RUNNING ] || fail "task 2 is not running: $(squeue -t all -j "$array")"
scancel "${array}_2"
state=$(finish "$merge" 240)
[ "$state" = "FAILED 2:0" ] || fail "the merge of an incomplete set must fail with exit 2, not: $state"
grep -q "again-2-of-4.h5 (shard 2/4) has .* jobs not run" shards/logs/qj-again-merge_"$merge".log \
  || fail "the merge log does not name shard 2: $(cat shards/logs/qj-again-merge_"$merge".log)"
[ ! -e again.h5 ] || fail "an incomplete merge wrote again.h5"
[ "$(scontrol -o show job "${array}_2" | grep -o 'ExitCode=[0-9:]*')" = "ExitCode=143:0" ] \
  || fail "the cancelled task did not stop on SIGTERM with 143"
grep -q "continue with" shards/logs/qj-again_"${array}"_2.log || fail "the cancelled task's log has no hint to continue"
read -r array merge <<< "$(submit again.toml 4 --tasks 2)"
state=$(finish "$merge" 240)
[ "$state" = "COMPLETED 0:0" ] || fail "merge after the resubmission: $state"
"$bin" compare again.h5 reference.h5 || fail "the merged file after a cancellation differs from the unsharded run"

say "passed in $((SECONDS - t0)) s"
cd / && rm -rf "$work"
