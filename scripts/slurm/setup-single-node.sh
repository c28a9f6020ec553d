#!/usr/bin/env bash
# setup-single-node.sh — a one-node Slurm cluster on this machine, for trying
# scripts/slurm/render.sh (and tests/slurm/test_slurm.sh) without a real farm.
#
#   scripts/slurm/setup-single-node.sh          # install, configure, start; wait for the node
#   scripts/slurm/setup-single-node.sh --stop   # stop slurmd, slurmctld and munged
#
# What it does, each step skipped when already done (re-running is harmless):
#   1. installs munge and slurm-wlm with apt-get if their daemons are missing;
#   2. creates /etc/munge/munge.key (owner munge, mode 0400) if absent;
#   3. starts munged as the munge user and checks that a credential round-trips;
#   4. writes /etc/slurm/slurm.conf: one node (this host, `hostname -s`) with
#      CPUs=$(nproc) and a little less memory than /proc/meminfo reports, one
#      default partition, select/cons_tres + CR_Core (so several 1-CPU jobs
#      share the node), proctrack/linuxproc and task/none (no cgroups needed),
#      no accounting, SlurmUser=root. An existing file is rewritten only if it
#      carries this script's marker line (a hand-written slurm.conf is kept);
#   5. starts slurmctld and slurmd (as daemons, no systemd needed), waits up to
#      30 s for the node, and resumes it if it comes up down or drained.
#
# Must run as root. Meant for containers and throw-away VMs: it starts the
# daemons directly rather than through systemd. Logs: /var/log/slurm/.
set -euo pipefail

MARKER='# written by reel scripts/slurm/setup-single-node.sh'
CONF_DIR=/etc/slurm
CONF=$CONF_DIR/slurm.conf
LOG_DIR=/var/log/slurm
CTLD_STATE=/var/spool/slurmctld
SLURMD_SPOOL=/var/spool/slurmd
RUN_DIR=/run/slurm
CTLD_PID=$RUN_DIR/slurmctld.pid
SLURMD_PID=$RUN_DIR/slurmd.pid

say() { printf 'setup-single-node: %s\n' "$*"; }
die() { printf 'setup-single-node: error: %s\n' "$*" >&2; exit 1; }

usage() {
  sed -n '2,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//'
}

# Pids of live processes with exactly this command name (never matching
# arguments, so this script's own command line can't match). Zombies are left
# out: a container's init may take a while to reap a daemon that was killed.
daemon_pids() { ps -eo pid=,stat=,comm= | awk -v n="$1" '$3 == n && $2 !~ /^Z/ {print $1}' | paste -sd' '; }
running() { [[ -n $(daemon_pids "$1") ]]; }

# Signal a daemon by the pid in its pid file, falling back to the pids of
# processes with exactly that command name; wait up to 10 s for them to go.
stop_daemon() {
  local name=$1 pidfile=${2:-} pids=""
  # Trust the pid file only if that pid still runs this daemon (not a reused pid).
  if [[ -n $pidfile && -s $pidfile ]] \
     && [[ $(ps -o comm= -p "$(cat "$pidfile")" 2>/dev/null) == "$name" ]]; then
    pids=$(cat "$pidfile")
  fi
  [[ -n $pids ]] || pids=$(daemon_pids "$name")
  if [[ -z $pids ]]; then
    say "$name is not running"
    return 0
  fi
  # shellcheck disable=SC2086  # one or more pids, split on purpose
  kill $pids 2>/dev/null || true
  for _ in $(seq 50); do
    running "$name" || { say "stopped $name (pid $pids)"; return 0; }
    sleep 0.2
  done
  say "warning: $name (pid $pids) still running after 10 s"
}

# mungekey, munged, slurmctld and slurmd live in sbin, which a container's
# PATH sometimes leaves out.
export PATH=$PATH:/usr/sbin:/sbin

