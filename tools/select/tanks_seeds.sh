#!/usr/bin/env bash
# The spread of the cascaded-tanks figure over seeds: models/cascaded-tanks.toml trained on
# estimation.csv with 10 disjoint blocks of random starts (seeds 1, 1001, ..., 9001; each
# run draws its 64 starts from seed, seed + 1, ...), each model run free once on
# validation.csv. Usage: tools/select/tanks_seeds.sh [RHONN_BINARY] (default: target/release/rhonn)
set -euo pipefail
cd "$(dirname "$0")/../.."
bin=${1:-target/release/rhonn}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
for k in $(seq 0 9); do
    seed=$((k * 1000 + 1))
    { grep -v '^seed' models/cascaded-tanks.toml; echo "seed = $seed"; } > "$tmp/spec.toml"
    "$bin" fit --data data/cascaded-tanks/estimation.csv --inputs u --outputs y \
        --model "$tmp/spec.toml" --out "$tmp/m$k" > /dev/null 2>&1
    rms=$("$bin" predict --model "$tmp/m$k/model.json" --data data/cascaded-tanks/validation.csv \
        --out "$tmp/p$k" | grep -o 'rms error [0-9.]*' | sed -n 1p)
    echo "seed $seed: free-run $rms V"
done
