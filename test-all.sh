#!/usr/bin/env bash
# Every test: the Rust workspace (with the mutation harness, crates/cli/tests/mutation.rs), the Python
# package (python/test.sh), then the firmware on an emulated Cortex-M4F and M7 against the
# host (embedded/run-qemu.sh; it needs the Rust target thumbv7em-none-eabihf and
# qemu-system-arm, and says so when they are missing).
#
# Every part runs even when an earlier one fails; the end says which failed, and the exit
# code is non-zero if any did. The Rust tests build in the release profile, so that the
# `rhonn` binary and the Python extension reuse the same compiled crates (one build, not
# three).
#
# The parts overlap, so that both cores of a 2-core machine stay busy (the Rust build has
# stretches on one crate, QEMU runs on one core): the firmware builds and runs, and the
# Python venv installs, while the Rust tests build; pytest runs beside the Rust tests. The
# parts that run in the background print their output when they end, under their name
# (kept in target/test-all/). The examples are not built here (each is compiled by CI's
# clippy, and crates/cli/tests/custom_plant.rs runs crates/cli/examples/custom_plant.rs).
set -uo pipefail
cd "$(dirname "$0")"
failed=()
logs=target/test-all
mkdir -p "$logs"
part() {
    local name=$1
    shift
    echo "== test-all.sh: $name"
    if ! "$@"; then
        failed+=("$name")
    fi
}
# A part in the background: its output into $logs/FILE.log, its exit code into FILE.rc.
started=()
background() {
    local file=$1 name=$2
    shift 2
    rm -f "$logs/$file.rc"
    ("$@" > "$logs/$file.log" 2>&1; echo $? > "$logs/$file.rc") &
    started+=("$!:$file:$name")
}
# Wait for a background part, print its output under its name, and note a failure.
finish() {
    local entry pid file name
    for entry in "${started[@]}"; do
        IFS=: read -r pid file name <<< "$entry"
        [ "$file" = "$1" ] || continue
        wait "$pid"
        echo "== test-all.sh: $name"
        cat "$logs/$file.log"
        if [ "$(cat "$logs/$file.rc" 2>/dev/null)" != 0 ]; then
            failed+=("$name")
        fi
    done
}
firmware="firmware (embedded/run-qemu.sh)"
if rustup target list --installed 2>/dev/null | grep -qx thumbv7em-none-eabihf && command -v qemu-system-arm >/dev/null; then
    background firmware "$firmware" embedded/run-qemu.sh
elif [ "${RHONN_REQUIRE_QEMU:-0}" = 1 ]; then
    echo "test-all.sh: embedded/run-qemu.sh needs 'rustup target add thumbv7em-none-eabihf' and qemu-system-arm" >&2
    failed+=("$firmware: not installed")
else
    echo "test-all.sh: NOT RUN: embedded/run-qemu.sh (install with 'rustup target add thumbv7em-none-eabihf' and 'apt-get install qemu-system-arm')" >&2
fi
# The venv and its packages download while the Rust tests build; the extension's own
# build waits for theirs (cargo's lock on target/) and reuses its crates.
background python-install "Python install (python/test.sh install)" python/test.sh install
rust="Rust (cargo test --workspace --release)"
# `--tests`: the targets whose manifest says `test = true` (every library's and binary's unit
# tests, the integration tests), not the examples, nor rhonn-python (`test = false`: pytest
# checks it; the Python install builds its extension). Every package stays selected
# (`--workspace`, no `--exclude`): leaving one out changes the features the shared crates are
# built with, and the Python install then rebuilt them (61 s more).
targets=(--workspace --release --locked --tests)
part "$rust: build" cargo test "${targets[@]}" --no-run
finish python-install
# The binary the Rust tests built (the same crates the Python extension's build reused).
export RHONN_BIN="$PWD/target/release/rhonn"
background python "Python (python/test.sh run)" python/test.sh run
# --no-fail-fast: one failing test binary does not hide the failures of the others (cargo
# stops at the first by default).
part "$rust" cargo test "${targets[@]}" --no-fail-fast
part "$rust: doc tests" cargo test --workspace --release --locked --doc
finish python
finish firmware
if [ ${#failed[@]} -gt 0 ]; then
    echo "test-all.sh: FAILED: ${failed[*]}" >&2
    exit 1
fi
echo "test-all.sh: every part passed"
