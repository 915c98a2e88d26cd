#!/usr/bin/env bash
# The spread of the coupled drives' figures over seeds: the structure `rhonn benchmark`'s
# default fit chooses there (the mean of a cascade of 2 neurons, one hidden, 16 random
# starts, and a lagged RHONN na = nb = 4 trained on its free run; their specs below, as
# model.json records them) trained on both training records with 10 disjoint blocks of the
# cascade's starts (seeds 1, 1001, ..., 9001; the RHONN is deterministic), each model run
# free on both test records seeing their first 4 outputs only, as the benchmark's protocol
# asks (`--init-window 4`).
# Usage: tools/select/drives_seeds.sh [RHONN_BINARY] (default: target/release/rhonn)
set -euo pipefail
cd "$(dirname "$0")/../.."
bin=${1:-target/release/rhonn}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
data=data/benchmarks/coupled-electric-drives
for part in train test; do
    for r in 1 2; do
        gzip -dc "$data/$part.csv.gz" |
            awk -F, -v r="$r" 'NR == 1 { print "t,u,y" } $1 == r { print $3 "," $4 "," $5 }' > "$tmp/$part$r.csv"
    done
done
for k in $(seq 0 9); do
    seed=$((k * 1000 + 1))
    cat > "$tmp/spec.toml" <<SPEC
[[members]]
kind = "cascade"
na = 2
nb = 2
nk = 1
law = "simulation-error"
epochs = 30
neurons = 2
free_exponents = true
starts = 16
settle = 5
seed = $seed
[[members]]
kind = "rhonn"
na = 4
nb = 4
nk = 1
degree = 2
law = "simulation-error"
epochs = 15
nonlinear_lags = 2
SPEC
    "$bin" fit --data "$tmp/train1.csv" --data "$tmp/train2.csv" --inputs u --outputs y \
        --model "$tmp/spec.toml" --out "$tmp/m$k" > /dev/null 2>&1
    line="seed $seed:"
    for r in 1 2; do
        rms=$("$bin" predict --model "$tmp/m$k/model.json" --data "$tmp/test$r.csv" --init-window 4 \
             --out "$tmp/p$k-$r" | grep -o 'rms error [0-9.]*' | sed -n 1p)
        line="$line test $r free-run $rms;"
    done
    echo "$line"
done
