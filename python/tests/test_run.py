"""rhonn.run, rhonn.campaign, scenarios: the same figures as the Rust tests."""

import json
import threading
import time

import numpy as np
import pytest

import rhonn

from conftest import read_csv


def test_thesis_ch5_pressure_error_converges_within_80_ms():
    r = rhonn.run("thesis-ch5")
    t, p, ph = (r.trajectory[k] for k in ("t", "p_line", "p_line_hat"))
    assert all(isinstance(v, np.ndarray) and v.dtype == np.float64 for v in r.trajectory.values())
    band = 0.01 * 2e6
    k_end = int(np.argmax(t >= 1.0))
    out = np.nonzero(np.abs(ph[:k_end] - p[:k_end]) > band)[0]
    t_conv = t[out[-1] + 1]
    assert 0.02 < t_conv <= 0.08, t_conv
    ident = {s["state"]: s for s in r.summary["identification"]}
    assert set(ident) == {"p_line", "stroke"}
    assert ident["p_line"]["whole_run"]["training"]["fit_percent"] > 95.0


def test_thesis_ch5_agrees_with_the_independent_reference(root):
    ref = read_csv(root / "crates/rhonn/tests/data/thesis_ch5_reference.csv")
    r = rhonn.run("thesis-ch5").trajectory
    assert len(r["t"]) == len(ref["t"])
    worst_x = np.max(np.abs(r["stroke_hat"] - ref["stroke_hat"]))
    off_p = np.mean(np.abs(r["p_line_hat"] - ref["p_line_hat"]) > 0.01e6)
    assert worst_x < 0.01e-3, worst_x
    assert off_p < 0.005, off_p


def test_run_writes_the_same_folder_as_the_command(tmp_path, rhonn_bin):
    import subprocess

    r = rhonn.run("thesis-ch3", out=tmp_path / "py")
    subprocess.run([rhonn_bin, "run", "thesis-ch3", "--out", str(tmp_path / "cli")], check=True, capture_output=True)
    for name in ("trajectory.csv", "states.svg"):
        assert (tmp_path / "py" / name).read_bytes() == (tmp_path / "cli" / name).read_bytes(), name
    cli = json.loads((tmp_path / "cli" / "summary.json").read_text())
    assert r.summary == cli
    # The same files, report.html included (the command's folder writer).
    files = lambda d: sorted(p.name for p in d.iterdir())
    assert files(tmp_path / "py") == files(tmp_path / "cli")
    assert "report.html" in files(tmp_path / "py")


def test_a_scenario_as_a_dict_and_another_plant():
    tomllib = pytest.importorskip("tomllib")  # Python 3.11+: the standard TOML reader

    spec = tomllib.loads(rhonn.show("tanks-control"))
    spec["duration_s"] = spec.get("duration_s", 2400.0) / 4
    r = rhonn.run(spec)
    t = r.trajectory["t"]
    assert spec["duration_s"] - 2.0 < t[-1] <= spec["duration_s"], t[-1]
    names = [c["controller"] for c in r.summary["control"]]
    assert len(names) == 2, names


def test_to_pandas():
    pd = pytest.importorskip("pandas")
    df = rhonn.run("thesis-ch3").to_pandas()
    assert isinstance(df, pd.DataFrame) and list(df.columns)[:2] == ["t", "p_line"]


def test_campaign_is_a_table_reproducible_from_its_seed(tmp_path):
    a = rhonn.campaign("tanks-control", runs=6, seed=3, threads=2)
    b = rhonn.campaign("tanks-control", runs=6, seed=3, threads=1, out=tmp_path / "c")
    assert list(a["run"]) == list(range(6))
    assert all(s == "ok" for s in a["status"])
    for k, v in a.items():
        if v.dtype == np.float64:
            np.testing.assert_array_equal(v, b[k], err_msg=k)
    assert (tmp_path / "c" / "runs.csv").exists()


def test_long_calls_release_the_gil(tmp_path):
    # Behaviour, not the machine's speed: while the campaign runs (its first runs are
    # on disk, the call has not returned), this thread runs Python code. With the GIL
    # held for the call, it could not run between the first run's line and the return.
    done = threading.Event()
    partial = tmp_path / "c" / "runs.partial.csv"

    def work():
        rhonn.campaign("regulated-pi", runs=24, threads=1, seed=1, out=tmp_path / "c")
        done.set()

    th = threading.Thread(target=work)
    th.start()
    seen_during_call = False
    while not done.is_set():
        if partial.exists() and partial.read_text().count("\n") > 1 and not done.is_set():
            seen_during_call = True
            break
        time.sleep(0.001)
    th.join()
    assert seen_during_call, "no Python code ran while the campaign was running"


def test_a_run_into_a_folder_leaves_the_users_files_alone(tmp_path):
    """Issue 56: ``rhonn.run("thesis-ch3", out=d)`` removed ``d/validation.csv`` silently (a
    file of that name was taken for an earlier run's). Only files a run's manifest lists go,
    and a run that would write over a file of the user's is refused, nothing written."""
    d = tmp_path / "d"
    d.mkdir()
    (d / "validation.csv").write_text("t,u,y\n0,1,2\n")
    (d / "notes.txt").write_text("mine")
    rhonn.run("thesis-ch3", out=d)
    rhonn.run("thesis-ch3", out=d)
    with pytest.raises(OSError, match="not a file an earlier rhonn run wrote"):
        rhonn.run("thesis-ch5", out=d)
    assert (d / "validation.csv").read_text() == "t,u,y\n0,1,2\n"
    assert (d / "notes.txt").read_text() == "mine"
    assert (d / "rhonn-manifest.json").exists()
