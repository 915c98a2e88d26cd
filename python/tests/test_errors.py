"""Every bad argument raises a Python exception whose message names the argument; no
panic crosses into Python."""

import numpy as np
import pytest

import rhonn

N = 200
U = np.sin(np.arange(N) * 0.1)
Y = np.cos(np.arange(N) * 0.07)


@pytest.fixture(scope="module")
def model():
    return rhonn.fit(U, Y, dt=0.1)


@pytest.mark.parametrize(
    "kwargs, exc, words",
    [
        (dict(u=np.zeros((N, 1, 1)), y=Y), ValueError, "u must be 1-D"),
        (dict(u=U[:-1], y=Y), ValueError, "u has 199 rows and y 200"),
        (dict(u=np.where(np.arange(N) == 5, np.nan, U), y=Y), ValueError, "u[5, 0] = nan"),
        (dict(u=U, y=np.where(np.arange(N) == 7, np.inf, Y)), ValueError, "y[7, 0] = inf"),
        (dict(u=U.astype(complex), y=Y), TypeError, "u must hold real numbers"),
        (dict(u=np.array(["a"] * N), y=Y), TypeError, "u must hold real numbers"),
        (dict(u=np.zeros((0, 1)), y=np.zeros((0, 1))), ValueError, "u is empty"),
        (dict(u=U, y=Y, dt=0.0), ValueError, "dt = 0"),
        (dict(u=U, y=Y, dt=-1.0), ValueError, "dt = -1"),
        (dict(u=U, y=Y, dt="4"), TypeError, "dt must be a number"),
        (dict(u=U, y=Y, inputs=["a", "b"]), ValueError, "inputs names 2 signals"),
        (dict(u=U, y=Y, model={"kind": "arx", "na": 0, "nb": 0}), ValueError, "in the model spec"),
        (dict(u=U, y=Y, model={"no_such_key": 1}), ValueError, "no_such_key"),
        (dict(u=U, y=Y, model=42), TypeError, "model must be None, a path"),
        (dict(u=U, y=Y, model="/no/such/spec.toml"), OSError, "/no/such/spec.toml"),
    ],
)
def test_fit_refuses(kwargs, exc, words):
    args = dict(dt=0.1)
    args.update(kwargs)
    with pytest.raises(exc) as e:
        rhonn.fit(args.pop("u"), args.pop("y"), **args)
    assert words in str(e.value)


def test_predict_refuses(model):
    # The values' rules are the library's (rhonn_sysid::prediction_options), negative and
    # huge ints included, named by Python's argument.
    for k, shown in ((0, "0"), (-3, "-3"), (2**200, r"\S+")):
        with pytest.raises(ValueError, match=f"`steps_ahead` = {shown} is not allowed: K >= 1 steps ahead"):
            model.predict(U, Y, steps_ahead=k)
    with pytest.raises(ValueError, match="`init_window` = -1 is not allowed: N >= 1"):
        model.predict(U, Y, init_window=-1)
    with pytest.raises(TypeError, match="steps_ahead must be an int"):
        model.predict(U, Y, steps_ahead=2.5)
    with pytest.raises(ValueError, match="u has 2 columns; 1 are needed"):
        model.predict(np.zeros((N, 2)), Y)
    with pytest.raises(ValueError, match="needs at least"):
        model.predict(U[:2], Y[:2], steps_ahead=10)


def test_run_and_campaign_refuse(tmp_path):
    with pytest.raises(ValueError, match="unknown scenario `no-such`"):
        rhonn.run("no-such")
    with pytest.raises(TypeError, match="scenario must be"):
        rhonn.run(3)
    with pytest.raises(ValueError, match="runs = 0"):
        rhonn.campaign("tanks-control", runs=0)
    with pytest.raises(ValueError, match="threads = 0"):
        rhonn.campaign("tanks-control", runs=2, threads=0)
    with pytest.raises(ValueError, match="duration"):
        spec = {"name": "bad", "duration_s": -1.0, "plant": {"kind": "pump"}}
        rhonn.run(spec)
    # A scenario names its plant; the pump's former format is refused with the way out.
    with pytest.raises(ValueError, match="output_interval_ms.*no `kind` in \\[plant\\].*scenarios.md"):
        rhonn.run({"name": "old", "duration_s": 1.0, "output_interval_ms": 1.0})


def test_load_refuses(tmp_path):
    with pytest.raises(OSError, match="missing.json"):
        rhonn.load(tmp_path / "missing.json")
    bad = tmp_path / "bad.json"
    bad.write_text('{"kind": "online-rhonn", "weights": []}')
    with pytest.raises(ValueError, match="bad.json is not a valid online model"):
        rhonn.load(bad)
    bad.write_text("not json")
    with pytest.raises(ValueError, match="bad.json is not JSON"):
        rhonn.load(bad)


