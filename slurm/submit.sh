#!/usr/bin/env bash
# Submit a rhonn campaign as a Slurm job array of TASKS shards and a merge job that
# runs when every shard has succeeded. Prints the two job ids.
#
#   slurm/submit.sh TASKS SCENARIO RUNS SEED OUTDIR [more `rhonn campaign` options]
#
# The merged campaign lands in OUTDIR/merged. Extra sbatch options (partition, time,
# account) go in SBATCH_* environment variables, e.g. SBATCH_PARTITION=short.
set -euo pipefail
if [ $# -lt 5 ]; then
    echo "usage: $0 TASKS SCENARIO RUNS SEED OUTDIR [rhonn campaign options]" >&2
    exit 2
fi
tasks=$1 scenario=$2 runs=$3 seed=$4 out=$5
shift 5
here=$(cd "$(dirname "$0")" && pwd)
rhonn=${RHONN:-rhonn}
mkdir -p "$out"
array=$(sbatch --parsable --array="1-$tasks" --output="$out/shard-%a.log" \
    --export=ALL,RHONN="$rhonn" "$here/campaign.sbatch" "$scenario" "$runs" "$seed" "$out" "$@")
shards=""
for k in $(seq 1 "$tasks"); do shards="$shards $out/shard-$k"; done
merge=$(sbatch --parsable --dependency="afterok:$array" --job-name=rhonn-merge \
    --output="$out/merge.log" --wrap="'$rhonn' merge $shards --out '$out/merged'")
echo "array job $array, merge job $merge"
