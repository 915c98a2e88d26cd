#!/usr/bin/env bash
# Integration test of the Slurm job array on a real one-node Slurm on loopback:
# installs Debian's slurm-wlm and munge if missing, makes a munge key, writes a minimal
# slurm.conf (proctrack/linuxproc, task/none, no cgroup.conf), starts munged, slurmctld
# and slurmd, submits a 4-task array campaign with slurm/submit.sh, waits for it and
# its merge job, and compares the merged campaign with the same campaign run on this
# machine: runs.csv, traces.csv, envelope.csv and summary.json must be identical.
#
# Needs root (packages, daemons); otherwise it prints why it skips and exits 0.
# .ci/run calls it. Usage: slurm/test-one-node.sh [path/to/rhonn]
set -euo pipefail
if [ "$(id -u)" != 0 ]; then
    echo "SKIP slurm integration test: not root (it installs slurm-wlm and munge and starts their daemons)"
    exit 0
fi
cd "$(dirname "$0")/.."
repo=$(pwd)
rhonn=$(realpath "${1:-target/release/rhonn}")
[ -x "$rhonn" ] || { echo "no rhonn binary at $rhonn: cargo build --release first" >&2; exit 1; }

if ! command -v sbatch >/dev/null || ! command -v munged >/dev/null; then
    echo "installing slurm-wlm and munge"
    export DEBIAN_FRONTEND=noninteractive
    apt-get update -qq >/dev/null
    apt-get install -y -qq --no-install-recommends slurm-wlm munge >/dev/null
fi

work=$(mktemp -d /tmp/rhonn-slurm.XXXXXX)
chmod 755 "$work"
cleanup() {
    for p in slurmd slurmctld munged; do
        [ -f "$work/$p.pid" ] && kill "$(cat "$work/$p.pid")" 2>/dev/null || true
    done
    sleep 1
    rm -rf "$work"
}
trap cleanup EXIT

# munge: a fresh key and a daemon with its own socket.
mkdir -p "$work/munge"
dd if=/dev/urandom of="$work/munge/munge.key" bs=1024 count=1 status=none
chown -R munge:munge "$work/munge" 2>/dev/null || true
chmod 700 "$work/munge"
chmod 400 "$work/munge/munge.key"
sock="$work/munge/munge.socket"
runuser -u munge -- munged --key-file="$work/munge/munge.key" --socket="$sock" \
    --pid-file="$work/munge/munged.pid" --log-file="$work/munge/munged.log" \
    --seed-file="$work/munge/munge.seed" --force
cp "$work/munge/munged.pid" "$work/munged.pid"

host=$(hostname -s)
cpus=$(nproc)
mkdir -p "$work/state" "$work/spool" "$work/logs" "$work/out"
cat > "$work/slurm.conf" <<CONF
ClusterName=rhonn-test
SlurmctldHost=$host(127.0.0.1)
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket=$sock
CredType=cred/munge
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
MpiDefault=none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
ReturnToService=2
StateSaveLocation=$work/state
SlurmdSpoolDir=$work/spool
SlurmctldPidFile=$work/slurmctld.pid
SlurmdPidFile=$work/slurmd.pid
SlurmctldLogFile=$work/logs/slurmctld.log
SlurmdLogFile=$work/logs/slurmd.log
SlurmctldPort=16817
SlurmdPort=16818
NodeName=$host NodeAddr=127.0.0.1 CPUs=$cpus State=UNKNOWN
PartitionName=test Nodes=$host Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF="$work/slurm.conf"
slurmctld -f "$SLURM_CONF"
slurmd -f "$SLURM_CONF"

# Wait for the node to be idle.
for _ in $(seq 1 60); do
    state=$(sinfo -h -o %t 2>/dev/null || true)
    [ "$state" = idle ] && break
    sleep 1
done
if [ "$state" != idle ]; then
    echo "FAIL: the Slurm node did not come up (state '$state')" >&2
    tail -20 "$work/logs/slurmctld.log" "$work/logs/slurmd.log" >&2 || true
    exit 1
fi
echo "one-node Slurm up: $(sinfo -h -o '%P %D %c %t')"

scenario=control-adaptive runs=24 seed=11
ids=$(RHONN="$rhonn" "$repo/slurm/submit.sh" 4 "$scenario" "$runs" "$seed" "$work/out/array")
echo "$ids"
merge_id=${ids##* }
# Wait for the merge job (it runs after every shard succeeded) to leave the queue.
for _ in $(seq 1 600); do
    squeue -h -j "$merge_id" 2>/dev/null | grep -q . || break
    sleep 1
done
if [ ! -f "$work/out/array/merged/runs.csv" ]; then
    echo "FAIL: no merged campaign" >&2
    cat "$work"/out/array/*.log >&2 || true
    squeue >&2 || true
    tail -20 "$work/logs/slurmctld.log" >&2 || true
    exit 1
fi
for k in 1 2 3 4; do
    n=$(($(wc -l < "$work/out/array/shard-$k/runs.csv") - 1))
    echo "shard $k: $n runs"
done

"$rhonn" campaign "$scenario" --runs "$runs" --seed "$seed" --out "$work/out/single" 2>/dev/null
for f in runs.csv traces.csv envelope.csv summary.json; do
    if ! cmp -s "$work/out/single/$f" "$work/out/array/merged/$f"; then
        echo "FAIL: $f of the Slurm array differs from the single-machine campaign" >&2
        diff "$work/out/single/$f" "$work/out/array/merged/$f" | head -5 >&2
        exit 1
    fi
done
echo "PASS slurm integration test: a 4-task array campaign of $scenario ($runs runs) merged to the single-machine result"
