# A one-node Slurm cluster on 127.0.0.1 from Debian's packages (munge, slurm-wlm), everything in a
# scratch folder: its own munge key and socket, a minimal slurm.conf, state, spool, logs and pids.
# Sourced; cluster_start DIR starts munged, slurmctld and slurmd (exported SLURM_CONF points the
# clients at it); cluster_stop stops them by their pids (the caller's EXIT trap).
cluster_pids=()

free_port() { python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'; }

cluster_start() {
    local d=$1 cpus=${2:-2}
    mkdir -p "$d/munge" "$d/state" "$d/spool"
    chmod 700 "$d/munge"
    head -c 1024 /dev/urandom >"$d/munge/munge.key"
    chmod 400 "$d/munge/munge.key"
    munged --force --key-file="$d/munge/munge.key" --socket="$d/munge/socket" --pid-file="$d/munge/munged.pid" \
        --log-file="$d/munge/munged.log" --seed-file="$d/munge/seed" || return 1
    cluster_pids+=("$(cat "$d/munge/munged.pid")")
    cat >"$d/slurm.conf" <<CONF
ClusterName=firmament-test
SlurmctldHost=localhost(127.0.0.1)
SlurmctldPort=$(free_port)
SlurmdPort=$(free_port)
SlurmUser=$(id -un)
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket=$d/munge/socket
CredType=cred/munge
StateSaveLocation=$d/state
SlurmdSpoolDir=$d/spool
SlurmctldPidFile=$d/slurmctld.pid
SlurmdPidFile=$d/slurmd.pid
SlurmctldLogFile=$d/slurmctld.log
SlurmdLogFile=$d/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SchedulerType=sched/builtin
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
ReturnToService=2
MpiDefault=none
SwitchType=switch/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
KillWait=10
NodeName=fmnode NodeHostname=$(hostname) NodeAddr=127.0.0.1 CPUs=$cpus State=UNKNOWN
PartitionName=test Nodes=fmnode Default=YES MaxTime=INFINITE State=UP
CONF
    export SLURM_CONF=$d/slurm.conf
    slurmctld -D -i -f "$SLURM_CONF" >"$d/slurmctld.out" 2>&1 &
    cluster_pids+=($!)
    slurmd -D -N fmnode -f "$SLURM_CONF" >"$d/slurmd.out" 2>&1 &
    cluster_pids+=($!)
    # up when the node is idle
    for _ in $(seq 1 100); do
        sinfo -h -N -o %t 2>/dev/null | grep -q '^idle' && return 0
        sleep 0.2
    done
    echo "the cluster did not come up:"; tail -5 "$d/slurmctld.log" "$d/slurmd.log" "$d/slurmd.out" 2>/dev/null
    return 1
}

cluster_stop() {
    local p
    for p in "${cluster_pids[@]}"; do kill "$p" 2>/dev/null; done
    for p in "${cluster_pids[@]}"; do
        for _ in $(seq 1 50); do kill -0 "$p" 2>/dev/null || break; sleep 0.1; done
        kill -9 "$p" 2>/dev/null
    done
    cluster_pids=()
}

# cluster_wait JOBID [SECONDS]: until no task of the job is pending or running
cluster_wait() {
    local id=$1 limit=${2:-900}
    for _ in $(seq 1 $((limit * 5))); do
        [ -z "$(squeue -h -j "$id" -o %i 2>/dev/null)" ] && return 0
        sleep 0.2
    done
    return 1
}
