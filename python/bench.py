"""Overhead of the Python interface, side by side with the Rust cost in one run (a bench,
not a test: timings on a shared machine are noisy, so each figure is the median of
repeats made in the same process).

    python python/bench.py            # after `pip install ./python`, from the repository root

Prints a table: OnlineIdentifier.update called from Python against the same updates
made from Rust; rhonn.run("thesis-ch5") against the same run made from Rust
(ScenarioSpec::run); and the command `rhonn run thesis-ch5` (which also writes its files).
"""

import json
import os
import pathlib
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

# Run as `python python/bench.py`, the script's own folder comes first on the path, and
# its `rhonn/` (the sources, without the compiled extension) would shadow the installed
# package: it failed to import `_rhonn`.
_HERE = pathlib.Path(__file__).resolve().parent
sys.path = [p for p in sys.path if pathlib.Path(p or ".").resolve() != _HERE]

import rhonn  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[1]


def tanks():
    d = np.loadtxt(ROOT / "data/cascaded-tanks/estimation.csv", delimiter=",", skiprows=1)
    return d[:, 0], d[:, 1:2].copy(), d[:, 2:3].copy()


def update_overhead(repeats=7):
    t, u, y = tanks()
    spec = ROOT / "models/tanks-online.toml"
    py_s, rust_s = [], []
    rows_u = [np.ascontiguousarray(r) for r in u]
    rows_y = [np.ascontiguousarray(r) for r in y]
    for _ in range(repeats):
        ident = rhonn.OnlineIdentifier(["u"], ["y"], dt=4.0, model=spec, y_offset=[5.5], y_scale=[2.2], u_offset=[2.8], u_scale=[1.0])
        rust_s.append(ident._rust_seconds_per_update(t, u, y))
        update = ident.update
        start = time.perf_counter()
        for k in range(len(t)):
            update(t[k], rows_u[k], rows_y[k])
        py_s.append((time.perf_counter() - start) / len(t))
    return statistics.median(py_s), statistics.median(rust_s)


def run_overhead(repeats=200):
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        rhonn.run("thesis-ch5")
        times.append(time.perf_counter() - start)
    rust = rhonn._rhonn._rust_run_seconds("thesis-ch5", repeats)
    return statistics.median(times), rust


def command_seconds(repeats=20):
    exe = os.environ.get("RHONN_BIN", str(ROOT / "target/release/rhonn"))
    times = []
    with tempfile.TemporaryDirectory() as d:
        for _ in range(repeats):
            start = time.perf_counter()
            subprocess.run([exe, "run", "thesis-ch5", "--out", d], check=True, capture_output=True)
            times.append(time.perf_counter() - start)
    return statistics.median(times)


def main():
    py_u, rust_u = update_overhead()
    py_run, rust_run = run_overhead()
    cmd = command_seconds()
    print(f"{'median of repeats':<44} {'Python':>12} {'Rust':>12} {'overhead':>12}")
    print(f"{'OnlineIdentifier.update [us/call]':<44} {py_u * 1e6:>12.3f} {rust_u * 1e6:>12.3f} {(py_u - rust_u) * 1e6:>9.3f} us")
    print(f"{'rhonn.run thesis-ch5 [ms] (Rust: ScenarioSpec::run)':<44} {py_run * 1e3:>12.3f} {rust_run * 1e3:>12.3f} {100 * (py_run / rust_run - 1):>10.1f} %")
    print(f"{'the command `rhonn run thesis-ch5` [ms]':<44} {'':>12} {cmd * 1e3:>12.3f}   (process start, CSV, SVG)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
