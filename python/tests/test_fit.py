"""rhonn.fit / Model.predict / save / load on the cascaded tanks, against the command."""

import json
import subprocess

import numpy as np
import pytest

import rhonn

from conftest import read_csv


@pytest.fixture(scope="module")
def tanks_model(tanks, root):
    est, _ = tanks
    return rhonn.fit(est["u"], est["y"], dt=4.0, model=root / "models/cascaded-tanks.toml", inputs=["u"], outputs=["y"])


@pytest.fixture(scope="module")
def command_prediction(tmp_path_factory, root, rhonn_bin):
    d = tmp_path_factory.mktemp("cli")
    data = root / "data/cascaded-tanks"
    run = lambda *a: subprocess.run([rhonn_bin, *map(str, a)], check=True, capture_output=True, cwd=root)
    run("fit", "--data", data / "estimation.csv", "--inputs", "u", "--outputs", "y",
        "--model", root / "models/cascaded-tanks.toml", "--out", d / "fit")
    run("predict", "--model", d / "fit/model.json", "--data", data / "validation.csv", "--out", d / "pred")
    run("predict", "--model", d / "fit/model.json", "--data", data / "validation.csv", "--out", d / "pred10",
        "--steps-ahead", "10")
    run("predict", "--model", d / "fit/model.json", "--data", data / "validation.csv", "--out", d / "pred_w2",
        "--init-window", "2")
    return d


def rms_from(pred, y, first):
    return float(np.sqrt(np.mean((pred[first:] - y[first:]) ** 2)))


def test_tanks_free_run_equals_the_command(tanks, tanks_model, command_prediction):
    _, val = tanks
    pred = tanks_model.predict(val["u"], val["y"])
    assert pred.shape == (len(val["t"]), 1)
    cli = json.loads((command_prediction / "pred/summary.json").read_text())["outputs"][0]
    first = len(val["t"]) - cli["samples"]
    rms = rms_from(pred[:, 0], val["y"], first)
    assert abs(rms - cli["rms_error"]) < 1e-6, (rms, cli["rms_error"])
    assert rms < 0.23  # the README's 0.222 V
    score = tanks_model.score(val["u"], val["y"])[0]
    assert score["samples"] == cli["samples"]
    for k in ("rms_error", "fit_percent", "nrmse"):
        assert abs(score[k] - cli[k]) < 1e-6, k
    csv = read_csv(command_prediction / "pred/prediction.csv")
    np.testing.assert_allclose(pred[:, 0], csv["y_hat"], rtol=0, atol=1e-9)
    # The ARX baseline's prediction and figures: the command's `y_hat_arx` and baseline.
    base = tanks_model.predict(val["u"], val["y"], baseline=True)
    np.testing.assert_allclose(base[:, 0], csv["y_hat_arx"], rtol=0, atol=1e-9)
    cli_base = json.loads((command_prediction / "pred/summary.json").read_text())["baseline_arx"][0]
    assert abs(tanks_model.score(val["u"], val["y"], baseline=True)[0]["rms_error"] - cli_base["rms_error"]) < 1e-9
    assert not np.allclose(base, pred)


def test_a_state_initialisation_window_equals_the_command(tanks, tanks_model, command_prediction):
    _, val = tanks
    # The cascade settles on 5 measured outputs; a window of 2 holds the first before them.
    pred = tanks_model.predict(val["u"], val["y"], init_window=2)
    csv = read_csv(command_prediction / "pred_w2/prediction.csv")
    np.testing.assert_allclose(pred[:, 0], csv["y_hat"], rtol=0, atol=1e-9)
    cli = json.loads((command_prediction / "pred_w2/summary.json").read_text())
    assert cli["init_window"] == 2
    score = tanks_model.score(val["u"], val["y"], init_window=2)[0]
    assert score["samples"] == len(val["t"]) - 2 == cli["outputs"][0]["samples"]
    assert abs(score["rms_error"] - cli["outputs"][0]["rms_error"]) < 1e-9
    assert not np.allclose(pred, tanks_model.predict(val["u"], val["y"]))
    for bad, err in ((0, ValueError), (True, TypeError), (2.0, TypeError)):
        with pytest.raises(err, match="init_window"):
            tanks_model.predict(val["u"], val["y"], init_window=bad)
    with pytest.raises(ValueError, match="init_window"):
        tanks_model.predict(val["u"], val["y"], steps_ahead=3, init_window=2)


