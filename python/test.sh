#!/usr/bin/env bash
# The Python package's tests: a venv (target/py-venv) with maturin, pytest and numpy,
# `pip install ./python` (maturin builds the extension through pip, as a user would),
# then pytest on python/tests. Needs python3 (3.9+) with venv and pip, and PyPI.
# `python/test.sh install` does the first part only and `python/test.sh run` the
# pytest part (test-all.sh installs while the Rust tests build, and runs pytest beside
# them); without an argument, both.
set -euo pipefail
cd "$(dirname "$0")/.."
step=${1:-all}
case "$step" in
all | install | run) ;;
*)
    echo "python/test.sh: unknown step '$step' (allowed: install, run, or none for both)" >&2
    exit 2
    ;;
esac
PY=${PYTHON:-python3}
VENV=target/py-venv
if [ "$step" != run ]; then
    if [ ! -x "$VENV/bin/python" ]; then
        "$PY" -m venv "$VENV"
    fi
    "$VENV/bin/python" -m pip install --quiet --upgrade pip
    "$VENV/bin/python" -m pip install --quiet maturin pytest numpy
    echo "python/test.sh: building the extension (pip install ./python): about 1.5 min on an idle 2-core machine, longer on a busy one; pip prints nothing meanwhile" >&2
    "$VENV/bin/python" -m pip install --quiet ./python
fi
[ "$step" = install ] && exit 0
# test-all.sh hands over the binary its `cargo test --release` built (RHONN_BIN): no second
# build. Run alone, this builds it.
if [ -z "${RHONN_BIN:-}" ]; then
    cargo build --release --locked --bin rhonn
    RHONN_BIN="$PWD/target/release/rhonn"
fi
export RHONN_BIN
# From the tests' folder, so that `import rhonn` is the installed package, not the source.
cd python/tests
"../../$VENV/bin/python" -m pytest -q .
