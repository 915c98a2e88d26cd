"""rhonn.OnlineIdentifier in a user's own loop: the same estimates as `rhonn identify`."""

import json
import subprocess

import numpy as np
import pytest

import rhonn

from conftest import read_csv


def test_same_estimates_as_rhonn_identify(tmp_path, root, rhonn_bin, tanks):
    est, _ = tanks
    spec = root / "models/tanks-online.toml"
    subprocess.run(
        [rhonn_bin, "identify", "--data", str(root / "data/cascaded-tanks/estimation.csv"), "--inputs", "u",
         "--outputs", "y", "--model", str(spec), "--epochs", "1", "--out", str(tmp_path / "id")],
        check=True, capture_output=True, cwd=root,
    )
    cli_model = json.loads((tmp_path / "id/model.json").read_text())
    sc = cli_model["scaling"]
    ident = rhonn.OnlineIdentifier(
        ["u"], ["y"], dt=4.0, model=spec, y_offset=sc["y_offset"], y_scale=sc["y_scale"],
        u_offset=sc["u_offset"], u_scale=sc["u_scale"], y_bounds=sc["y_bounds"],
    )
    y_hat = np.array([ident.update(t, [u], [y])[0] for t, u, y in zip(est["t"], est["u"], est["y"])])
    w = ident.weights
    assert w.shape == (1, len(ident.term_names))
    np.testing.assert_allclose(w, np.array(cli_model["weights"]), rtol=1e-9, atol=1e-12)
    estimate = read_csv(tmp_path / "id/estimate.csv")
    np.testing.assert_allclose(y_hat, estimate["y_hat"], rtol=0, atol=1e-9)


def test_freeze_gives_a_model_that_saves_and_predicts(tmp_path, tanks):
    est, val = tanks
    ident = rhonn.OnlineIdentifier(
        ["u"], ["y"], dt=4.0, model={}, y_offset=[5.0], y_scale=[2.0], u_offset=[5.0], u_scale=[2.0]
    )
    errors = []
    for t, u, y in zip(est["t"], est["u"], est["y"]):
        errors.append(ident.update(t, np.array([u]), np.array([y]))[0] - y)
    errors = np.abs(errors)
    assert errors[-200:].mean() < errors[:200].mean()
    model = ident.freeze()
    w = ident.weights.copy()
    ident.update(est["t"][-1] + 4.0, [5.0], [5.0])
    np.testing.assert_array_equal(ident.weights, w)  # frozen: the weights stay
    assert model.kind == "online-rhonn"
    model.save(tmp_path / "online.json")
    back = rhonn.load(tmp_path / "online.json")
    p1 = model.predict(val["u"], val["y"], steps_ahead=5)
    np.testing.assert_array_equal(p1, back.predict(val["u"], val["y"], steps_ahead=5))
    assert p1.shape == (len(val["u"]), 1) and np.all(np.isfinite(p1))


def test_lagged_structure_matches_rhonn_identify_and_predicts(tmp_path, root, rhonn_bin, tanks):
    """The lagged structure from Python (as a dict): the command's estimates and weights,
    and its frozen model predicts as `rhonn predict` does."""
    est, val = tanks
    spec = root / "models/tanks-online-lagged.toml"
    subprocess.run(
        [rhonn_bin, "identify", "--data", str(root / "data/cascaded-tanks/estimation.csv"), "--inputs", "u",
         "--outputs", "y", "--model", str(spec), "--out", str(tmp_path / "id")],
        check=True, capture_output=True, cwd=root,
    )
    cli_model = json.loads((tmp_path / "id/model.json").read_text())
    sc = cli_model["scaling"]
    model = {"structure": "lagged", "degree": 2, "lags": {"na": 3, "nb": 2, "nk": 1}}
    ident = rhonn.OnlineIdentifier(
        ["u"], ["y"], dt=4.0, model=model, y_offset=sc["y_offset"], y_scale=sc["y_scale"],
        u_offset=sc["u_offset"], u_scale=sc["u_scale"], y_bounds=sc["y_bounds"],
    )
    y_hat = np.array([ident.update(t, [u], [y])[0] for t, u, y in zip(est["t"], est["u"], est["y"])])
    assert ident.term_names[:5] == ["y[k-1]", "y[k-2]", "y[k-3]", "u[k-1]", "u[k-2]"]
    np.testing.assert_allclose(ident.weights, np.array(cli_model["weights"]), rtol=1e-9, atol=1e-12)
    estimate = read_csv(tmp_path / "id/estimate.csv")
    np.testing.assert_allclose(y_hat, estimate["y_hat"], rtol=0, atol=1e-9)
    frozen = ident.freeze()
    free = frozen.predict(val["u"], val["y"])
    rms = float(np.sqrt(np.mean((free[:, 0] - val["y"]) ** 2)))
    assert 0.55 < rms < 0.70, rms  # the README's 0.641 V (its first 3 samples are measured)


