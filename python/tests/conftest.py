"""Shared fixtures: the repository's root, its data, and the `rhonn` command."""

import os
import pathlib
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]


def read_csv(path):
    import numpy as np

    with open(path, encoding="utf-8") as f:
        header = f.readline().strip().split(",")
    data = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    return {name: data[:, j] for j, name in enumerate(header)}


@pytest.fixture(scope="session")
def root():
    return ROOT


@pytest.fixture(scope="session")
def tanks():
    d = ROOT / "data" / "cascaded-tanks"
    return read_csv(d / "estimation.csv"), read_csv(d / "validation.csv")


@pytest.fixture(scope="session")
def rhonn_bin():
    """The command line built from the same sources (the test script builds it first)."""
    path = pathlib.Path(os.environ.get("RHONN_BIN", ROOT / "target" / "release" / "rhonn"))
    if not path.exists():
        subprocess.run(["cargo", "build", "--release", "--locked", "--bin", "rhonn"], cwd=ROOT, check=True)
    assert path.exists(), f"no rhonn command at {path}: run `cargo build --release`"
    return str(path)
