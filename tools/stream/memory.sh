#!/bin/bash
# The memory and time of `rhonn identify --stream` as the stream grows: a simulated
# nonlinear system (y[k+1] = 0.8 y + 0.3 u + 0.4 u tanh(2 y), u a held sine every 9
# samples), generated line by line and piped into the command (the bank, open-ended),
# for each length given (default 1 and 10 million samples). Prints one line per length:
# samples, maximum resident memory and wall time (GNU time). Needs python3 and
# /usr/bin/time; build first with `cargo build --release`.
set -euo pipefail
here="$(cd "$(dirname "$0")/../.." && pwd)"
bin="${RHONN_BIN:-$here/target/release/rhonn}"
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT
gen() {
    python3 - "$1" <<'PY'
import math, sys
n = int(sys.argv[1])
sys.stdout.write("t,u,y\n")
y = u = 0.0
rows = []
for k in range(n):
    if k % 9 == 0:
        u = 2.0 * math.sin(0.37 * k)
    rows.append(f"{k * 0.1:.1f},{u:.6f},{y:.6f}\n")
    y = 0.8 * y + 0.3 * u + 0.4 * u * math.tanh(2 * y)
    if len(rows) == 10000:
        sys.stdout.write("".join(rows))
        rows = []
sys.stdout.write("".join(rows))
PY
}
echo "samples | max resident [MB] | wall [s]"
for n in "${@:-1000000 10000000}"; do
    for m in $n; do
        gen "$m" | /usr/bin/time -o "$out/time" -f "%M %e" "$bin" identify --stream --inputs u --outputs y \
            --every "$m" --out "$out/s$m" > /dev/null 2>&1
        read -r kb s < "$out/time"
        echo "$m | $(echo "scale=1; $kb / 1024" | bc) | $s"
    done
done