def test_cascade_structure_matches_rhonn_identify(tmp_path, root, rhonn_bin, tanks):
    """The cascade structure from Python (as a dict), one pass: the command's estimates,
    parameters and their names."""
    est, _ = tanks
    spec = tmp_path / "cascade.toml"
    spec.write_text('structure = "cascade"\ncascade = { starts = 8 }\n')
    subprocess.run(
        [rhonn_bin, "identify", "--data", str(root / "data/cascaded-tanks/estimation.csv"), "--inputs", "u",
         "--outputs", "y", "--model", str(spec), "--out", str(tmp_path / "id")],
        check=True, capture_output=True, cwd=root,
    )
    cli_model = json.loads((tmp_path / "id/model.json").read_text())
    sc = cli_model["scaling"]
    ident = rhonn.OnlineIdentifier(
        ["u"], ["y"], dt=4.0, model={"structure": "cascade", "cascade": {"starts": 8}},
        y_offset=sc["y_offset"], y_scale=sc["y_scale"], u_offset=sc["u_offset"], u_scale=sc["u_scale"],
        y_bounds=sc["y_bounds"],
    )
    y_hat = np.array([ident.update(t, [u], [y])[0] for t, u, y in zip(est["t"], est["u"], est["y"])])
    assert ident.term_names == ["b[u]", "k1", "k2", "alpha1", "alpha2", "g1", "o1", "xmax1", "xmax2", "c"]
    np.testing.assert_allclose(ident.weights, np.array(cli_model["weights"]), rtol=1e-12, atol=0)
    estimate = read_csv(tmp_path / "id/estimate.csv")
    np.testing.assert_allclose(y_hat, estimate["y_hat"], rtol=0, atol=1e-12)


def test_wiener_hammerstein_structure_matches_rhonn_identify_and_predicts(tmp_path, root, rhonn_bin, tanks):
    """The Wiener-Hammerstein structure from Python (as a dict): fitted on its window, then
    learned on; the command's estimates, weights and term names, and its frozen model
    predicts as `rhonn predict` does. Frozen before its window is full, it says why."""
    est, val = tanks
    block = {"poles": 2, "degree": 3, "window": 600}
    spec = tmp_path / "wh.toml"
    spec.write_text('structure = "wiener-hammerstein"\nblock = { poles = 2, degree = 3, window = 600 }\n'
                    "output_margin = 0.5\n")
    subprocess.run(
        [rhonn_bin, "identify", "--data", str(root / "data/cascaded-tanks/estimation.csv"), "--inputs", "u",
         "--outputs", "y", "--model", str(spec), "--out", str(tmp_path / "id")],
        check=True, capture_output=True, cwd=root,
    )
    cli_model = json.loads((tmp_path / "id/model.json").read_text())
    sc = cli_model["scaling"]
    model = {"structure": "wiener-hammerstein", "block": block, "output_margin": 0.5}
    ident = rhonn.OnlineIdentifier(
        ["u"], ["y"], dt=4.0, model=model, y_offset=sc["y_offset"], y_scale=sc["y_scale"],
        u_offset=sc["u_offset"], u_scale=sc["u_scale"], y_bounds=sc["y_bounds"],
    )
    with pytest.raises(ValueError, match="window of 600 samples"):
        ident.freeze()
    y_hat = np.array([ident.update(t, [u], [y])[0] for t, u, y in zip(est["t"], est["u"], est["y"])])
    assert ident.term_names[:4] == ["u mean", "u deviation", "y mean", "y deviation"]
    np.testing.assert_allclose(ident.weights, np.array(cli_model["weights"]), rtol=1e-12, atol=0)
    estimate = read_csv(tmp_path / "id/estimate.csv")
    np.testing.assert_allclose(y_hat, estimate["y_hat"], rtol=0, atol=1e-12)
    frozen = ident.freeze()
    subprocess.run(
        [rhonn_bin, "predict", "--model", str(tmp_path / "id/model.json"), "--data",
         str(root / "data/cascaded-tanks/validation.csv"), "--out", str(tmp_path / "p")],
        check=True, capture_output=True, cwd=root,
    )
    predicted = read_csv(tmp_path / "p/prediction.csv")
    np.testing.assert_allclose(frozen.predict(val["u"], val["y"])[:, 0], predicted["y_hat"], rtol=0, atol=1e-12)