def test_the_commands_model_loads_and_predicts_the_same(tanks, tanks_model, command_prediction):
    _, val = tanks
    m = rhonn.load(command_prediction / "fit/model.json")
    assert m.kind == "fit" and m.inputs == ["u"] and m.outputs == ["y"] and m.sample_time_s == 4.0
    np.testing.assert_allclose(m.predict(val["u"], val["y"]), tanks_model.predict(val["u"], val["y"]), atol=1e-9)


def test_save_load_round_trip(tmp_path, tanks, tanks_model):
    _, val = tanks
    tanks_model.save(tmp_path / "model.json")
    back = rhonn.load(tmp_path / "model.json")
    for k in (None, 10):
        np.testing.assert_array_equal(back.predict(val["u"], val["y"], k), tanks_model.predict(val["u"], val["y"], k))
    assert not list(tmp_path.glob("*.partial"))


def test_summary_and_k_steps_ahead_equal_the_command(tanks, tanks_model, command_prediction):
    _, val = tanks
    s = tanks_model.summary
    assert s["training"]["free_run"][0]["outputs"][0]["output"] == "y"
    p10 = tanks_model.predict(val["u"], val["y"], steps_ahead=10)
    cli = json.loads((command_prediction / "pred10/summary.json").read_text())["outputs"][0]
    first = len(val["t"]) - cli["samples"]
    assert abs(rms_from(p10[:, 0], val["y"], first) - cli["rms_error"]) < 1e-6


def test_several_recordings_and_default_names(tanks):
    est, _ = tanks
    h = len(est["u"]) // 2
    m = rhonn.fit([est["u"][:h], est["u"][h:]], [est["y"][:h], est["y"][h:]], dt=4.0, select="none")
    assert m.inputs == ["u"] and m.outputs == ["y"]
    assert len(m.summary["training"]["free_run"]) == 2


def test_non_contiguous_and_integer_arrays_are_accepted(tanks):
    est, _ = tanks
    u2 = np.repeat(est["u"][:, None], 2, axis=1)[:, ::2]  # a strided view
    assert not u2.flags["C_CONTIGUOUS"]
    y = est["y"]
    a = rhonn.fit(u2, y, dt=4.0, select="none")
    b = rhonn.fit(np.ascontiguousarray(u2), y, dt=4, select="none")
    np.testing.assert_array_equal(a.predict(u2, y), b.predict(est["u"], y))
    rhonn.fit(np.round(est["u"] * 100).astype(np.int64), y, dt=4.0, select="none")


def test_without_a_model_the_structure_is_selected_as_the_command_does(tanks):
    est, val = tanks
    m = rhonn.fit(est["u"], est["y"], dt=4.0)  # select="auto" is the default without a model
    sel = m.summary["selection"]
    chosen = sel["candidates"][sel["chosen"]]
    assert chosen["score"] <= sel["candidates"][sel["best_arx"]]["score"]
    # On the tanks the selection picks the continuous-time cascade, as `rhonn fit` does.
    assert chosen["model"]["kind"] == "cascade"
    pred = m.predict(val["u"], val["y"])
    rms = float(np.sqrt(np.mean((pred[5:, 0] - val["y"][5:]) ** 2)))
    assert rms < 0.3, rms
    with pytest.raises(ValueError, match="select"):
        rhonn.fit(est["u"], est["y"], dt=4.0, select="best")
    with pytest.raises(ValueError, match="both name the structure"):
        rhonn.fit(est["u"], est["y"], dt=4.0, select="auto", model={"kind": "arx"})
    # "none": the fixed default structure, no selection; with a model, the model's (the
    # command line's rule: `--select none` keeps `--model`'s).
    assert "selection" not in rhonn.fit(est["u"], est["y"], dt=4.0, select="none").summary
    m = rhonn.fit(est["u"], est["y"], dt=4.0, select="none", model={"kind": "arx"})
    assert m.summary["model"]["kind"] == "arx" and "selection" not in m.summary


