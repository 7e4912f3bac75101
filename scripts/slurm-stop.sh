#!/usr/bin/env bash
# Stops the one-node Slurm cluster that scripts/slurm-start.sh started: cancels the jobs
# left in its queue, then sends SIGTERM (SIGKILL after 20 s) to slurmd, slurmctld and
# munged, each only if the pid in its file (under GRIDPLAN_SLURM_DIR, default
# /tmp/gridplan-slurm) is alive and has the daemon's name. A munged this script did not
# start (no pid file) is left running. Exits 1 only if a daemon survives SIGKILL.
set -uo pipefail

dir=${GRIDPLAN_SLURM_DIR:-/tmp/gridplan-slurm}

alive_pid() {
    local pid
    [ -s "$1" ] || return 1
    pid=$(tr -dc '0-9' < "$1")
    [ -n "$pid" ] && [ "$(cat "/proc/$pid/comm" 2>/dev/null)" = "$2" ] || return 1
    [ "$(awk '{print $3}' "/proc/$pid/stat" 2>/dev/null)" != Z ] || return 1
    echo "$pid"
}
running() { [ -r "/proc/$1/stat" ] && [ "$(awk '{print $3}' "/proc/$1/stat" 2>/dev/null)" != Z ]; }

if alive_pid "$dir/slurmctld.pid" slurmctld > /dev/null; then
    jobs=$(timeout 10 squeue -h -o '%A' 2> /dev/null | sort -u | tr '\n' ' ')
    if [ -n "${jobs// /}" ]; then
        echo "[slurm-stop] cancelling jobs $jobs"
        # shellcheck disable=SC2086
        timeout 10 scancel $jobs 2> /dev/null || true
    fi
fi
status=0
for name in slurmd slurmctld munged; do
    if pid=$(alive_pid "$dir/$name.pid" "$name"); then
        echo "[slurm-stop] stopping $name ($pid)"
        kill -TERM "$pid" 2> /dev/null
        for _ in $(seq 40); do
            running "$pid" || break
            sleep 0.5
        done
        if running "$pid"; then
            kill -KILL "$pid" 2> /dev/null
            sleep 1
            if running "$pid"; then
                echo "[slurm-stop] $name ($pid) survives SIGKILL" >&2
                status=1
            fi
        fi
    fi
    rm -f "$dir/$name.pid"
done
exit "$status"
