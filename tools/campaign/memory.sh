#!/bin/bash
# The memory and time of `rhonn campaign` as the number of runs grows: a campaign of a
# two-tanks scenario of 2 s in open loop (each run a few microseconds, so that the rows,
# not the runs, are what is measured), for each number of runs given (default 1,000,
# 100,000 and 1,000,000). Prints one line per number: runs, maximum resident memory and
# wall time (GNU time), and the same for the binary in RHONN_BEFORE when it is set (side
# by side in one run). Needs /usr/bin/time; build first with `cargo build --release`.
set -euo pipefail
here="$(cd "$(dirname "$0")/../.." && pwd)"
bin="${RHONN_BIN:-$here/target/release/rhonn}"
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT
cat > "$out/memory.toml" <<'TOML'
name = "memory"
description = "two tanks, 2 s in open loop: a campaign's memory bench"
duration_s = 2.0
output_interval_s = 1.0

[plant]
kind = "tanks"
initial = [100.0, 100.0]

[input]
voltage = { kind = "constant", value = 5.0 }
TOML
measure() {
    /usr/bin/time -o "$out/time" -f "%M %e" "$1" campaign "$out/memory.toml" --runs "$2" \
        --envelope-runs 0 --out "$out/c" > /dev/null 2>&1
    rm -rf "$out/c"
    read -r kb s < "$out/time"
    echo "$(echo "scale=1; $kb / 1024" | bc) | $s"
}
if [ -n "${RHONN_BEFORE:-}" ]; then
    echo "runs | max resident [MB] | wall [s] | before: max resident [MB] | wall [s]"
else
    echo "runs | max resident [MB] | wall [s]"
fi
for n in ${@:-1000 100000 1000000}; do
    line="$n | $(measure "$bin" "$n")"
    if [ -n "${RHONN_BEFORE:-}" ]; then
        line="$line | $(measure "$RHONN_BEFORE" "$n")"
    fi
    echo "$line"
done