def test_the_selection_options_are_those_of_the_command(tanks):
    est, _ = tanks
    # Judged 5 samples ahead, with a budget too small for any: the ARX candidates still
    # run, the others are skipped and the findings say so.
    m = rhonn.fit(est["u"], est["y"], dt=4.0, select_steps_ahead=5, budget=1e-9)
    sel = m.summary["selection"]
    assert "5 samples ahead" in sel["judged_by"], sel["judged_by"]
    assert any("exceeds the budget" in f for f in sel["findings"]), sel["findings"]
    assert sel["candidates"][sel["chosen"]]["model"]["kind"] == "arx"
    with pytest.raises(ValueError, match="apply to the selection only"):
        rhonn.fit(est["u"], est["y"], dt=4.0, select="none", budget=5.0)
    with pytest.raises(ValueError, match="budget"):
        rhonn.fit(est["u"], est["y"], dt=4.0, budget=float("nan"))
    for k in (0, -3):
        with pytest.raises(ValueError, match=f"select_steps_ahead {k} is not allowed"):
            rhonn.fit(est["u"], est["y"], dt=4.0, select_steps_ahead=k)
    with pytest.raises(TypeError, match="select_steps_ahead must be an int"):
        rhonn.fit(est["u"], est["y"], dt=4.0, select_steps_ahead=2.5)
    # As many steps as the record's samples: refused naming Python's argument, not the
    # command's option.
    with pytest.raises(ValueError, match="`select_steps_ahead` = 1024 is not allowed") as e:
        rhonn.fit(est["u"], est["y"], dt=4.0, select_steps_ahead=len(est["u"]))
    assert "--select" not in str(e.value)


def test_the_default_fit_equals_the_command_with_its_baseline(tmp_path, root, rhonn_bin, tanks):
    """The same data through `rhonn fit` (no spec: the structure selected) and through
    `rhonn.fit`: the same model.json (model and ARX baseline: the selection's best ARX on
    the folds) and the same figures in summary.json, the baseline's included."""
    est, _ = tanks
    subprocess.run(
        [rhonn_bin, "fit", "--data", str(root / "data/cascaded-tanks/estimation.csv"), "--inputs", "u",
         "--outputs", "y", "--out", str(tmp_path / "fit")],
        check=True, capture_output=True, cwd=root,
    )
    cli = json.loads((tmp_path / "fit/model.json").read_text())
    cli_summary = json.loads((tmp_path / "fit/summary.json").read_text())
    m = rhonn.fit(est["u"], est["y"], dt=4.0, inputs=["u"], outputs=["y"])
    py = json.loads(m.to_json())
    assert py["model"]["weights"] == cli["model"]["weights"]
    assert py["baseline"] == cli["baseline"]
    assert py["baseline"]["spec"]["na"] == cli_summary["selection"]["candidates"][cli_summary["selection"]["best_arx"]]["model"]["na"]
    for key in ("training", "baseline_arx", "model", "features"):
        assert m.summary[key] == _without_sources(cli_summary[key]), key


def _without_sources(v):
    """summary.json names the command's files; Python's recordings are `recording K`."""
    if isinstance(v, dict):
        return {k: ("recording 0" if k == "data" else _without_sources(x)) for k, x in v.items()}
    if isinstance(v, list):
        return [_without_sources(x) for x in v]
    return v


def test_warnings_are_warnings_and_an_online_model_has_no_baseline(tanks):
    est, val = tanks
    m = rhonn.fit(est["u"], est["y"], dt=4.0, model={"kind": "arx", "na": 1, "nb": 1})
    # The tanks sampled far faster than they move for one lag: a data warning, and nothing
    # of the selection's findings (those are in summary["selection"]).
    assert m.warnings and all(not w.startswith("selection:") for w in m.warnings), m.warnings
    assert any("changes slowly" in w for w in m.warnings), m.warnings
    # Worded for Python: no command-line option, no `t` column.
    assert not any("--resample" in w or "`t`" in w for w in m.warnings), m.warnings
    assert any("before fitting" in w for w in m.warnings), m.warnings
    ident = rhonn.OnlineIdentifier(["u"], ["y"], dt=4.0, model={})
    for t, u, y in zip(est["t"][:50], est["u"][:50], est["y"][:50]):
        ident.update(t, u, y)
    with pytest.raises(ValueError, match="no ARX baseline"):
        ident.freeze().predict(val["u"], val["y"], baseline=True)


