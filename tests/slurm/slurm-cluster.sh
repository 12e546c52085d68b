#!/usr/bin/env bash
# A one-machine Slurm cluster for as long as a command runs:
#   tests/slurm/slurm-cluster.sh COMMAND [ARGS...]
# starts munged, slurmctld and slurmd (Debian 12: munge, slurmctld, slurmd, slurm-client) with a
# private key, state, spool and log directory, this machine as the only node with the core count
# and memory `slurmd -C` detects, and the daemons talking over 127.0.0.1 on two free ports;
# runs COMMAND with SLURM_CONF set (sbatch, squeue, scancel ... then use this cluster);
# then cancels every job, stops the daemons and removes the directory, whatever happened.
# COMMAND's stdin is /dev/null.  Exits with COMMAND's status, or 1 when the cluster does not
# come up (its logs are printed).
# Needs root: slurmd starts jobs as their submitter, and munged must own its key.
set -euo pipefail

if [ $# -eq 0 ]; then
  echo "usage: $0 COMMAND [ARGS...]" >&2
  exit 2
fi
# Without Slurm or root: a failure in CI (CI=true), elsewhere a skip that says why (exit 77,
# CTest's SKIP_RETURN_CODE for this test).
unavailable() {
  if [ "${CI:-}" = true ]; then
    echo "$0: $1" >&2
    exit 1
  fi
  echo "$0: SKIPPED: $1 (with CI=true this fails)" >&2
  exit 77
}
for tool in munged slurmctld slurmd sbatch squeue scancel sinfo jq; do
  command -v "$tool" >/dev/null ||
    unavailable "'$tool' not found: install Debian's munge, slurmctld, slurmd, slurm-client and jq (.ci/install-deps)"
done
[ "$(id -u)" -eq 0 ] || unavailable "needs root (slurmd starts jobs as their submitter; CI runs as root)"

dir=$(mktemp -d /tmp/foldcast-slurm.XXXXXX)
chmod 700 "$dir"
pids=()
command_pid=""

stop_cluster() {
  local status=$?
  trap - EXIT INT TERM HUP
  if [ -n "$command_pid" ]; then
    kill -TERM "$command_pid" 2>/dev/null || true
    wait "$command_pid" 2>/dev/null || true
  fi
  if [ -n "${SLURM_CONF:-}" ] && [ -n "${pids[*]}" ]; then
    # Jobs first, so that their slurmstepd and processes end before the daemons do.
    scancel --full --quiet --user=root 2>/dev/null || true
    for _ in $(seq 1 60); do
      # squeue's default states: pending, running, completing (not the finished ones).
      [ -z "$(squeue --noheader --format=%A 2>/dev/null | head -n 1)" ] && break
      sleep 0.5
    done
  fi
  for ((i = ${#pids[@]} - 1; i >= 0; i--)); do kill -TERM "${pids[i]}" 2>/dev/null || true; done
  for pid in "${pids[@]}"; do
    for _ in $(seq 1 20); do kill -0 "$pid" 2>/dev/null || break; sleep 0.25; done
    kill -KILL "$pid" 2>/dev/null || true
    wait "$pid" 2>/dev/null || true
  done
  rm -rf "$dir"
  exit "$status"
}
trap stop_cluster EXIT
trap 'exit 130' INT
trap 'exit 143' TERM
trap 'exit 129' HUP

show_logs() {
  for log in "$dir"/log/*; do
    [ -f "$log" ] && { echo "--- $log"; tail -n 40 "$log"; }
  done >&2
}

# Two TCP ports nobody listens on (hexadecimal in /proc/net/tcp*).
free_port() {
  local port
  while :; do
    port=$((20000 + RANDOM % 20000))
    if ! grep -qi ":$(printf '%04X' "$port") " /proc/net/tcp /proc/net/tcp6 2>/dev/null &&
       [ "$port" != "${1:-}" ]; then
      echo "$port"
      return
    fi
  done
}
ctld_port=$(free_port)
slurmd_port=$(free_port "$ctld_port")

mkdir -p "$dir"/{munge,state,spool,log}
chmod 755 "$dir"/munge  # munged wants its socket's directory searchable by every client
# munged wants a key of at least 32 bytes readable by its user only.
head -c 1024 /dev/urandom >"$dir/munge/munge.key"
chmod 400 "$dir/munge/munge.key"
munged --foreground --force --socket="$dir/munge/munge.socket" --key-file="$dir/munge/munge.key" \
  --pid-file="$dir/munge/munged.pid" --seed-file="$dir/munge/munged.seed" \
  --log-file="$dir/log/munged.log" >>"$dir/log/munged.out" 2>&1 &
pids+=($!)

# "NodeName=vm CPUs=2 Boards=1 SocketsPerBoard=1 CoresPerSocket=2 ThreadsPerCore=1 RealMemory=24152"
hardware=$(slurmd -C | head -n 1)
case "$hardware" in
  NodeName=*" CPUs="*) ;;
  *) echo "$0: slurmd -C printed no node line: $hardware" >&2; exit 1 ;;
esac
node=${hardware%% *}
node=${node#NodeName=}
cat >"$dir/slurm.conf" <<EOF
ClusterName=foldcast-test
SlurmctldHost=$node(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$dir/munge/munge.socket
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/log/slurmctld.log
SlurmdLogFile=$dir/log/slurmd.log
SlurmctldDebug=info
SlurmdDebug=info
# No cgroups (containers and CI machines rarely delegate them): processes tracked by parentage.
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
MpiDefault=none
MailProg=/bin/true
# Cores and memory are consumable, as on a production cluster: a task asking for more than
# the node has is refused at submission.
SelectType=select/cons_tres
SelectTypeParameters=CR_Core_Memory
SchedulerType=sched/builtin
# Quick turns for tests: the next array task starts as soon as one ends (batch_sched_delay
# defaults to 3 s), and sbatch --wait polls every 2 s (its interval grows to MinJobAge / 2).
SchedulerParameters=batch_sched_delay=0
ReturnToService=2
# As production clusters do: a job asking for more than the partition allows is refused at
# submission instead of pending for ever.
EnforcePartLimits=ALL
# A cancelled task gets SIGTERM, then SIGKILL after KillWait seconds.
KillWait=5
InactiveLimit=0
MinJobAge=4
$hardware NodeAddr=127.0.0.1 State=UNKNOWN
PartitionName=test Nodes=$node Default=YES MaxTime=INFINITE State=UP
EOF
export SLURM_CONF="$dir/slurm.conf"

for _ in $(seq 1 40); do [ -S "$dir/munge/munge.socket" ] && break; sleep 0.25; done
slurmctld -D -i -f "$SLURM_CONF" >>"$dir/log/slurmctld.out" 2>&1 &
pids+=($!)
slurmd -D -N "$node" -f "$SLURM_CONF" >>"$dir/log/slurmd.out" 2>&1 &
pids+=($!)

# Up when the node is idle in sinfo (slurmd registered with slurmctld).
up=false
for _ in $(seq 1 120); do
  if [ "$(sinfo --noheader --nodes="$node" --format=%T 2>/dev/null)" = "idle" ]; then up=true; break; fi
  sleep 0.5
done
if ! $up; then
  echo "$0: the cluster did not come up within 60 s" >&2
  sinfo >&2 || true
  show_logs
  exit 1
fi
echo "slurm-cluster: $hardware, slurmctld on 127.0.0.1:$ctld_port, slurmd on :$slurmd_port ($dir)" >&2

# In the background, so that a signal to this script runs its trap at once (bash defers traps
# while a foreground child runs); the trap ends the command first.
status=0
"$@" &
command_pid=$!
wait "$command_pid" || status=$?
command_pid=""
if [ "$status" -ne 0 ]; then show_logs; fi
exit "$status"
