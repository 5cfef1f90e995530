#!/usr/bin/env bash
# tests/slurm/start.sh and stop.sh from the states a machine can be left in:
#  1. the controller's state directory holds another cluster's state (its
#     clustername file names another cluster, which slurmctld refuses with
#     CLUSTER NAME MISMATCH): start.sh moves it aside, keeping it, and the
#     cluster starts;
#  2. a start that failed half-way (only munged running): stop.sh stops it,
#     without waiting for a controller that is not there.
#
#   tests/slurm/test_start.sh
#
# Needs root; leaves the one-node cluster running, as start.sh does.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
STATE=/var/spool/slurmctld
log=$(mktemp /tmp/qj-slurm-start.XXXXXX)
say() { echo "[slurm-start-test] $*"; }
fail() { echo "[slurm-start-test] FAILED: $*" >&2; cat "$log" >&2; exit 1; }
alive() { [ -f "$2" ] && [ "$(cat "/proc/$(cat "$2")/comm" 2>/dev/null)" = "$1" ]; }

say "1. another cluster's state in $STATE"
"$here/stop.sh" > /dev/null
mkdir -p "$STATE"
printf 'othercluster' > "$STATE/clustername"   # as slurmctld leaves it for ClusterName=othercluster
echo "a file of the other cluster" > "$STATE/left-by-othercluster"
"$here/start.sh" > "$log" 2>&1 || fail "start.sh over another cluster's state (exit $?)"
aside=$(sed -n "s/.*holds the state of cluster 'othercluster', not 'ci': moving it to //p" "$log")
[ -n "$aside" ] || fail "start.sh did not say that it moved the other cluster's state aside"
[ -f "$aside/left-by-othercluster" ] || fail "the other cluster's state was not kept in $aside"
[ "$(tr -d '[:space:]' < "$STATE/clustername")" = ci ] || fail "$STATE/clustername: $(cat "$STATE/clustername")"
rm -rf "$aside"   # the state this test made up

say "2. a start that failed half-way: only munged runs"
"$here/stop.sh" > /dev/null
runuser -u munge -- /usr/sbin/munged
alive munged /run/munge/munged.pid || fail "munged did not start"
"$here/stop.sh" > "$log" 2>&1 || fail "stop.sh after a start that failed half-way (exit $?)"
! alive munged /run/munge/munged.pid || fail "munged is still running after stop.sh"

say "the cluster again"
"$here/start.sh" > "$log" 2>&1 || fail "start.sh after stop.sh (exit $?)"
rm -f "$log"
say "passed"