def test_an_ensemble_the_selection_chooses_is_the_commands(tmp_path, root, rhonn_bin):
    """DaISy's hair dryer (its benchmark train file): the default selection chooses an
    ensemble (the mean of its best candidates); `rhonn.fit` gives the command's model.json,
    every member's weights included, and the same training figures and members in its summary."""
    import gzip

    with gzip.open(root / "data/benchmarks/daisy-hair-dryer/train.csv.gz", "rt") as f:
        text = f.read()
    # `rhonn fit` reads the time from a column `t`; the benchmark's file names it `t_s`.
    head, body = text.split("\n", 1)
    assert head == "k,t_s,u_heater_V,y_outlet_temp_V", head
    csv_path = tmp_path / "train.csv"
    csv_path.write_text("k,t,u_heater_V,y_outlet_temp_V\n" + body)
    subprocess.run(
        [rhonn_bin, "fit", "--data", str(csv_path), "--inputs", "u_heater_V", "--outputs", "y_outlet_temp_V",
         "--out", str(tmp_path / "fit")],
        check=True, capture_output=True, cwd=root,
    )
    cli = json.loads((tmp_path / "fit/model.json").read_text())
    cli_summary = json.loads((tmp_path / "fit/summary.json").read_text())
    sel = cli_summary["selection"]
    chosen = sel["candidates"][sel["chosen"]]
    assert chosen["name"].startswith("mean of the best"), chosen["name"]
    assert len(cli["members"]) == len(chosen["members"]) - 1 >= 1
    d = read_csv(csv_path)
    m = rhonn.fit(d["u_heater_V"], d["y_outlet_temp_V"], dt=0.08, inputs=["u_heater_V"], outputs=["y_outlet_temp_V"])
    py = json.loads(m.to_json())
    assert py["model"]["weights"] == cli["model"]["weights"]
    assert [x["weights"] for x in py["members"]] == [x["weights"] for x in cli["members"]]
    assert m.summary["training"] == _without_sources(cli_summary["training"])
    assert m.summary["members"] == cli_summary["members"]
    assert len(m.summary["members"]) == len(chosen["members"])


def test_a_masked_array_is_refused_unless_nothing_is_masked(tanks):
    """Issue 56: a numpy masked array's mask was ignored (the values under it were fitted)."""
    est, _ = tanks
    y = np.ma.masked_array(est["y"], mask=np.zeros(len(est["y"]), dtype=bool))
    y.mask[10] = True
    with pytest.raises(ValueError, match=r"y is a masked array with 1 masked value"):
        rhonn.fit(est["u"], y, dt=4.0, model={"kind": "arx", "na": 2, "nb": 2})
    y.mask[10] = False
    m = rhonn.fit(est["u"], y, dt=4.0, model={"kind": "arx", "na": 2, "nb": 2})
    assert np.isfinite(m.score(est["u"], est["y"])[0]["rms_error"])


