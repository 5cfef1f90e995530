#!/usr/bin/env bash
# Stop the single-node SLURM cluster started by tests/slurm/start.sh.
#
#   tests/slurm/stop.sh             # cancel all jobs, stop slurmd, slurmctld, munged
#   tests/slurm/stop.sh --restart   # keep jobs and munged (start.sh's config reload)
#
# Idempotent, and safe after a start that failed half-way (only munged up,
# say): a daemon that is not running is skipped. Each daemon is sent
# SIGTERM by the PID in its pid file (slurmctld then saves its state), and
# SIGKILL if it is still there after 20 s.
set -euo pipefail
restart=; [ "${1:-}" = --restart ] && restart=1

stop() {   # stop NAME PIDFILE
  local pid
  # only a live process with the expected name (a stale pid file may name another)
  [ -f "$2" ] && pid=$(cat "$2") && [ "$(cat "/proc/$pid/comm" 2>/dev/null)" = "$1" ] \
    || { echo "$1: not running"; return 0; }
  kill -TERM "$pid"
  for _ in $(seq 1 40); do kill -0 "$pid" 2>/dev/null || { echo "$1: stopped"; return 0; }; sleep 0.5; done
  echo "$1: still running after 20 s, killing $pid"; kill -KILL "$pid" 2>/dev/null || true
}

alive() { [ -f "$2" ] && [ "$(cat "/proc/$(cat "$2")/comm" 2>/dev/null)" = "$1" ]; }

# Jobs' processes (slurmstepd and below) outlive slurmd: cancel them first
# (only a running slurmctld knows them: after a start that failed half-way,
# asking would wait for a controller that is not there).
if [ -z "$restart" ] && alive slurmctld /run/slurmctld.pid && jobs=$(squeue -h -o %A 2>/dev/null) && [ -n "$jobs" ]; then
  echo "cancelling jobs: $(echo $jobs)"
  scancel $jobs || true
  for _ in $(seq 1 40); do [ -z "$(squeue -h -t R,CG,S -o %A 2>/dev/null)" ] && break; sleep 0.5; done
fi
stop slurmd /run/slurmd.pid
stop slurmctld /run/slurmctld.pid
[ -n "$restart" ] || stop munged /run/munge/munged.pid
