#!/usr/bin/env bash
# A real single-node Slurm cluster on this machine, for tests (docs/cluster.md): munged, slurmctld
# and slurmd from Debian's packages, every file (key, sockets, state, logs, slurm.conf) in one
# folder, nothing under /etc or /run touched. Needs root (slurmd starts jobs as their users).
#
#   scripts/slurm-local.sh start DIR   # prints `export SLURM_CONF=DIR/slurm.conf`
#   scripts/slurm-local.sh stop DIR
set -euo pipefail
usage() { echo "usage: $0 start|stop DIR" >&2; exit 2; }
[ $# -eq 2 ] || usage
action=$1
dir=$(realpath -m "$2")
conf="$dir/slurm.conf"
node=$(hostname -s)

stop() {
  if [ -f "$conf" ]; then
    SLURM_CONF="$conf" scontrol shutdown >/dev/null 2>&1 || true
  fi
  for pidfile in "$dir/slurmd.pid" "$dir/slurmctld.pid" "$dir/munge/munged.pid"; do
    if [ -f "$pidfile" ]; then
      pid=$(cat "$pidfile")
      for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; kill "$pid" 2>/dev/null || true; sleep 0.1; done
      rm -f "$pidfile"
    fi
  done
}

case "$action" in
  start)
    [ "$(id -u)" -eq 0 ] || { echo "slurm-local: slurmd needs root" >&2; exit 1; }
    for program in munged slurmctld slurmd sinfo sbatch; do
      command -v "$program" >/dev/null || { echo "slurm-local: $program is missing (scripts/install-deps.sh)" >&2; exit 1; }
    done
    stop
    ctld_port=${NAVAID_SLURMCTLD_PORT:-16817}
    slurmd_port=${NAVAID_SLURMD_PORT:-16818}
    for port in "$ctld_port" "$slurmd_port"; do
      if (exec 3<>"/dev/tcp/127.0.0.1/$port") 2>/dev/null; then
        echo "slurm-local: port $port is in use (another Slurm?); set NAVAID_SLURMCTLD_PORT / NAVAID_SLURMD_PORT" >&2
        exit 1
      fi
    done
    rm -rf "$dir"
    mkdir -p "$dir/key" "$dir/munge" "$dir/state" "$dir/spool" "$dir/log"
    chmod 700 "$dir/key"
    chmod 755 "$dir" "$dir/munge"
    head -c 1024 /dev/urandom > "$dir/key/munge.key"
    chmod 400 "$dir/key/munge.key"
    munged --force --socket="$dir/munge/munge.socket" --key-file="$dir/key/munge.key" \
      --pid-file="$dir/munge/munged.pid" --seed-file="$dir/munge/munged.seed" --log-file="$dir/log/munged.log"
    memory_mb=$(awk '/MemTotal/ {print int($2 / 1024 * 0.8)}' /proc/meminfo)
    cat > "$conf" <<EOF
ClusterName=navaid-local
SlurmctldHost=$node
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$dir/munge/munge.socket
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/log/slurmctld.log
SlurmdLogFile=$dir/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core_Memory
ReturnToService=2
MpiDefault=none
MinJobAge=600
NodeName=$node NodeAddr=127.0.0.1 CPUs=$(nproc) RealMemory=$memory_mb State=UNKNOWN
PartitionName=local Nodes=$node Default=YES MaxTime=INFINITE State=UP
EOF
    export SLURM_CONF="$conf"
    slurmctld -f "$conf"
    slurmd -f "$conf"
    for _ in $(seq 100); do
      if sinfo --noheader --states=idle --format=%N 2>/dev/null | grep -q "$node"; then
        echo "export SLURM_CONF=$conf"
        exit 0
      fi
      sleep 0.2
    done
    echo "slurm-local: the node did not come up idle in 20 s; logs in $dir/log" >&2
    sinfo >&2 || true
    tail -n 20 "$dir/log/slurmctld.log" "$dir/log/slurmd.log" >&2 || true
    stop
    exit 1
    ;;
  stop)
    stop
    ;;
  *)
    usage
    ;;
esac
