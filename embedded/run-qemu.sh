#!/usr/bin/env bash
# Build the firmware (the pump's RHONN adaptive pressure controller and rhonn-core's general
# online identifier, FixedOnline, against a discretised pump: 2,000 periods of 5 ms) three ways and
# run each in QEMU: on an emulated Cortex-M4F (mps2-an386, single-precision FPU) with the
# controller in f32 and in f64 (done in software there), and on a Cortex-M7 (mps2-an500,
# double-precision FPU) in f64. Run the same loop on the host (rhonn-core built without
# std, as on the target) in both precisions and compare every printed value and the
# digest of every value of every period. Prints `bit-identical: yes` and a table of
# flash, static RAM and instructions per control step, the controller's and the
# identifier's apart (QEMU -icount shift=0: one
# instruction per nanosecond of virtual time, read with SysTick and calibrated on 20,000
# nops). Fails (non-zero) when an output differs from the host's, QEMU fails, flash > 64
# KiB or static RAM and stack > 8 KiB, or the Cortex-M4F's f32 step exceeds 20,000 instructions.
# Needs: rustup target thumbv7em-none-eabihf, Debian's qemu-system-arm, python3.
set -euo pipefail
cd "$(dirname "$0")"
target=thumbv7em-none-eabihf
if ! rustup target list --installed 2>/dev/null | grep -qx "$target"; then
    echo "run-qemu.sh: the Rust target $target is missing: rustup target add $target" >&2
    exit 2
fi
if ! command -v qemu-system-arm >/dev/null; then
    echo "run-qemu.sh: qemu-system-arm is missing: apt-get install qemu-system-arm" >&2
    exit 2
fi
out=target/qemu
mkdir -p "$out"
cargo build --release --locked --features host --bin host -q
cp target/release/host "$out/host-f64"
cargo build --release --locked --features host,single --bin host -q
cp target/release/host "$out/host-f32"
"$out/host-f64" > "$out/host-f64.txt"
"$out/host-f32" > "$out/host-f32.txt"
build() { # name cpu features
    RUSTFLAGS="-C target-cpu=$2" CARGO_TARGET_DIR="target/$1" \
        cargo build --release --locked --target "$target" --features "$3" --bin firmware -q
    cp "target/$1/$target/release/firmware" "$out/$1.elf"
}
build m4-f32 cortex-m4 target,single
build m4-f64 cortex-m4 target
build m7-f64 cortex-m7 target
run() { # name machine cpu
    if ! timeout 300 qemu-system-arm -machine "$2" -cpu "$3" -nographic -monitor none \
        -semihosting-config enable=on,target=native -icount shift=0 -kernel "$out/$1.elf" > "$out/$1.txt" 2>&1; then
        echo "run-qemu.sh: the firmware failed on $2 ($3):" >&2
        cat "$out/$1.txt" >&2
        exit 1
    fi
}
run m4-f32 mps2-an386 cortex-m4
run m4-f64 mps2-an386 cortex-m4
run m7-f64 mps2-an500 cortex-m7
same=yes
for name in m4-f32 m4-f64 m7-f64; do
    host="$out/host-${name#*-}.txt"
    if ! diff <(grep -v -e '^instructions_per_step' -e '^controller_instructions' -e '^identifier_instructions' -e '^stack_bytes' "$out/$name.txt") "$host" > "$out/$name.diff"; then
        same=no
        echo "run-qemu.sh: $name differs from the host:" >&2
        head -20 "$out/$name.diff" >&2
    fi
done
lines=$(wc -l < "$out/host-f64.txt")
echo "compared: $lines lines per run (every 100th period's values and their bits, a digest of every value of all 2,000 periods, the regulation figures), each firmware against the host build of the same precision"
grep -e '^regulation' -e '^online_identifier' "$out/host-f64.txt" | sed 's/^/f64 /'
grep -e '^regulation' -e '^online_identifier' "$out/host-f32.txt" | sed 's/^/f32 /'
echo "bit-identical: $same"
[ "$same" = yes ] || exit 1
python3 - "$out" <<'PY'
import re, subprocess, sys
out = sys.argv[1]
def size(elf):
    r = subprocess.run(["python3", "elf_size.py", elf], capture_output=True, text=True, check=True)
    return dict(kv.split("=") for kv in r.stdout.split())
def steps(name):
    text = open(f"{out}/{name}.txt").read()
    count = lambda what: tuple(int(v) for v in re.search(what + r" mean=(\d+) max=(\d+)", text).groups())
    stack = re.search(r"stack_bytes=(\d+)", text)
    return count("instructions_per_step"), count("controller_instructions"), count("identifier_instructions"), int(stack.group(1))
rows = []
ok = True
for key, name in [("m4-f32", "Cortex-M4F (mps2-an386), controller in f32 (FPU)"),
                  ("m4-f64", "Cortex-M4F (mps2-an386), controller in f64 (software)"),
                  ("m7-f64", "Cortex-M7 (mps2-an500), controller in f64 (FPU)")]:
    s = size(f"{out}/{key}.elf")
    flash, ram = int(s["flash_bytes"]), int(s["ram_bytes"])
    (mean, worst), ctl, ident, stack = steps(key)
    rows.append((name, flash, ram, stack, mean, worst, ctl, ident))
    ok &= flash <= 64 * 1024 and ram + stack <= 8 * 1024
    if key == "m4-f32":
        ok &= worst <= 20000
print()
print("| target | flash [bytes] (budget 65,536) | static RAM + stack high-water [bytes] (budget 8,192) | instructions per control step, mean / max (budget 20,000) | of which the controller / the general identifier, mean | share of a 5 ms period at 40 MHz |")
print("|---|---|---|---|---|---|")
for name, flash, ram, stack, mean, worst, ctl, ident in rows:
    share = mean / (0.005 * 40e6) * 100
    flag = "" if worst <= 20000 else " (over budget)"
    print(f"| {name} | {flash:,} | {ram:,} + {stack:,} | {mean:,} / {worst:,}{flag} | {ctl[0]:,} / {ident[0]:,} | {share:.1f} % |")
sys.exit(0 if ok else 1)
PY
