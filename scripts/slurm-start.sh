#!/usr/bin/env bash
# Starts a one-node Slurm cluster on this machine for the Slurm test (CI's `== slurm`
# block), without systemd: munged, slurmctld and slurmd are started by hand.
#
# - Installs slurmctld, slurmd, slurm-client and munge with apt-get when a command is
#   missing (no Recommends), with a temporary /usr/sbin/policy-rc.d that forbids the
#   packages' init scripts from starting daemons during the install.
# - Writes a one-node /etc/slurm/slurm.conf (the path sbatch reads by default; a file
#   not written by this script is saved as slurm.conf.bak.<time> first).
# - Starts the daemons detached (setsid, no inherited stdin/stdout, so a caller's pipe
#   closes), and waits until the node is idle, within GRIDPLAN_SLURM_TIMEOUT seconds.
# Exits 0 only when the cluster takes jobs; else 1 with the daemons' last log lines.
# Needs root. Stop with scripts/slurm-stop.sh (same GRIDPLAN_SLURM_DIR).
#
# Environment: GRIDPLAN_SLURM_DIR (state, logs, pid files; /tmp/gridplan-slurm),
# GRIDPLAN_SLURM_TIMEOUT (seconds per wait; 60).
set -euo pipefail

dir=${GRIDPLAN_SLURM_DIR:-/tmp/gridplan-slurm}
timeout_s=${GRIDPLAN_SLURM_TIMEOUT:-60}
conf=/etc/slurm/slurm.conf
mark="# written by gridplan scripts/slurm-start.sh"
host=$(hostname -s)
t0=$(date +%s)

say() { echo "[slurm-start +$(( $(date +%s) - t0 ))s] $*"; }
fail() {
    echo "[slurm-start] error: $*" >&2
    for log in "$dir/log/slurmctld.log" "$dir/log/slurmd.log" "$dir/log/munged.out"; do
        if [ -s "$log" ]; then echo "--- $log (last lines)" >&2; tail -n 12 "$log" >&2; fi
    done
    exit 1
}
# The pid in pid file $1 if that process is alive, not a zombie (PID 1 here may reap
# late), and named $2.
alive_pid() {
    local pid
    [ -s "$1" ] || return 1
    pid=$(tr -dc '0-9' < "$1")
    [ -n "$pid" ] && [ "$(cat "/proc/$pid/comm" 2>/dev/null)" = "$2" ] || return 1
    [ "$(awk '{print $3}' "/proc/$pid/stat" 2>/dev/null)" != Z ] || return 1
    echo "$pid"
}
# until SECONDS WHAT COMMAND...: retries COMMAND every 0.5 s.
until_ok() {
    local end=$(( $(date +%s) + $1 )) what=$2
    shift 2
    until "$@" > /dev/null 2>&1; do
        [ "$(date +%s)" -lt "$end" ] || fail "timed out waiting for $what"
        sleep 0.5
    done
}

[ "$(id -u)" = 0 ] || fail "needs root (it installs packages and starts daemons)"
mkdir -p "$dir/log" "$dir/state" "$dir/spool"

missing=0
for command in munged munge unmunge slurmctld slurmd sbatch squeue sinfo scontrol; do
    command -v "$command" > /dev/null 2>&1 || missing=1
done
if [ "$missing" = 1 ]; then
    say "installing slurmctld slurmd slurm-client munge"
    policy=/usr/sbin/policy-rc.d
    own_policy=0
    if [ ! -e "$policy" ]; then
        printf '#!/bin/sh\n# gridplan slurm-start.sh: no daemon starts during the install.\nexit 101\n' > "$policy"
        chmod 755 "$policy"
        own_policy=1
        trap 'rm -f "$policy"' EXIT
    fi
    export DEBIAN_FRONTEND=noninteractive
    apt-get update -qq > "$dir/log/apt.log" 2>&1 || { tail -n 20 "$dir/log/apt.log" >&2; fail "apt-get update"; }
    apt-get install -y -qq --no-install-recommends slurmctld slurmd slurm-client munge \
        >> "$dir/log/apt.log" 2>&1 || { tail -n 20 "$dir/log/apt.log" >&2; fail "apt-get install"; }
    if [ "$own_policy" = 1 ]; then rm -f "$policy"; trap - EXIT; fi
fi

# munge: a key, its directories, and the daemon (an already working munged is used).
if [ ! -s /etc/munge/munge.key ]; then
    mkdir -p /etc/munge
    if command -v mungekey > /dev/null; then
        mungekey --create --keyfile=/etc/munge/munge.key --force
    else
        dd if=/dev/urandom of=/etc/munge/munge.key bs=1024 count=1 status=none
    fi
fi
for d in /etc/munge /run/munge /var/log/munge /var/lib/munge; do
    mkdir -p "$d"
    chown munge:munge "$d"
