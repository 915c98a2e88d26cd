#!/usr/bin/env bash
# Every test: the Rust workspace, then the Python package (python/test.sh).
set -euo pipefail
cd "$(dirname "$0")"
cargo test --workspace --locked
python/test.sh
