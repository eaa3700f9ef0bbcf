#!/usr/bin/env bash
# A real single-node Slurm cluster on this machine, in one private directory: munged,
# slurmctld and slurmd started by hand (no init scripts, no systemd), on free ports, so that
# scripts/slurm/submit.sh can be tried and tested without a cluster. Root only (slurmd runs
# jobs as their owners). The packages come from scripts/setup.sh.
#
#   scripts/slurm/local_cluster.sh start DIR   # prints: export SLURM_CONF=DIR/slurm.conf
#   scripts/slurm/local_cluster.sh stop DIR    # cancels its jobs, stops the daemons it started
#
# `start` records the daemons' PIDs in DIR/pids and waits until the node is idle; `stop`
# signals only those PIDs (checked against the command line that names DIR), TERM first and
# KILL after 10 s, and treats a zombie as stopped. Logs: DIR/log/.
set -euo pipefail

die() {
  echo "local_cluster: $*" >&2
  exit 1
}

[ $# -eq 2 ] || die "usage: $0 start|stop DIR"
action=$1
dir=$(realpath -m "$2")
conf=$dir/slurm.conf

# A TCP port nothing listens on (a connection to it is refused).
free_port() {
  local port
  for _ in $(seq 1 200); do
    port=$((20000 + RANDOM % 40000))
    if [ "$port" != "${1:-}" ] && ! (exec 3<>"/dev/tcp/127.0.0.1/$port") 2>/dev/null; then
      echo "$port"
      return 0
    fi
  done
  die "no free TCP port found"
}

# Whether PID is a live (not zombie) process whose command line names this cluster's DIR.
ours_and_alive() {
  local pid=$1 state
  state=$(awk '{print $3}' "/proc/$pid/stat" 2>/dev/null) || return 1
  [ -n "$state" ] && [ "$state" != Z ] || return 1
  tr '\0' ' ' <"/proc/$pid/cmdline" 2>/dev/null | grep -qF -- "$dir/"
}

start() {
  [ "$(id -u)" -eq 0 ] || die "run as root (slurmd starts jobs as their users)"
  local b
  for b in munged slurmctld slurmd sinfo sbatch squeue scontrol scancel; do
    command -v "$b" >/dev/null || die "$b is missing: run scripts/setup.sh"
  done
  [ ! -e "$dir/pids" ] || die "$dir already holds a cluster (stop it first)"
  mkdir -p "$dir"/{munge,state,spool,log}
  # munged refuses a socket whose directory, or any directory above it, others cannot enter.
  chmod 0755 "$dir" "$dir/munge"
  local up=$dir
  while [ "$up" != / ]; do
    up=$(dirname "$up")
    [ -n "$(find "$up" -maxdepth 0 -perm -o+x)" ] ||
      die "$up is not searchable by others (mode o+x), which munged requires above its socket"
  done
  : >"$dir/pids"

  head -c 1024 /dev/urandom >"$dir/munge/munge.key"
  chmod 0400 "$dir/munge/munge.key"
  munged -F --socket="$dir/munge/munge.socket.2" --key-file="$dir/munge/munge.key" \
    --pid-file="$dir/munge/munged.pid" --seed-file="$dir/munge/munged.seed" \
    </dev/null >"$dir/log/munged.log" 2>&1 &
  echo "munged $!" >>"$dir/pids"
  for _ in $(seq 1 100); do
    [ -S "$dir/munge/munge.socket.2" ] && break
    sleep 0.05
  done
  [ -S "$dir/munge/munge.socket.2" ] || die "munged did not start (see $dir/log/munged.log)"

  local ctld_port slurmd_port node
  ctld_port=$(free_port)
  slurmd_port=$(free_port "$ctld_port")
  # This machine's CPUs, sockets, cores and memory, as slurmd sees them, under the name
  # localhost.
  node=$(slurmd -C | head -1 | sed -e 's/^NodeName=[^ ]*/NodeName=localhost NodeAddr=127.0.0.1/')
  cat >"$conf" <<EOF
# Written by scripts/slurm/local_cluster.sh: one node on localhost, everything under $dir.
ClusterName=taskmatrix
SlurmctldHost=localhost(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$dir/munge/munge.socket.2
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/log/slurmctld.log
SlurmdLogFile=$dir/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
JobCompType=jobcomp/filetxt
JobCompLoc=$dir/log/jobcomp.txt
SchedulerType=sched/backfill
SchedulerParameters=batch_sched_delay=0
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
MpiDefault=none
SwitchType=switch/none
ReturnToService=2
MailProg=/bin/true
$node
PartitionName=debug Nodes=ALL Default=YES MaxTime=INFINITE State=UP
EOF
  slurmctld -D -f "$conf" </dev/null >"$dir/log/slurmctld.out" 2>&1 &
  echo "slurmctld $!" >>"$dir/pids"
  slurmd -D -f "$conf" -N localhost </dev/null >"$dir/log/slurmd.out" 2>&1 &
  echo "slurmd $!" >>"$dir/pids"

  local state=""
  for _ in $(seq 1 300); do
    state=$(SLURM_CONF=$conf sinfo -h -o %T 2>/dev/null || true)
    [ "$state" = idle ] && break
    sleep 0.1
  done
  [ "$state" = idle ] || die "the node is not idle after 30 s ('$state'; see $dir/log/)"
  echo "export SLURM_CONF=$conf"
}

stop() {
  [ -f "$dir/pids" ] || return 0
  # Jobs first, through this cluster's controller only, so that no job outlives its daemons.
  local alive
  if SLURM_CONF=$conf squeue -h -o %i >/dev/null 2>&1; then
    SLURM_CONF=$conf scancel --quiet --user="$(id -un)" 2>/dev/null || true
    for _ in $(seq 1 100); do
      [ -z "$(SLURM_CONF=$conf squeue -h -o %i 2>/dev/null)" ] && break
      sleep 0.1
    done
  fi
  local name pid
  for name in slurmd slurmctld munged; do
    pid=$(awk -v n="$name" '$1 == n {print $2}' "$dir/pids")
    [ -n "$pid" ] || continue
    ours_and_alive "$pid" || continue
    kill -TERM "$pid" 2>/dev/null || true
    alive=1
    for _ in $(seq 1 100); do
      ours_and_alive "$pid" || {
        alive=0
        break
      }
      sleep 0.1
    done
    if [ "$alive" -eq 1 ]; then
      echo "local_cluster: $name ($pid) ignored TERM for 10 s; killing it" >&2
      kill -KILL "$pid" 2>/dev/null || true
    fi
  done
  rm -f "$dir/pids"
}

case "$action" in
  start) start ;;
  stop) stop ;;
  *) die "usage: $0 start|stop DIR" ;;
esac
