#!/usr/bin/env bash
# A single-node Slurm cluster on this machine: slurmctld and slurmd as root, munge for
# authentication, state and logs under one folder. scripts/test-cluster.sh runs the Slurm job
# array of deploy/slurm/ on it; it also serves to try that array by hand (docs/cluster.md).
#
#   scripts/slurm-cluster.sh start    install what is missing, start munged and both daemons,
#                                     wait until the node takes jobs
#   scripts/slurm-cluster.sh status   the daemons and the node
#   scripts/slurm-cluster.sh stop     stop the daemons (and munged if this script started it)
#
# Slurm's commands find this cluster through SLURM_CONF, which `start` prints:
#   export SLURM_CONF=$LENSRAY_SLURM_DIR/slurm.conf
# LENSRAY_SLURM_DIR (default ${TMPDIR:-/tmp}/lensray-slurm) holds the configuration, state, logs
# and pid files. The configuration is the simplest that runs on a container or VM without systemd
# or cgroups: proctrack/linuxproc tracks a job's processes by parent id, task/none binds nothing.
# Debian 12 / Ubuntu: installs slurm-wlm and munge with apt-get when missing.
set -euo pipefail

say() { echo "slurm-cluster: $*"; }
die() { say "$*" >&2; exit 1; }

dir=${LENSRAY_SLURM_DIR:-${TMPDIR:-/tmp}/lensray-slurm}
conf=$dir/slurm.conf
host=$(hostname -s)

SUDO=""
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null 2>&1 || die "slurmctld and slurmd run as root: run this as root or with sudo"
  SUDO="sudo"
fi

install_packages() {
  local missing=() p
  for p in slurm-wlm munge; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  [ ${#missing[@]} -eq 0 ] && return
  command -v apt-get >/dev/null 2>&1 || die "install ${missing[*]} (Slurm and munge) by hand: no apt-get here"
  say "installing: ${missing[*]}"
  $SUDO apt-get update -qq
  # The packages' own services may fail to start where there is no init system; this script
  # starts the daemons itself.
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq "${missing[@]}" >/dev/null
}

munge_works() { munge -n 2>/dev/null | unmunge >/dev/null 2>&1; }

start_munge() {
  munge_works && return
  if ! $SUDO test -s /etc/munge/munge.key; then
    say "creating the munge key /etc/munge/munge.key"
    $SUDO install -d -o munge -g munge -m 0700 /etc/munge
    $SUDO dd if=/dev/urandom of=/etc/munge/munge.key bs=1024 count=1 status=none
    $SUDO chown munge:munge /etc/munge/munge.key
    $SUDO chmod 0400 /etc/munge/munge.key
  fi
  $SUDO install -d -o munge -g munge -m 0755 /run/munge
  $SUDO install -d -o munge -g munge -m 0700 /var/lib/munge /var/log/munge
  say "starting munged"
  $SUDO runuser -u munge -- /usr/sbin/munged
  $SUDO touch "$dir/munged.started"
  local i
  for i in $(seq 50); do munge_works && return; sleep 0.1; done
  die "munged does not answer: see /var/log/munge/munged.log"
}

write_conf() {
  # One node with every CPU of this machine, one partition; no accounting, no cgroups. The
  # daemons talk over 127.0.0.1, so the host name need not resolve.
  $SUDO tee "$conf" >/dev/null <<EOF
ClusterName=lensray
SlurmctldHost=$host(127.0.0.1)
AuthType=auth/munge
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
SlurmUser=root
SlurmdUser=root
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/log/slurmctld.log
SlurmdLogFile=$dir/log/slurmd.log
ReturnToService=2
MpiDefault=none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
KillWait=5
NodeName=$host NodeAddr=127.0.0.1 CPUs=$(nproc) State=UNKNOWN
PartitionName=lensray Nodes=$host Default=YES MaxTime=INFINITE State=UP
EOF
}

# Whether the daemon whose pid file is $1 runs.
running() { [ -f "$1" ] && $SUDO kill -0 "$(cat "$1")" 2>/dev/null; }

node_state() { SLURM_CONF=$conf sinfo -h -N -o %T 2>/dev/null | head -n1; }

start() {
  install_packages
  $SUDO install -d -m 0755 "$dir" "$dir/state" "$dir/spool" "$dir/log"
  start_munge
  if ! running "$dir/slurmctld.pid"; then
    write_conf
    say "starting slurmctld (configuration $conf)"
    # -c: a fresh cluster, without jobs left from an earlier start.
    $SUDO slurmctld -c -f "$conf"
  fi
  if ! running "$dir/slurmd.pid"; then
    say "starting slurmd"
    $SUDO slurmd -f "$conf"
  fi
  local i state=""
  for i in $(seq 150); do
    state=$(node_state)
    case $state in idle|mixed|allocated) break ;; esac
    sleep 0.2
  done
  case $state in
    idle|mixed|allocated) ;;
    *) tail -n 5 "$dir/log/slurmctld.log" "$dir/log/slurmd.log" >&2 || true
       die "node $host is '${state:-not listed}' after 30 s, not idle (logs above, in $dir/log)" ;;
  esac
  say "up: node $host ($(nproc) CPUs) is $state"
  echo "export SLURM_CONF=$conf"
}

stop_daemon() {
  local name=$1 pidfile=$dir/$1.pid pid i
  running "$pidfile" || return 0
  pid=$(cat "$pidfile")
  say "stopping $name ($pid)"
  $SUDO kill "$pid"
  for i in $(seq 100); do $SUDO kill -0 "$pid" 2>/dev/null || return 0; sleep 0.1; done
  $SUDO kill -9 "$pid" 2>/dev/null || true
}

stop() {
  stop_daemon slurmd
  stop_daemon slurmctld
  if [ -f "$dir/munged.started" ]; then
    say "stopping munged"
    $SUDO kill "$(cat /run/munge/munged.pid 2>/dev/null)" 2>/dev/null || true
    $SUDO rm -f "$dir/munged.started"
  fi
}

status() {
  local d rc=0
  for d in slurmctld slurmd; do
    if running "$dir/$d.pid"; then echo "$d: running ($(cat "$dir/$d.pid"))"; else echo "$d: stopped"; rc=1; fi
  done
  if munge_works; then echo "munged: running"; else echo "munged: stopped"; rc=1; fi
  [ $rc -eq 0 ] && SLURM_CONF=$conf sinfo -N
  echo "export SLURM_CONF=$conf"
  return $rc
}

case ${1:-} in
  start) start ;;
  stop) stop ;;
  status) status ;;
  *) die "usage: scripts/slurm-cluster.sh start|stop|status" ;;
esac
