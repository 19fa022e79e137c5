#!/usr/bin/env bash
# A single-node Slurm cluster on this machine, for the sweep tests:
#   scripts/slurm_local.sh start DIR   # munged, slurmctld and slurmd (configless) in DIR; waits for the node
#   scripts/slurm_local.sh stop DIR    # stops what start started
# Clients (sbatch, squeue, sacct) find the cluster through SLURM_CONF=DIR/slurm.conf.
# Needs Debian's slurm-wlm and munge, and root (the daemons run as root, SlurmUser=root).
set -euo pipefail
cmd=${1:?start or stop}
dir=$(realpath -m "${2:?state directory}")

stop() {
  for p in slurmd slurmctld munged; do
    if [ -f "$dir/$p.pid" ]; then
      kill "$(cat "$dir/$p.pid")" 2>/dev/null || true
      rm -f "$dir/$p.pid"
    fi
  done
  sleep 1
}

if [ "$cmd" = stop ]; then stop; exit 0; fi
[ "$cmd" = start ] || { echo "usage: $0 start|stop DIR" >&2; exit 2; }

mkdir -p "$dir"/{state,spool,log,munge}
host=$(hostname -s)
cpus=$(nproc)
mem=$(( $(awk '/MemTotal/ {print $2}' /proc/meminfo) / 1024 - 1024 ))
port=$(( 16000 + RANDOM % 20000 ))

# munge on its default socket (slurmd fetches its configuration before it could read
# another socket's path from it): reuse a running munged, else start one with a key of its own
if ! munge -n 2>/dev/null | unmunge >/dev/null 2>&1; then
  mkdir -p /run/munge
  key="$dir/munge/munge.key"
  [ -s "$key" ] || head -c 1024 /dev/urandom > "$key"
  chmod 400 "$key"
  munged --key-file="$key" --pid-file="$dir/munged.pid" \
    --log-file="$dir/log/munged.log" --seed-file="$dir/munge/seed" --force
fi

cat > "$dir/slurm.conf" <<CONF
ClusterName=greybox-test
SlurmctldHost=$host
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
SlurmctldPort=$port
SlurmdPort=$((port + 1))
SlurmctldParameters=enable_configless
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/log/slurmctld.log
SlurmdLogFile=$dir/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
SchedulerType=sched/backfill
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
MpiDefault=none
ReturnToService=2
NodeName=$host CPUs=$cpus RealMemory=$mem State=UNKNOWN
PartitionName=debug Nodes=$host Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF="$dir/slurm.conf"

# the controller reads the file; the node daemon fetches it from the controller (configless)
slurmctld -D -f "$dir/slurm.conf" >"$dir/log/slurmctld.out" 2>&1 &
echo $! > "$dir/slurmctld.pid"
for _ in $(seq 50); do scontrol ping >/dev/null 2>&1 && break; sleep 0.2; done
env -u SLURM_CONF slurmd -D --conf-server "$host:$port" >"$dir/log/slurmd.out" 2>&1 &
echo $! > "$dir/slurmd.pid"
for _ in $(seq 150); do
  state=$(sinfo -h -n "$host" -o %t 2>/dev/null || true)
  case "$state" in idle*|mix*|alloc*) echo "slurm up: node $host $state, SLURM_CONF=$dir/slurm.conf"; exit 0;; esac
  sleep 0.2
done
echo "the node did not come up (state '${state:-}'); logs in $dir/log:" >&2
tail -n 20 "$dir"/log/*.log "$dir"/log/*.out >&2 || true
stop
exit 1
