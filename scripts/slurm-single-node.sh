#!/usr/bin/env bash
# A single-node Slurm on this machine (Debian's slurm-wlm with munge), and
# ism-batch as a Slurm job array on it: bench/batch.sh with BATCH_ENGINE=slurm
# (two shards, --shard $SLURM_ARRAY_TASK_ID/$SLURM_ARRAY_TASK_COUNT), then
# the results compared with a GNU parallel run of the same batch: same lines,
# statuses, error lines and figures. Not run in CI (it starts daemons).
#
#   scripts/slurm-single-node.sh [PARALLEL_DIR]
#
# PARALLEL_DIR: the outputs of an earlier `BATCH_OUT=PARALLEL_DIR bench/batch.sh`
# to compare with; without it the GNU parallel run is made first. Needs root
# (installs packages, starts munged, slurmctld and slurmd, which it stops on
# exit). Everything else lives in $SLURM_WORK (default /tmp/ism-slurm):
# slurm.conf, state, logs, and the batch outputs (slurm/, parallel/).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
work="${SLURM_WORK:-/tmp/ism-slurm}"
parallel_dir="${1:-$work/parallel}"
if [ "$(id -u)" -ne 0 ]; then
  echo "slurm-single-node: run as root (it installs slurm-wlm and starts its daemons)" >&2
  exit 1
fi

need=()
for p in slurm-wlm munge python3 parallel; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || need+=("$p")
done
if [ ${#need[@]} -gt 0 ]; then
  echo "slurm-single-node: installing ${need[*]}" >&2
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends "${need[@]}" >/dev/null
fi

rm -rf "$work/state" "$work/spool" "$work/slurm" "$work/slurm.list" "$work"/slurm.slurm-*.log
mkdir -p "$work/state" "$work/spool" "$work/munge"
host="$(hostname -s)"
# This machine as slurmd sees it (CPUs, sockets, cores, threads, memory).
node="$(slurmd -C | head -1)"
conf="$work/slurm.conf"
cat > "$conf" <<CONF
ClusterName=ism
SlurmctldHost=$host
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CryptoType=crypto/munge
MpiDefault=none
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
ReturnToService=2
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
StateSaveLocation=$work/state
SlurmdSpoolDir=$work/spool
SlurmctldPidFile=$work/slurmctld.pid
SlurmdPidFile=$work/slurmd.pid
SlurmctldLogFile=$work/slurmctld.log
SlurmdLogFile=$work/slurmd.log
$node State=UNKNOWN
PartitionName=batch Nodes=$host Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF="$conf"

# munge: a key if there is none, and our own munged on its own socket.
if [ ! -s /etc/munge/munge.key ]; then
  mungekey --create --keyfile=/etc/munge/munge.key
  chown munge:munge /etc/munge/munge.key
  chmod 400 /etc/munge/munge.key
fi
mkdir -p /run/munge && chown munge:munge /run/munge "$work/munge"
started=()
stop() {
  # Only the daemons this script started, by the process ids they recorded.
  for pidfile in "${started[@]}"; do
    [ -s "$pidfile" ] && kill "$(cat "$pidfile")" 2>/dev/null || true
  done
}
trap stop EXIT
if ! munge -n </dev/null >/dev/null 2>&1; then
  runuser -u munge -- /usr/sbin/munged --pid-file="$work/munge/munged.pid" \
    --log-file="$work/munge/munged.log" --seed-file="$work/munge/munged.seed"
  started+=("$work/munge/munged.pid")
fi
munge -n </dev/null | unmunge >/dev/null

slurmctld -f "$conf"
started+=("$work/slurmctld.pid")
slurmd -f "$conf"
started+=("$work/slurmd.pid")
for _ in $(seq 60); do
  if sinfo -h -N -o '%T' 2>/dev/null | grep -q idle; then break; fi
  sleep 1
done
sinfo -N -o '%N %c %m %T' >&2
sinfo -h -N -o '%T' | grep -q idle || { echo "slurm-single-node: the node did not come up (see $work/*.log)" >&2; exit 1; }

if [ ! -s "$parallel_dir/results.jsonl" ]; then
  echo "slurm-single-node: GNU parallel run into $parallel_dir" >&2
  BATCH_OUT="$parallel_dir" "$root/bench/batch.sh" > "$parallel_dir.md"
fi
echo "slurm-single-node: job array into $work/slurm" >&2
BATCH_ENGINE=slurm BATCH_OUT="$work/slurm" "$root/bench/batch.sh" > "$work/slurm.md"
cat "$work/slurm.md"
python3 "$root/bench/batch_results.py" compare "$parallel_dir" "$work/slurm"