if [[ ${1:-} == -h || ${1:-} == --help ]]; then usage; exit 0; fi
[[ $# -le 1 ]] || die "too many arguments (try --help)"
[[ $# -eq 0 || $1 == --stop ]] || die "unknown option '$1' (try --help)"
[[ $(id -u) -eq 0 ]] || die "must run as root (it installs packages and starts daemons)"

if [[ ${1:-} == --stop ]]; then
  # Order: compute daemon, controller, then the authentication they both use.
  stop_daemon slurmd "$SLURMD_PID"
  stop_daemon slurmctld "$CTLD_PID"
  stop_daemon munged /run/munge/munged.pid
  exit 0
fi

# ---- 1. packages -----------------------------------------------------------
need=()
command -v munged    >/dev/null 2>&1 || need+=(munge)
command -v slurmctld >/dev/null 2>&1 || need+=(slurm-wlm)
command -v slurmd    >/dev/null 2>&1 || need+=(slurm-wlm)
command -v ps        >/dev/null 2>&1 || need+=(procps)  # this script finds daemons with ps
if ((${#need[@]})); then
  say "installing $(printf '%s\n' "${need[@]}" | sort -u | paste -sd' ') with apt-get"
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -q
  # shellcheck disable=SC2046  # package names, split on purpose
  apt-get install -y -q --no-install-recommends $(printf '%s\n' "${need[@]}" | sort -u)
else
  say "munge and slurm-wlm are installed ($(slurmctld -V))"
fi

# ---- 2. munge key ----------------------------------------------------------
install -d -o munge -g munge -m 0700 /etc/munge /var/log/munge
install -d -o munge -g munge -m 0711 /var/lib/munge
install -d -o munge -g munge -m 0755 /run/munge
if [[ ! -s /etc/munge/munge.key ]]; then
  if command -v mungekey >/dev/null 2>&1; then
    mungekey --create --keyfile=/etc/munge/munge.key
  else
    dd if=/dev/urandom of=/etc/munge/munge.key bs=1024 count=1 status=none
  fi
  say "created /etc/munge/munge.key"
else
  say "munge key exists: /etc/munge/munge.key"
fi
chown munge:munge /etc/munge/munge.key
chmod 0400 /etc/munge/munge.key

# ---- 3. munged -------------------------------------------------------------
if running munged; then
  say "munged is running"
else
  # A stale socket or pid file from a killed container makes munged refuse to
  # start; it is safe to remove them when no munged runs.
  rm -f /run/munge/munge.socket.2 /run/munge/munge.socket.2.lock /run/munge/munged.pid
  runuser -u munge -- munged
  say "started munged"
fi
for _ in $(seq 25); do
  munge -n </dev/null 2>/dev/null | unmunge >/dev/null 2>&1 && break
  sleep 0.2
done
munge -n </dev/null | unmunge >/dev/null || die "munge credentials do not round-trip (see /var/log/munge/munged.log)"

# ---- 4. slurm.conf ---------------------------------------------------------
node=$(hostname -s)
cpus=$(nproc)
mem_kb=$(awk '/^MemTotal:/ {print $2}' /proc/meminfo)
# Leave the system about 5 % (at least 256 MiB): slurmd drains a node that
# reports less memory than the configuration claims.
mem_mb=$((mem_kb / 1024))
spare=$((mem_mb / 20)); ((spare >= 256)) || spare=256
real_mem=$((mem_mb - spare)); ((real_mem >= 1)) || real_mem=1

# Take sockets, cores and threads from slurmd's own view of the hardware when
# it agrees with nproc (then CR_Core's "one core" really is one CPU); otherwise
# (e.g. a container restricted to some CPUs) give the CPU count alone.
topology=""
hw=$(slurmd -C 2>/dev/null | head -n1 || true)
if [[ $hw =~ CPUs=([0-9]+) ]] && [[ ${BASH_REMATCH[1]} == "$cpus" ]]; then
  for key in Boards SocketsPerBoard CoresPerSocket ThreadsPerCore; do
    [[ $hw =~ $key=([0-9]+) ]] && topology+=" $key=${BASH_REMATCH[1]}"
  done
fi

new_conf=$(cat <<EOF
$MARKER
# One node, this host; rerun the script to regenerate (hand edits are lost
# unless the first line is removed).
ClusterName=reel
SlurmctldHost=$node
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
MpiDefault=none
# No mail server here; silences slurmctld's complaint about a missing mailer.
MailProg=/bin/true

StateSaveLocation=$CTLD_STATE
SlurmdSpoolDir=$SLURMD_SPOOL
SlurmctldPidFile=$CTLD_PID
SlurmdPidFile=$SLURMD_PID
SlurmctldLogFile=$LOG_DIR/slurmctld.log
SlurmdLogFile=$LOG_DIR/slurmd.log

# No cgroups: track a job's processes through /proc, bind nothing.
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
# Don't drain the node over a CPU/topology mismatch with slurm.conf.
SlurmdParameters=config_overrides
# A node that was down comes back by itself once slurmd registers.
ReturnToService=2

SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core

# No accounting database: sacct does not work; finished jobs stay visible to
# "scontrol show job" for MinJobAge seconds.
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
JobCompType=jobcomp/none
MinJobAge=600

NodeName=$node CPUs=$cpus$topology RealMemory=$real_mem State=UNKNOWN
PartitionName=main Nodes=$node Default=YES MaxTime=INFINITE State=UP
EOF
)

install -d -m 0755 "$CONF_DIR" "$LOG_DIR" "$RUN_DIR"
install -d -m 0700 "$CTLD_STATE" "$SLURMD_SPOOL"
conf_changed=0
if [[ -e $CONF ]] && [[ $(head -n1 "$CONF") != "$MARKER" ]]; then
  say "keeping $CONF (not written by this script; remove it to let the script write one)"
elif [[ -e $CONF ]] && [[ $(cat "$CONF") == "$new_conf" ]]; then
  say "$CONF is up to date (node $node, CPUs=$cpus$topology, RealMemory=$real_mem MB)"
else
  printf '%s\n' "$new_conf" >"$CONF"
  conf_changed=1
  say "wrote $CONF (node $node, CPUs=$cpus$topology, RealMemory=$real_mem MB)"
fi
# proctrack/linuxproc and task/none read no cgroup.conf; write a harmless one
# anyway so that a slurmd that looks for it finds it (cgroups left unused).
if [[ ! -e $CONF_DIR/cgroup.conf ]]; then
  printf '%s\n%s\n' "$MARKER" 'CgroupPlugin=autodetect' >"$CONF_DIR/cgroup.conf"
  say "wrote $CONF_DIR/cgroup.conf"
fi

# ---- 5. daemons ------------------------------------------------------------
started=0
if ((conf_changed)) && { running slurmctld || running slurmd; }; then
  # "scontrol reconfigure" does not apply every change (a node's CPUs, for
  # one), so restart both; running job steps survive a slurmd restart.
  say "$CONF changed: restarting the Slurm daemons"
  stop_daemon slurmd "$SLURMD_PID"
  stop_daemon slurmctld "$CTLD_PID"
fi
if running slurmctld; then
  say "slurmctld is running"
else
  slurmctld
  started=1
  say "started slurmctld (log: $LOG_DIR/slurmctld.log)"
fi
if running slurmd; then
  say "slurmd is running"
else
  slurmd
  started=1
  say "started slurmd (log: $LOG_DIR/slurmd.log)"
fi

# Wait for the node: sinfo answers once slurmctld listens; the node turns idle
# (or mixed/allocated, if jobs already run) once slurmd has registered.
state=""
resumed=0
for i in $(seq 60); do
  state=$(timeout 5 sinfo -h -n "$node" -o %T 2>/dev/null | head -n1 || true)
  case $state in
    *'*') ;;  # a trailing * means "not responding": slurmd has not registered yet
    idle* | mixed* | allocated* | completing*) break ;;
    down* | drain* | fail*)
      # Typically left over from an earlier run (slurmd stopped, or the node
      # was marked down by hand); one resume is enough once slurmd is up.
      # Give a daemon that was just started 2 s to register first.
      if ((!resumed && (i > 4 || !started))); then
        scontrol update nodename="$node" state=resume 2>/dev/null \
          && say "node $node was $state; resumed it"
        resumed=1
      fi ;;
  esac
  sleep 0.5
done
ready=0
case $state in
  *'*') ;;  # still not responding
  idle* | mixed* | allocated* | completing*) ready=1 ;;
esac
if ((!ready)); then
  reason=$(sinfo -h -n "$node" -o %E 2>/dev/null || true)
  die "node $node is '${state:-not answering}'${reason:+ ($reason)} after 30 s; see $LOG_DIR/slurmctld.log and $LOG_DIR/slurmd.log"
fi
say "node $node is $state; partition: $(sinfo -h -o '%P %a %D %C' | head -n1) (CPUs allocated/idle/other/total)"
((started)) || say "nothing to start; all daemons were already running"
say "try: sbatch --wait --wrap hostname; stop with: $0 --stop"
