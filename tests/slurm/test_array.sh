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
#  3. one task cancelled while running (scancel: SIGTERM) and one stopped by
#     its time limit (SIGTERM, TIMEOUT): each log ends with the resubmission
#     of its shard (`slurm_array.sh again.toml 4 --tasks K`, never a
#     `quakejoint sweep` for the login node); the merge still runs
#     (afterany), refuses the incomplete set naming both shards, and its log
#     ends with their resubmission; that command, run as printed, continues
#     their journals, and the new merge equals the unsharded run. (The two
#     tasks are held, QUAKEJOINT_TEST_HOLD, so that they are still running
#     when stopped, however fast the machine.)
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

say "3. a task cancelled and one timed out while they run, both resubmitted as their logs say"
cp job.toml again.toml
read -r array merge <<< "$(QUAKEJOINT_TEST_HOLD=2/4,3/4 submit again.toml 4)"
log_of() { echo "shards/logs/qj-again_${array}_$1.log"; }
# waits until task $1 has started its sweep (its signal handlers are in place)
started() {
  local deadline=$((SECONDS + 240))
  until grep -q "started:" "$(log_of "$1")" 2>/dev/null; do
    [ $SECONDS -lt $deadline ] || fail "task $1 never started its sweep"
    sleep 1
  done
}
started 2
scancel "${array}_2"
started 3
scontrol update JobId="${array}_3" TimeLimit=0:01 || fail "cannot shorten the time limit of task 3"
state=$(finish "$merge" 400)
[ "$state" = "FAILED 2:0" ] || fail "the merge of an incomplete set must fail with exit 2, not: $state"
merge_log=shards/logs/qj-again-merge_"$merge".log
for k in 2 3; do
  grep -q "again-$k-of-4.h5 (shard $k/4) has .* jobs not run" "$merge_log" || fail "the merge log does not name shard $k: $(cat "$merge_log")"
done
[ ! -e again.h5 ] || fail "an incomplete merge wrote again.h5"
[ "$(scontrol -o show job "${array}_2" | grep -o 'JobState=[A-Z]* .*ExitCode=[0-9:]*' | sed -E 's/JobState=([A-Z]+).*ExitCode=/\1 /')" = "CANCELLED 143:0" ] \
  || fail "the cancelled task did not stop on SIGTERM with 143: $(scontrol -o show job "${array}_2")"
[ "$(scontrol -o show job "${array}_3" | grep -o 'JobState=[A-Z]* .*ExitCode=[0-9:]*' | sed -E 's/JobState=([A-Z]+).*ExitCode=/\1 /')" = "TIMEOUT 143:0" ] \
  || fail "the timed-out task did not stop on SIGTERM with 143: $(scontrol -o show job "${array}_3")"
# the advice: the line after "continue with" (tasks) and after "resubmit the
# shards" (merge): the script, this config and N, --tasks, nothing else
advice() { grep -A1 "$1" "$2" | sed -n 2p | sed 's/^ *//'; }
for k in 2 3; do
  a=$(advice "continue with" "$(log_of $k)")
  [[ "$a" == *"/scripts/slurm_array.sh again.toml 4 --tasks $k" ]] || fail "task $k's log advises: '$a': $(tail -n 5 "$(log_of $k)")"
done
a=$(advice "resubmit the shards" "$merge_log")
[[ "$a" == *"/scripts/slurm_array.sh again.toml 4 --tasks 2,3" ]] || fail "the merge's log advises: '$a': $(cat "$merge_log")"
! grep -q "quakejoint sweep" "$merge_log" "$(log_of 2)" "$(log_of 3)" || fail "a log advises running quakejoint sweep"
# done as the merge's log says
out=$(bash -c "$a") || fail "the advised command failed: $a"
echo "$out" >&2
read -r array merge <<< "$(echo "$out" | sed -nE 's/^submitted .* job array ([0-9]+) and the merge as job ([0-9]+).*/\1 \2/p')"
[ -n "$merge" ] || fail "no job ids from the advised command"
state=$(finish "$merge" 240)
[ "$state" = "COMPLETED 0:0" ] || fail "merge after the resubmission: $state"
"$bin" compare again.h5 reference.h5 || fail "the merged file after a cancellation and a timeout differs from the unsharded run"

say "passed in $((SECONDS - t0)) s"
cd / && rm -rf "$work"
