#!/usr/bin/env bash
# A real one-node Slurm cluster on this machine, for the array-job test in tests/dataset.rs
# (docs/datasets.md "Settling"). `make setup` installs Debian's `slurm-wlm munge`;
# `make test` runs `up` before the tests and `down` after them (also when a test fails).
#
#   scripts/slurm_local.sh up      # munge key, slurm.conf, munged, slurmctld, slurmd; waits for `idle`
#   scripts/slurm_local.sh down    # stops the daemons `up` started, by their recorded PIDs
#   scripts/slurm_local.sh status  # what answers, and what `up` started
#
# Both are idempotent: a second `up` finds the cluster answering and starts nothing; `down` with
# nothing recorded stops nothing. A cluster this script did not start (a `sinfo` that answers, a
# slurm.conf without this script's marker line, a munged already serving) is used as it is and
# never stopped. Needs root (re-runs itself with sudo otherwise).
#
# The cluster: `SlurmctldHost` and one node named `hostname -s` at 127.0.0.1 with `nproc` CPUs and
# 90% of MemTotal, one default partition, munge authentication, `proctrack/linuxproc` and
# `task/none` (no cgroups needed), `select/cons_tres` with `CR_Core` (one task per core), and
# `ReturnToService=2` (a node that was down comes back by itself).
set -euo pipefail

if [ "$(id -u)" != 0 ]; then
    exec sudo --preserve-env=BLOCKWORLD_SLURM_STATE "$0" "$@"
fi

state=${BLOCKWORLD_SLURM_STATE:-/run/blockworld-slurm}
pids=$state/pids # lines "NAME PID", one per daemon `up` started
conf=/etc/slurm/slurm.conf
marker="# Written by blockworld scripts/slurm_local.sh (up rewrites only a file with this line)."
node=$(hostname -s)

say() { echo "slurm_local: $*"; }

# Whether a controller answers. Without a slurm.conf no client can reach one; with this script's
# own slurm.conf, only while the slurmctld of its PID file runs; else ask, for at most 5 s (a
# client retries an absent controller for about 10 s).
cluster_answers() {
    [ -f "$conf" ] || [ -n "${SLURM_CONF:-}" ] || return 1
    if grep -qxF "$marker" "$conf" 2>/dev/null; then
        running slurmctld "$(cat /run/slurmctld.pid 2>/dev/null)" || return 1
    fi
    [ -n "$(timeout 5 sinfo -h -o %t 2>/dev/null)" ]
}

# Whether process PID runs program NAME (not a later process that reuses the PID).
running() { [ -n "$2" ] && [ "$(cat "/proc/$2/comm" 2>/dev/null)" = "$1" ]; }

munge_serves() { munge -n 2>/dev/null | unmunge >/dev/null 2>&1; }

# Records a daemon that `up` started, from the PID file it wrote when it went into background.
record() {
    local name=$1 pidfile=$2 i
    for i in $(seq 50); do
        [ -s "$pidfile" ] && break
        sleep 0.1
    done
    [ -s "$pidfile" ] || { say "$name wrote no PID file $pidfile; see /var/log/slurm and /var/log/munge"; exit 1; }
    echo "$name $(tr -d '[:space:]' <"$pidfile")" >>"$pids"
}

write_munge_key() {
    if [ -f /etc/munge/munge.key ]; then return; fi
    say "writing a new munge key /etc/munge/munge.key"
    mkdir -p /etc/munge
    dd if=/dev/urandom of=/etc/munge/munge.key bs=1024 count=1 status=none
    chown munge:munge /etc/munge/munge.key
    chmod 400 /etc/munge/munge.key
}

