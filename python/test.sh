#!/usr/bin/env bash
# The Python package's tests: a venv (target/py-venv) with maturin, pytest and numpy,
# `pip install ./python` (maturin builds the extension through pip, as a user would),
# then pytest on python/tests. Needs python3 (3.9+) with venv and pip, and PyPI.
set -euo pipefail
cd "$(dirname "$0")/.."
PY=${PYTHON:-python3}
VENV=target/py-venv
if [ ! -x "$VENV/bin/python" ]; then
    "$PY" -m venv "$VENV"
fi
"$VENV/bin/python" -m pip install --quiet --upgrade pip
"$VENV/bin/python" -m pip install --quiet maturin pytest numpy
cargo build --release --locked --bin rhonn
"$VENV/bin/python" -m pip install --quiet ./python
export RHONN_BIN="$PWD/target/release/rhonn"
# From the tests' folder, so that `import rhonn` is the installed package, not the source.
cd python/tests
"../../$VENV/bin/python" -m pytest -q .
