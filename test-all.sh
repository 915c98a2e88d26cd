#!/usr/bin/env bash
# Every test: the Rust workspace (with the mutation harness, tests/mutation.rs), the Python
# package (python/test.sh), then the firmware on an emulated Cortex-M4F and M7 against the
# host (embedded/run-qemu.sh; it needs the Rust target thumbv7em-none-eabihf and
# qemu-system-arm, and says so when they are missing).
#
# Every part runs even when an earlier one fails; the end says which failed, and the exit
# code is non-zero if any did. The Rust tests build in the release profile, so that the
# `rhonn` binary and the Python extension reuse the same compiled crates (one build, not
# three).
set -uo pipefail
cd "$(dirname "$0")"
failed=()
part() {
    local name=$1
    shift
    echo "== test-all.sh: $name"
    if ! "$@"; then
        failed+=("$name")
    fi
}
# --no-fail-fast: one failing test binary does not hide the failures of the others (cargo
# stops at the first by default).
part "Rust (cargo test --workspace --release)" cargo test --workspace --release --locked --no-fail-fast
# The binary the Rust tests built (the same crates the Python extension's build reuses).
export RHONN_BIN="$PWD/target/release/rhonn"
part "Python (python/test.sh)" python/test.sh
if rustup target list --installed 2>/dev/null | grep -qx thumbv7em-none-eabihf && command -v qemu-system-arm >/dev/null; then
    part "firmware (embedded/run-qemu.sh)" embedded/run-qemu.sh
elif [ "${RHONN_REQUIRE_QEMU:-0}" = 1 ]; then
    echo "test-all.sh: embedded/run-qemu.sh needs 'rustup target add thumbv7em-none-eabihf' and qemu-system-arm" >&2
    failed+=("firmware (embedded/run-qemu.sh): not installed")
else
    echo "test-all.sh: NOT RUN: embedded/run-qemu.sh (install with 'rustup target add thumbv7em-none-eabihf' and 'apt-get install qemu-system-arm')" >&2
fi
if [ ${#failed[@]} -gt 0 ]; then
    echo "test-all.sh: FAILED: ${failed[*]}" >&2
    exit 1
fi
echo "test-all.sh: every part passed"