write_conf() {
    if [ -f "$conf" ] && ! grep -qxF "$marker" "$conf"; then
        say "$conf was not written by this script and no cluster answers sinfo;"
        say "start that cluster yourself, or move $conf away and run up again"
        exit 1
    fi
    local cpus mem_mb
    cpus=$(nproc)
    mem_mb=$(awk '/^MemTotal:/ { print int($2 / 1024 * 0.9) }' /proc/meminfo)
    mkdir -p /etc/slurm /var/spool/slurmctld /var/spool/slurmd /var/log/slurm
    cat >"$conf.tmp" <<EOF
$marker
ClusterName=blockworld
SlurmctldHost=$node(127.0.0.1)
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
MpiDefault=none
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
ReturnToService=2
KillWait=5
StateSaveLocation=/var/spool/slurmctld
SlurmdSpoolDir=/var/spool/slurmd
SlurmctldPidFile=/run/slurmctld.pid
SlurmdPidFile=/run/slurmd.pid
SlurmctldLogFile=/var/log/slurm/slurmctld.log
SlurmdLogFile=/var/log/slurm/slurmd.log
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
NodeName=$node NodeAddr=127.0.0.1 CPUs=$cpus RealMemory=$mem_mb State=UNKNOWN
PartitionName=debug Nodes=$node Default=YES MaxTime=INFINITE State=UP
EOF
    mv "$conf.tmp" "$conf"
}

start_munged() {
    if munge_serves; then
        say "munged already serves; using it"
        return
    fi
    mkdir -p /run/munge /var/log/munge /var/lib/munge
    chown -R munge:munge /run/munge /var/log/munge /var/lib/munge
    rm -f /run/munge/munged.pid
    # As the munge user, as Debian runs it: the key and /run/munge are its own.
    runuser -u munge -- munged
    record munged /run/munge/munged.pid
}

wait_idle() {
    local i t
    for i in $(seq 120); do
        t=$(sinfo -h -n "$node" -o %t 2>/dev/null || true)
        case $t in
        # Exactly: a trailing `*` (e.g. `idle*`) means slurmd has not answered yet.
        idle | mix | alloc) say "node $node is $t after $(((i - 1) * 250)) ms"; return ;;
        down* | drain*) scontrol update NodeName="$node" State=RESUME >/dev/null 2>&1 || true ;;
        esac
        sleep 0.25
    done
    say "node $node did not become idle in 30 s (sinfo: ${t:-no answer}); see /var/log/slurm"
    exit 1
}

up() {
    for bin in munged slurmctld slurmd sinfo sbatch; do
        command -v "$bin" >/dev/null || { say "$bin is not installed; run make setup"; exit 1; }
    done
    if cluster_answers; then
        if [ -s "$pids" ]; then say "already up (PIDs in $pids)"; else say "a Slurm cluster already answers; using it, starting nothing"; fi
        wait_idle
        return
    fi
    mkdir -p "$state"
    if [ -s "$pids" ]; then
        say "stale record $pids from an earlier up; stopping what is left of it first"
        down
        mkdir -p "$state"
    fi
    write_munge_key
    write_conf
    start_munged
    rm -f /run/slurmctld.pid /run/slurmd.pid
    slurmctld
    record slurmctld /run/slurmctld.pid
    slurmd
    record slurmd /run/slurmd.pid
    wait_idle
    say "started $(tr '\n' ' ' <"$pids")(record $pids)"
}

# Stops one recorded daemon: TERM, up to 10 s, then KILL; only when the PID still runs that program.
stop() {
    local name=$1 pid=$2 i
    if ! running "$name" "$pid"; then
        say "$name (pid $pid) is no longer running"
        return
    fi
    kill -TERM "$pid"
    for i in $(seq 100); do
        [ -e "/proc/$pid" ] || { say "stopped $name (pid $pid)"; return; }
        sleep 0.1
    done
    kill -KILL "$pid" 2>/dev/null || true
    say "killed $name (pid $pid) after 10 s"
}

down() {
    if [ ! -s "$pids" ]; then
        say "nothing to stop (no daemons recorded in $pids)"
        return
    fi
    # The reverse order of starting: slurmd, slurmctld, munged.
    tac "$pids" | while read -r name pid; do stop "$name" "$pid"; done
    rm -f "$pids"
}

status() {
    if cluster_answers; then sinfo; else say "no Slurm cluster answers sinfo"; fi
    if [ -s "$pids" ]; then say "started by up: $(tr '\n' ' ' <"$pids")"; else say "nothing recorded in $pids"; fi
}

case ${1:-} in
up) up ;;
down) down ;;
status) status ;;
*)
    echo "usage: $0 up|down|status" >&2
    exit 2
    ;;
esac
