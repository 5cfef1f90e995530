#!/usr/bin/env bash
# Start a single-node SLURM cluster on this machine (Debian 12, root, no systemd).
#
#   tests/slurm/start.sh      # install if needed, configure, start, wait, smoke-test
#   tests/slurm/stop.sh       # stop it again
#
# Idempotent: packages are installed only when missing, slurm.conf is rewritten
# only when it changes (the SLURM daemons are then restarted), daemons already
# running are left alone, and a state directory left by another cluster (whose
# name slurmctld would refuse: CLUSTER NAME MISMATCH) is moved aside to
# /var/spool/slurmctld.<its cluster>.<time>.<pid>, not deleted. Daemons are started
# from their binaries, not systemd. Exits non-zero, with log tails, when the
# node is not idle or a job fails (tests/slurm/stop.sh then stops whatever
# did start, munged included).
set -euo pipefail

TIMEOUT=${SLURM_START_TIMEOUT:-60}   # seconds to wait for the node / smoke jobs
CONF=/etc/slurm/slurm.conf
LOGDIR=/var/log/slurm
CLUSTER=ci
STATE=/var/spool/slurmctld
t0=$SECONDS
say() { echo "[slurm-start +$((SECONDS - t0))s] $*"; }

diagnose() {
  echo "---- diagnostics ----"
  for f in /var/log/munge/munged.log "$LOGDIR/slurmctld.log" "$LOGDIR/slurmd.log"; do
    [ -f "$f" ] && { echo "== tail $f"; tail -n 30 "$f"; }
  done
  sinfo -R 2>&1 || true
  scontrol show node 2>&1 || true
}
trap 'rc=$?; [ $rc -ne 0 ] && { say "FAILED (exit $rc)"; diagnose; }; exit $rc' EXIT

# alive NAME PIDFILE: the pid file names a live process called NAME
alive() { [ -f "$2" ] && [ "$(cat "/proc/$(cat "$2")/comm" 2>/dev/null)" = "$1" ]; }

# --- 1. packages ----------------------------------------------------------
pkgs=(munge slurmctld slurmd slurm-client)
missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f '${Status}' "$p" 2>/dev/null | grep -q 'ok installed' || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  say "installing ${missing[*]}"
  # Keep the packages' maintainer scripts from trying to start services.
  own_policy=
  if [ ! -e /usr/sbin/policy-rc.d ]; then
    printf '#!/bin/sh\nexit 101\n' > /usr/sbin/policy-rc.d; chmod +x /usr/sbin/policy-rc.d; own_policy=1
  fi
  export DEBIAN_FRONTEND=noninteractive
  apt_rc=0
  { apt-get update -qq && apt-get install -y -qq --no-install-recommends "${missing[@]}"; } \
    > /tmp/slurm-apt.log 2>&1 || apt_rc=$?
  [ -z "$own_policy" ] || rm -f /usr/sbin/policy-rc.d
  [ $apt_rc -eq 0 ] || { tail -n 40 /tmp/slurm-apt.log; exit 1; }
  say "installed"
fi

# --- 2. hostname: slurmd must find itself under NodeName ------------------
host=$(hostname -s)
if ! getent hosts "$host" > /dev/null; then
  say "$host does not resolve: adding it to /etc/hosts"
  echo "127.0.0.1 $host" >> /etc/hosts
fi

# --- 3. munge --------------------------------------------------------------
# munged refuses a key or directories that others can read or write.
install -d -o munge -g munge -m 0700 /etc/munge /var/lib/munge /var/log/munge
install -d -o munge -g munge -m 0755 /run/munge      # /run is a tmpfs: gone after reboot
if [ ! -s /etc/munge/munge.key ]; then
  say "creating munge key"
  dd if=/dev/urandom of=/etc/munge/munge.key bs=1024 count=1 status=none
fi
chown munge:munge /etc/munge/munge.key; chmod 0400 /etc/munge/munge.key
if ! alive munged /run/munge/munged.pid; then
  say "starting munged"
  runuser -u munge -- /usr/sbin/munged
fi
for _ in $(seq 1 20); do munge -n | unmunge > /dev/null 2>&1 && break; sleep 0.5; done
munge -n | unmunge > /dev/null || { echo "munge does not work"; exit 1; }