def test_online_identifier_refuses():
    with pytest.raises(ValueError, match="dt = 0"):
        rhonn.OnlineIdentifier(["u"], ["y"], dt=0.0)
    with pytest.raises(ValueError, match=r"y_scale\[0\] = 0"):
        rhonn.OnlineIdentifier(["u"], ["y"], dt=1.0, model={}, y_scale=[0.0])
    with pytest.raises(ValueError, match="outputs is empty"):
        rhonn.OnlineIdentifier(["u"], [], dt=1.0)
    ident = rhonn.OnlineIdentifier(["u"], ["y"], dt=1.0)
    with pytest.raises(ValueError, match="u has 2 values; 1 are needed"):
        ident.update(0.0, [1.0, 2.0], [0.0])
    with pytest.raises(ValueError, match=r"(?i)y\[0\] = nan"):
        ident.update(0.0, [1.0], [float("nan")])
    with pytest.raises(TypeError, match="u must be a 1-D array or a sequence"):
        ident.update(0.0, "abc", [0.0])
    ident.update(0.0, [1.0], [0.0])
    with pytest.raises(ValueError):
        ident.update(0.0, [1.0], [0.0])  # time does not increase


def test_odd_inputs_raise_exceptions_never_panics(tmp_path):
    """A Rust panic would arrive as pyo3's PanicException, a BaseException that
    `except Exception` does not catch: this test would then fail."""
    m = rhonn.fit(U, Y, dt=0.1)
    odd = [
        lambda: rhonn.fit(U, np.zeros((N, 0)), dt=0.1),
        lambda: rhonn.fit(np.zeros((N, 0)), Y, dt=0.1),
        lambda: rhonn.fit(U[:2], Y[:2], dt=0.1),
        lambda: rhonn.fit([U, U], [Y], dt=0.1),
        lambda: rhonn.fit(U, Y, dt=float("nan")),
        lambda: rhonn.fit(U, Y, dt=1e308),
        lambda: rhonn.fit(U, Y, dt=0.1, model={"kind": "rhonn", "degree": 99, "na": 50, "nb": 50}),
        lambda: m.predict(U[:1], Y[:1]),
        lambda: m.predict(np.zeros((N, 0)), Y),
        lambda: m.predict(U, Y, steps_ahead=10**12),
        lambda: rhonn._rhonn.Model.from_json("{}"),
        lambda: rhonn._rhonn.Model.from_json('{"kind": "online-rhonn"}'),
        lambda: rhonn.campaign("tanks-control", runs=10**8),
        lambda: rhonn.run({"name": "x"}),
        lambda: rhonn.run({"plant": {"kind": "tanks"}}),
        lambda: rhonn.OnlineIdentifier([], ["y"], dt=1.0).update(0.0, [], [1.0]),
        lambda: rhonn.OnlineIdentifier(["u"], ["y"], dt=1.0, model={"degree": 40, "max_factors": 40}),
        lambda: rhonn.OnlineIdentifier(["u"], ["y"], dt=1.0, y_bounds=[(1.0, 0.0)]),
        lambda: rhonn.OnlineIdentifier(["u"], ["y"], dt=1.0).update(float("inf"), [0.0], [0.0]),
    ]
    raised = 0
    for k, call in enumerate(odd):
        try:
            call()
        except Exception as e:  # noqa: BLE001 - any ordinary exception is fine here
            assert str(e), f"case {k}: an exception without a message"
            raised += 1
    assert raised >= len(odd) - 3, raised


def test_online_identifier_refuses_what_it_used_to_take_silently():
    """Issue 33: complex inputs lost their imaginary part, a string of names was split into
    letters, a NaN in a dict spec read as "not JSON", a denormal dt was blamed on a gain."""
    ident = rhonn.OnlineIdentifier(["u"], ["y"], dt=1.0)
    with pytest.raises(TypeError, match="u must hold real numbers, not complex"):
        ident.update(0.0, np.array([1.0 + 2.0j]), [1.0])
    with pytest.raises(TypeError, match="inputs must be a sequence of names"):
        rhonn.OnlineIdentifier("uv", ["y"], dt=1.0)
    with pytest.raises(ValueError, match=r"model\['gain'\] = nan is not allowed"):
        rhonn.OnlineIdentifier(["u"], ["y"], dt=1.0, model={"gain": float("nan")})
    with pytest.raises(ValueError, match="sample time"):
        rhonn.OnlineIdentifier(["u"], ["y"], dt=1e-320)
    # One input: a plain number is its value (issue 38).
    a = rhonn.OnlineIdentifier(["u"], ["y"], dt=1.0)
    b = rhonn.OnlineIdentifier(["u"], ["y"], dt=1.0)
    for k in range(5):
        np.testing.assert_array_equal(a.update(float(k), 0.5 * k, [0.1 * k]), b.update(float(k), [0.5 * k], [0.1 * k]))


def test_a_model_whose_free_run_overflows_raises(tmp_path, root, rhonn_bin, tanks):
    """An online cascade whose output offset is 1e300 (finite, a valid model) predicts
    outputs whose error overflows: an exception, as `rhonn predict` refuses it."""
    import json
    import subprocess

    _, val = tanks
    subprocess.run(
        [rhonn_bin, "identify", "--data", str(root / "data/cascaded-tanks/estimation.csv"), "--inputs", "u",
         "--outputs", "y", "--model", str(root / "models/tanks-online-cascade.toml"), "--out",
         str(tmp_path / "id")],
        check=True, capture_output=True, cwd=root,
    )
    m = json.loads((tmp_path / "id/model.json").read_text())
    m["weights"][0][-1] = 1e300
    (tmp_path / "huge.json").write_text(json.dumps(m))
    model = rhonn.load(tmp_path / "huge.json")
    with pytest.raises((ValueError, RuntimeError), match="prediction of `y`.*not finite"):
        model.predict(val["u"], val["y"])
