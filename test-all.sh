#!/usr/bin/env bash
# Every test: the Rust workspace, the Python package (python/test.sh), then the firmware
# on an emulated Cortex-M4F and M7 against the host (embedded/run-qemu.sh; it needs the
# Rust target thumbv7em-none-eabihf and qemu-system-arm, and says so when they are missing).
set -euo pipefail
cd "$(dirname "$0")"
cargo test --workspace --locked
python/test.sh
if rustup target list --installed 2>/dev/null | grep -qx thumbv7em-none-eabihf && command -v qemu-system-arm >/dev/null; then
    embedded/run-qemu.sh
elif [ "${RHONN_REQUIRE_QEMU:-0}" = 1 ]; then
    echo "test-all.sh: embedded/run-qemu.sh needs 'rustup target add thumbv7em-none-eabihf' and qemu-system-arm" >&2
    exit 1
else
    echo "test-all.sh: NOT RUN: embedded/run-qemu.sh (install with 'rustup target add thumbv7em-none-eabihf' and 'apt-get install qemu-system-arm')" >&2
fi