def test_without_a_model_it_chooses_online_as_rhonn_identify_does(tmp_path, root, rhonn_bin, tanks):
    """No model: the bank, fed the tanks' estimation record one sample at a time, gives
    `rhonn identify --epochs 1`'s selection (every candidate's prequential figures and the
    winner), its model (weights and scaling) and its free run on the validation record."""
    est, val = tanks
    data = root / "data/cascaded-tanks"
    subprocess.run(
        [rhonn_bin, "identify", "--data", str(data / "estimation.csv"), "--validate", str(data / "validation.csv"),
         "--inputs", "u", "--outputs", "y", "--epochs", "1", "--out", str(tmp_path / "id")],
        check=True, capture_output=True, cwd=root,
    )
    summary = json.loads((tmp_path / "id/summary.json").read_text())
    cli_model = json.loads((tmp_path / "id/model.json").read_text())
    ident = rhonn.OnlineIdentifier(["u"], ["y"], dt=4.0, samples=len(est["t"]))
    y_hat = [ident.update(t, u, y)[0] for t, u, y in zip(est["t"], est["u"], est["y"])]
    assert np.all(np.isfinite(y_hat))
    assert ident.selection == summary["selection"]
    model = ident.freeze()
    assert ident.selection is None
    saved = json.loads(model.to_json())
    assert saved["weights"] == cli_model["weights"]
    assert saved["scaling"] == cli_model["scaling"]
    free = model.predict(val["u"], val["y"])[:, 0]
    validation = read_csv(tmp_path / "id/validation.csv")
    np.testing.assert_array_equal(free, validation["y_free_run"])


def test_choosing_online_refuses_a_scaling_it_would_not_use():
    with pytest.raises(ValueError, match="y_offset needs a model"):
        rhonn.OnlineIdentifier(["u"], ["y"], dt=1.0, y_offset=[1.0])
    with pytest.raises(ValueError, match="samples = 2 is not allowed"):
        rhonn.OnlineIdentifier(["u"], ["y"], dt=1.0, samples=2)
    with pytest.raises(ValueError, match="a given model does not use it"):
        rhonn.OnlineIdentifier(["u"], ["y"], dt=1.0, model={}, samples=100)
    ident = rhonn.OnlineIdentifier(["u"], ["y"], dt=1.0)
    ident.update(0.0, 1.0, 2.0)
    with pytest.raises(ValueError, match="at least 2 samples"):
        ident.freeze()


def test_the_benchs_rust_timings_are_library_calls(tanks):
    """python/bench.py's Rust side: the same updates on a copy (the identifier stays as it
    was), and the median of runs of a scenario; errors as for any call."""
    est, _ = tanks
    t, u, y = est["t"][:50], est["u"][:50].reshape(-1, 1), est["y"][:50].reshape(-1, 1)
    ident = rhonn.OnlineIdentifier(["u"], ["y"], dt=4.0, model={}, y_offset=[5.0], y_scale=[2.0], u_offset=[5.0], u_scale=[2.0])
    w = ident.weights.copy()
    # A duration: only that it is one (speed belongs in python/bench.py).
    s = ident._rust_seconds_per_update(t, u, y)
    assert np.isfinite(s) and s > 0
    np.testing.assert_array_equal(ident.weights, w)
    with pytest.raises(ValueError, match="one row per sample"):
        ident._rust_seconds_per_update(t[:10], u, y)
    with pytest.raises(ValueError, match="a given model"):
        rhonn.OnlineIdentifier(["u"], ["y"], dt=4.0)._rust_seconds_per_update(t, u, y)
    r = rhonn._rhonn._rust_run_seconds("thesis-ch5", 1)
    assert np.isfinite(r) and r > 0


def _frozen_rms(est, val, glitch_at=None, glitch=None, pause_at=None):
    ident = rhonn.OnlineIdentifier(["u"], ["y"], dt=4.0, samples=len(est["t"]))
    for k, (t, u, y) in enumerate(zip(est["t"], est["u"], est["y"])):
        if pause_at is not None and k >= pause_at:
            t += 1e6
        if k == glitch_at:
            y = glitch
        ident.update(t, u, y)
    model = ident.freeze()
    free = model.predict(val["u"], val["y"])[:, 0]
    return float(np.sqrt(np.mean((free - val["y"]) ** 2))), ident


def test_a_glitch_a_huge_value_and_a_pause_do_not_poison_the_identifier(tanks):
    """Issue 56: one glitch y = 1e10 at sample 500 leaves the frozen model's free-run RMS
    within 5 % of the clean stream's; 1e200 is refused and learning goes on; after a pause
    of 1e6 s learning resumes instead of failing."""
    est, val = tanks
    clean, ident = _frozen_rms(est, val)
    assert ident.notes == []
    glitched, ident = _frozen_rms(est, val, glitch_at=500, glitch=1e10)
    assert abs(glitched / clean - 1) <= 0.05, (clean, glitched)
    assert any("skipped" in n and "1e10" in n for n in ident.notes), ident.notes
    ident = rhonn.OnlineIdentifier(["u"], ["y"], dt=4.0, samples=len(est["t"]))
    for k in range(len(est["t"])):
        if k == 500:
            with pytest.raises(ValueError, match="magnitude at most 1e150"):
                ident.update(est["t"][k], est["u"][k], 1e200)
            continue
        ident.update(est["t"][k], est["u"][k], est["y"][k])
    ident.freeze()
    paused, ident = _frozen_rms(est, val, pause_at=500)
    assert np.isfinite(paused) and paused <= 2 * clean, (clean, paused)
    assert any("gap in time" in n for n in ident.notes), ident.notes


