"""The mutation harness of the Python API: seeded hostile values for every argument of
``fit``, ``Model.predict``, ``load`` and ``OnlineIdentifier``. Every call either returns
finite numbers or raises an ``Exception`` (never a ``PanicException``, which ``except
Exception`` does not catch, and never a hang: each case is bounded by ``signal.alarm``).
A longer run: ``RHONN_MUTANTS=5000 python -m pytest python/tests/test_mutation.py``."""

import json
import os
import random
import signal

import numpy as np
import pytest

import rhonn

N = 120
T = np.arange(N) * 0.1
U = np.sin(T)
Y = np.cos(0.7 * T)
CASES = int(os.environ.get("RHONN_MUTANTS", "300"))
HOSTILE = [np.nan, np.inf, -np.inf, 1.7e308, -1.7e308, 5e-324, 0.0, -1.0, 1e9, 1e-9]


class Hang(Exception):
    pass


def _alarm(signum, frame):
    raise Hang()


@pytest.fixture(scope="module")
def fitted(tmp_path_factory):
    m = rhonn.fit(U, Y, dt=0.1, model={"kind": "arx", "na": 2, "nb": 2})
    p = tmp_path_factory.mktemp("m") / "model.json"
    m.save(p)
    return p


def _hostile_array(rng, base):
    a = np.array(base, dtype=float, copy=True)
    k = rng.randrange(6)
    if k == 0:
        a[rng.randrange(len(a))] = rng.choice(HOSTILE)
    elif k == 1:
        a[:] = rng.choice(HOSTILE)
    elif k == 2:
        return a[: rng.randrange(0, 4)]
    elif k == 3:
        return a.astype(complex)
    elif k == 4:
        return a.reshape(-1, 1, 1)
    return a * rng.choice([1e150, 1e-150, -1.0])


def _mutated_model(rng, path):
    m = json.loads(open(path).read())
    leaves = []

    def walk(v, at):
        if isinstance(v, dict):
            for k, x in v.items():
                walk(x, at + [k])
        elif isinstance(v, list):
            for i, x in enumerate(v):
                walk(x, at + [i])
        elif isinstance(v, (int, float)) and not isinstance(v, bool):
            leaves.append(at)

    walk(m, [])
    at = rng.choice(leaves)
    cur = m
    for k in at[:-1]:
        cur = cur[k]
    cur[at[-1]] = rng.choice([1.7e308, -1.7e308, 5e-324, 0, -1, 1e9, "x", None, []])
    return m


def _case(rng, fitted, tmp):
    kind = rng.randrange(4)
    if kind == 0:
        u, y = _hostile_array(rng, U), Y
        if rng.random() < 0.5:
            u, y = U, _hostile_array(rng, Y)
        return np.asarray(rhonn.fit(u, y, dt=rng.choice([0.1, 0.1, 1e-320, 1e308, -0.1])).predict(U, Y))
    if kind == 1:
        m = rhonn.load(fitted)
        return np.asarray(m.predict(_hostile_array(rng, U), Y, steps_ahead=rng.choice([None, 1, 5])))
    if kind == 2:
        p = tmp / "mutant.json"
        p.write_text(json.dumps(_mutated_model(rng, fitted)))
        return np.asarray(rhonn.load(p).predict(U, Y))
    ident = rhonn.OnlineIdentifier(
        ["u"], ["y"], dt=rng.choice([0.1, 0.1, 1e-320, 1e308]), y_scale=[rng.choice([1.0, 1.0] + HOSTILE)]
    )
    out = []
    for k in range(20):
        u = [rng.choice(HOSTILE)] if k == 10 and rng.random() < 0.5 else [U[k]]
        out.append(ident.update(float(T[k]), u, [Y[k]]))
    return np.asarray(out)


def test_hostile_python_calls_raise_exceptions_or_give_finite_numbers(fitted, tmp_path):
    rng = random.Random(1)
    old = signal.signal(signal.SIGALRM, _alarm)
    outcomes = {"returned": 0, "raised": 0}
    try:
        for i in range(CASES):
            signal.alarm(60)
            try:
                out = _case(rng, fitted, tmp_path)
                assert np.all(np.isfinite(out)), f"case {i}: non-finite result returned"
                outcomes["returned"] += 1
            except Hang:
                pytest.fail(f"case {i}: still running after 60 s")
            except AssertionError:
                raise
            except Exception as e:  # noqa: BLE001 - any Exception is a refusal; a panic is not one
                assert type(e).__name__ != "PanicException", f"case {i}: {e}"
                assert str(e), f"case {i}: {type(e).__name__} without a message"
                outcomes["raised"] += 1
            finally:
                signal.alarm(0)
    finally:
        signal.signal(signal.SIGALRM, old)
    assert outcomes["returned"] > 10 and outcomes["raised"] > 10, outcomes