def test_an_output_the_arx_predicts_better_gets_it_and_the_model_runs_as_one(tmp_path):
    # y1 linear, y2 a saturating bilinear system of the same input: the structure chosen for
    # both is a RHONN; the best ARX beats it on y1 on every fold, so it predicts y1.
    rng = np.random.default_rng(11)
    n = 900
    u = np.repeat(rng.uniform(-1, 1, n // 9 + 1), 9)[:n]
    y1, y2 = np.zeros(n), np.zeros(n)
    for k in range(1, n):
        y1[k] = 0.8 * y1[k - 1] + 0.2 * u[k - 1]
        y2[k] = 0.6 * y2[k - 1] + 0.3 * u[k - 1] + 0.4 * np.tanh(y2[k - 1]) * u[k - 1]
    y = np.column_stack([y1, y2])
    m = rhonn.fit(u, y, dt=1.0, inputs=["u"], outputs=["y1", "y2"])
    sel = m.summary["selection"]
    kinds = [sel["candidates"][c["chosen"]]["model"]["kind"] for c in sel["by_output"]]
    assert kinds[0] == "arx" and kinds[1] != "arx", sel["findings"]
    assert [o["output"] for o in m.summary["by_output"]] == ["y1"]
    pred = m.predict(u, y)
    assert pred.shape == (n, 2)
    base = m.predict(u, y, baseline=True)
    rms = lambda a, b: float(np.sqrt(np.mean((a[20:] - b[20:]) ** 2)))
    assert rms(pred[:, 1], y2) < rms(base[:, 1], y2)
    m.save(tmp_path / "model.json")
    back = rhonn.load(tmp_path / "model.json")
    np.testing.assert_array_equal(back.predict(u, y), pred)


def test_inputs_beyond_the_training_range_warn_and_inputs_within_it_do_not(tanks, tanks_model):
    _, val = tanks
    import warnings

    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        tanks_model.predict(val["u"], val["y"])  # the validation record's input: within the range
    said = [str(w.message) for w in said]
    assert not [w for w in said if w.startswith("input")], said
    # Its measured level goes below the training's lowest by more than a tenth of the span
    # (2.16 V against 2.91 V, 3 % of its samples): said as well.
    assert [w for w in said if w.startswith("output `y` of the data was measured over [2.16")], said
    with pytest.warns(UserWarning, match=r"input `u` of the data spans \[.*the model extrapolates there"):
        tanks_model.predict(1.5 * np.asarray(val["u"]), val["y"])


def test_a_state_space_model_from_python_is_the_commands(tmp_path, tanks, root, rhonn_bin):
    """`kind = "state-space"` through `rhonn.fit` and through `rhonn fit --model`: the same
    model.json's prediction, sample for sample, free and 5 steps ahead."""
    est, val = tanks
    spec = {"kind": "state-space", "na": 2, "nk": 0, "degree": 2, "activation": "identity",
            "settle": 5, "epochs": 15}
    m = rhonn.fit(est["u"], est["y"], dt=4.0, model=spec, inputs=["u"], outputs=["y"])
    assert m.summary["model"]["kind"] == "state-space"
    toml = "\n".join(f"{k} = {json.dumps(v)}" for k, v in spec.items())
    (tmp_path / "ss.toml").write_text(toml + "\n")
    data = root / "data/cascaded-tanks"
    run = lambda *a: subprocess.run([rhonn_bin, *map(str, a)], check=True, capture_output=True, cwd=root)
    run("fit", "--data", data / "estimation.csv", "--inputs", "u", "--outputs", "y",
        "--model", tmp_path / "ss.toml", "--out", tmp_path / "fit")
    for steps, folder in ((None, "pred"), (5, "pred5")):
        extra = ["--steps-ahead", "5"] if steps else []
        run("predict", "--model", tmp_path / "fit/model.json", "--data", data / "validation.csv",
            "--out", tmp_path / folder, *extra)
        csv = read_csv(tmp_path / folder / "prediction.csv")
        pred = m.predict(val["u"], val["y"], steps_ahead=steps)
        np.testing.assert_allclose(pred[:, 0], csv["y_hat"], rtol=0, atol=1e-9)


def test_the_mean_kind_predicts_each_outputs_training_mean(tanks):
    # The smallest model kind (`kind = "mean"`): the reference a model must beat, through
    # Python as through the command (crates/cli/tests/model_kind.rs).
    est, val = tanks
    m = rhonn.fit(est["u"], est["y"], dt=4.0, model={"kind": "mean"})
    pred = m.predict(val["u"], val["y"])
    assert np.all(pred == pred[0]) and abs(pred[0, 0] - np.mean(est["y"])) < 1e-12 * np.mean(est["y"])
    assert abs(m.summary["training"]["free_run"][0]["outputs"][0]["fit_percent"]) < 1e-9
    assert np.array_equal(m.predict(val["u"], val["y"], steps_ahead=4), pred)