# --- 4. slurm.conf ---------------------------------------------------------
# The node's line comes from the hardware slurmd sees (CPUs, sockets, cores,
# threads, RealMemory), so the node is never drained for a config mismatch.
node=$(slurmd -C | head -n 1 | sed "s/^NodeName=[^ ]*/NodeName=$host/")
cpus=$(sed -n 's/.*CPUs=\([0-9]*\).*/\1/p' <<< "$node")
mem=$(sed -n 's/.*RealMemory=\([0-9]*\).*/\1/p' <<< "$node")
install -d -m 0755 /etc/slurm "$LOGDIR" "$STATE" /var/spool/slurmd
new=$(cat <<EOF
# Written by tests/slurm/start.sh: one node on localhost, no accounting, no cgroups.
ClusterName=$CLUSTER
SlurmctldHost=$host(127.0.0.1)
SlurmUser=root
AuthType=auth/munge
StateSaveLocation=$STATE
SlurmdSpoolDir=/var/spool/slurmd
SlurmctldPidFile=/run/slurmctld.pid
SlurmdPidFile=/run/slurmd.pid
SlurmctldLogFile=$LOGDIR/slurmctld.log
SlurmdLogFile=$LOGDIR/slurmd.log
SlurmctldDebug=info
SlurmdDebug=info
# No systemd/cgroup here: track processes by /proc, no task containment.
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
MpiDefault=none
PropagateResourceLimits=NONE
MailProg=/bin/true
# Credential lifetime; also how long a requeued job waits before it may start
# again (default 120 s).
AuthInfo=cred_expire=10
# No accounting; finished jobs stay in scontrol/squeue for MinJobAge seconds,
# and every finished job gets a line (with ExitCode) in the jobcomp file.
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
JobCompType=jobcomp/filetxt
JobCompLoc=$LOGDIR/jobcomp.log
MinJobAge=300
# CPUs and memory are both consumable; a job without --mem gets DefMemPerCPU.
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU_Memory
DefMemPerCPU=$((mem / cpus))
# Reject impossible jobs at submit time; schedule fast; quick kills.
EnforcePartLimits=ALL
SchedulerType=sched/backfill
SchedulerParameters=sched_interval=2,bf_interval=1
ReturnToService=2
KillWait=5
InactiveLimit=0
$node State=UNKNOWN NodeAddr=127.0.0.1
PartitionName=debug Nodes=$host Default=YES MaxTime=INFINITE State=UP
EOF
)
changed=
if [ ! -f "$CONF" ] || [ "$(cat "$CONF")" != "$new" ]; then
  say "writing $CONF"
  printf '%s\n' "$new" > "$CONF"
  changed=1
fi

# --- 5. slurmctld and slurmd (root, daemonised) ---------------------------
if [ -n "$changed" ] && { alive slurmctld /run/slurmctld.pid || alive slurmd /run/slurmd.pid; }; then
  say "config changed: restarting the SLURM daemons"
  "$(dirname "$0")/stop.sh" --restart
fi
# slurmctld refuses a state directory written by a cluster of another name
# (an earlier slurm.conf, another test set-up): move that state aside
if ! alive slurmctld /run/slurmctld.pid && [ -f "$STATE/clustername" ]; then
  other=$(tr -d '[:space:]' < "$STATE/clustername")
  if [ "$other" != "$CLUSTER" ]; then
    aside="$STATE.$(tr -dc 'A-Za-z0-9_.-' <<< "${other:-unnamed}").$(date +%Y%m%dT%H%M%S).$$"
    say "$STATE holds the state of cluster '$other', not '$CLUSTER': moving it to $aside"
    mv "$STATE" "$aside"
    install -d -m 0755 "$STATE"
  fi
fi
if ! alive slurmctld /run/slurmctld.pid; then say "starting slurmctld"; slurmctld; fi
if ! alive slurmd /run/slurmd.pid; then say "starting slurmd"; slurmd -N "$host"; fi

# --- 6. wait for an idle node, then run a trivial job ---------------------
# (mixed/allocated: start.sh was rerun while jobs run; '*' or drain/down: bad)
say "waiting for $host to be idle"
deadline=$((SECONDS + TIMEOUT))
until state=$(sinfo -h -n "$host" -o %T 2>/dev/null) && [[ $state =~ ^(idle|mixed|allocated)$ ]]; do
  [ $SECONDS -lt $deadline ] || { echo "node state after ${TIMEOUT}s: '${state:-}'"; exit 1; }
  sleep 1
done
say "node $state; smoke-testing srun and sbatch --wait"
timeout "$TIMEOUT" srun -N1 -n1 -t 1 --mem=10M true
out=$(mktemp)
timeout "$TIMEOUT" sbatch --wait -Q -t 1 --mem=10M -o "$out" --wrap 'echo ok'
grep -qx ok "$out" || { echo "sbatch job printed: $(cat "$out")"; exit 1; }
rm -f "$out"
say "SLURM is up: $node"