def test_the_online_identifier_and_the_stream_command_give_the_same_figures(tanks, rhonn_bin, root, tmp_path):
    """`rhonn identify --stream` (the command) and `rhonn.OnlineIdentifier` (a user's loop),
    fed the same samples with the same length, print and return the same estimates, and
    freeze the same model."""
    est, _ = tanks
    n = len(est["t"])
    ident = rhonn.OnlineIdentifier(["u"], ["y"], dt=4.0, samples=n)
    y_hat = [ident.update(t, [u], [y])[0] for t, u, y in zip(est["t"], est["u"], est["y"])]
    model = json.loads(ident.freeze().to_json())
    args = ["identify", "--stream", "--samples", str(n), "--inputs", "u", "--outputs", "y"]
    out = subprocess.run(
        [rhonn_bin, *args, "--out", str(tmp_path / "s")],
        input=(root / "data" / "cascaded-tanks" / "estimation.csv").read_text(),
        capture_output=True,
        text=True,
        check=True,
    ).stdout.splitlines()
    assert out[0] == "t,y_hat,y_prequential_rms"
    # The command prints from the second sample (the first sets the clock).
    streamed = [float(line.split(",")[1]) for line in out[1:]]
    assert streamed == y_hat[1:]
    assert json.loads((tmp_path / "s" / "model.json").read_text()) == model


def _two_outputs(path, n, seed):
    """Two outputs of different nature side by side: `y1` a linear lag of `u1`, `y2` a
    nonlinear system driven by `u2`, written as CSV and read back (the loop and the command
    see the same numbers)."""
    rng = np.random.default_rng(seed)
    u1 = np.repeat(rng.uniform(-1, 1, n // 13 + 1), 13)[:n]
    u2 = np.repeat(rng.uniform(-2, 2, n // 9 + 1), 9)[:n]
    y1, y2 = np.zeros(n), np.zeros(n)
    for k in range(n - 1):
        y1[k + 1] = 0.9 * y1[k] + 0.2 * u1[k]
        y2[k + 1] = 0.8 * y2[k] + 0.3 * u2[k] + 0.4 * u2[k] * np.tanh(2 * y2[k])
    t = np.arange(n) * 0.1
    np.savetxt(path, np.column_stack([t, u1, u2, y1, y2]), delimiter=",", header="t,u1,u2,y1,y2", comments="")
    return read_csv(path)


def test_on_two_outputs_each_output_has_its_own_bank_as_in_rhonn_identify(tmp_path, rhonn_bin):
    """No model, two outputs: the loop runs each output's own bank beside the joint one and
    gives `rhonn identify --epochs 1`'s selection (`by_output` included), its per-output
    model and its free run on a validation record."""
    est = _two_outputs(tmp_path / "two.csv", 3000, 3)
    val = _two_outputs(tmp_path / "val.csv", 1500, 4)
    subprocess.run(
        [rhonn_bin, "identify", "--data", "two.csv", "--validate", "val.csv", "--inputs", "u1,u2",
         "--outputs", "y1,y2", "--epochs", "1", "--out", "id"],
        check=True, capture_output=True, cwd=tmp_path,
    )
    summary = json.loads((tmp_path / "id/summary.json").read_text())
    cli_model = json.loads((tmp_path / "id/model.json").read_text())
    ident = rhonn.OnlineIdentifier(["u1", "u2"], ["y1", "y2"], dt=0.1, samples=len(est["t"]))
    for k in range(len(est["t"])):
        ident.update(est["t"][k], [est["u1"][k], est["u2"][k]], [est["y1"][k], est["y2"][k]])
    assert ident.selection == summary["selection"]
    assert [o["output"] for o in ident.selection["by_output"]] == ["y1", "y2"]
    model = ident.freeze()
    saved = json.loads(model.to_json())
    assert saved["model"]["structure"] == cli_model["model"]["structure"] == "per-output"
    for key in ("weights", "scaling", "own_y_bounds"):
        assert saved[key] == cli_model[key], key
    with pytest.raises(ValueError, match="differ in length"):
        ident.weights
    free = model.predict(np.column_stack([val["u1"], val["u2"]]), np.column_stack([val["y1"], val["y2"]]))
    validation = read_csv(tmp_path / "id/validation.csv")
    np.testing.assert_array_equal(free[:, 0], validation["y1_free_run"])
    np.testing.assert_array_equal(free[:, 1], validation["y2_free_run"])