done
chown munge:munge /etc/munge/munge.key
chmod 0700 /etc/munge
chmod 0400 /etc/munge/munge.key
chmod 0755 /run/munge
munge_works() { munge -n | unmunge; }
if ! munge_works > /dev/null 2>&1; then
    say "starting munged"
    rm -f "$dir/munged.pid"
    # --force: a killed munged may have left its socket.
    runuser -u munge -- setsid /usr/sbin/munged --force < /dev/null >> "$dir/log/munged.out" 2>&1 \
        || fail "munged did not start"
    until_ok "$timeout_s" "munged" munge_works
    cp /run/munge/munged.pid "$dir/munged.pid"
fi

# One node with the layout slurmd detects (a mismatch drains it), all on 127.0.0.1.
layout=$(slurmd -C 2>/dev/null | head -n 1 || true)
field() { sed -n "s/.*[[:space:]]$1=\([0-9]*\).*/\1/p" <<< "$layout"; }
cpus=$(field CPUs)
cpus=${cpus:-$(nproc)}
topology=""
if [ -n "$(field CoresPerSocket)" ]; then
    topology="Boards=$(field Boards) SocketsPerBoard=$(field SocketsPerBoard) CoresPerSocket=$(field CoresPerSocket) ThreadsPerCore=$(field ThreadsPerCore)"
fi
memory=$(( $(free -m | awk '/^Mem:/ {print $2}') * 9 / 10 ))
cat > "$dir/slurm.conf" <<EOF
$mark ($dir)
ClusterName=gridplan
SlurmctldHost=$host(127.0.0.1)
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
MpiDefault=none
SwitchType=switch/none
# No cgroups in a container: plain process tracking, no task plugin.
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/filetxt
JobCompLoc=$dir/log/jobcomp.log
# Finished jobs stay visible to scontrol (and to afterok) for an hour.
MinJobAge=3600
# A job whose afterok dependency can never hold is cancelled, not left pending
# (this key, not SchedulerParameters, since Slurm 20.11).
DependencyParameters=kill_invalid_depend
# Start pending array tasks at once, not in waves 3 s apart.
SchedulerParameters=batch_sched_delay=0
ReturnToService=2
MailProg=/bin/true
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/log/slurmctld.log
SlurmdLogFile=$dir/log/slurmd.log
NodeName=$host NodeAddr=127.0.0.1 CPUs=$cpus $topology RealMemory=$memory State=UNKNOWN
PartitionName=debug Nodes=ALL Default=YES MaxTime=INFINITE State=UP
EOF
mkdir -p /etc/slurm
if [ -f "$conf" ] && ! grep -qF "$mark" "$conf"; then
    backup="$conf.bak.$(date +%Y%m%d%H%M%S)"
    say "saving the existing $conf as $backup"
    cp -p "$conf" "$backup"
fi
changed=0
if ! cmp -s "$dir/slurm.conf" "$conf"; then
    cp "$dir/slurm.conf" "$conf"
    chmod 644 "$conf"
    changed=1
fi

ctld_answers() {
    alive_pid "$dir/slurmctld.pid" slurmctld > /dev/null || fail "slurmctld died (see its log)"
    scontrol ping 2> /dev/null | grep -q UP
}
start() {
    local name=$1
    shift
    if alive_pid "$dir/$name.pid" "$name" > /dev/null; then
        return 0
    fi
    say "starting $name"
    rm -f "$dir/$name.pid"
    setsid "$name" "$@" < /dev/null >> "$dir/log/$name.out" 2>&1 || fail "$name exited at start"
    until_ok "$timeout_s" "$name's pid file" alive_pid "$dir/$name.pid" "$name"
}
if [ "$changed" = 1 ] && alive_pid "$dir/slurmctld.pid" slurmctld > /dev/null; then
    scontrol reconfigure || true
fi
# -c: start without the jobs of an earlier run; -i: ignore state it cannot read.
start slurmctld -c -i
until_ok "$timeout_s" "slurmctld to answer scontrol ping" ctld_answers
start slurmd

say "waiting for node $host to be idle"
end=$(( $(date +%s) + timeout_s ))
while :; do
    state=$(sinfo -h -N -n "$host" -o '%T' 2> /dev/null | head -n 1 || true)
    case "$state" in
        idle | mixed | allocated | completing) break ;;
        down* | drain* | fail*) scontrol update nodename="$host" state=resume > /dev/null 2>&1 || true ;;
    esac
    alive_pid "$dir/slurmctld.pid" slurmctld > /dev/null || fail "slurmctld died"
    alive_pid "$dir/slurmd.pid" slurmd > /dev/null || fail "slurmd died"
    [ "$(date +%s)" -lt "$end" ] || fail "node $host is '${state:-unknown}' after ${timeout_s}s"
    sleep 1
done
say "node $host is $state: the cluster takes jobs"
