#!/usr/bin/env python3
"""Choose the online identifier's settings for the pump (models/pump-online.toml) on the
identification record alone, by 3-fold cross-validation over contiguous thirds of
pump-identify: `rhonn identify` on two thirds (two records, in time order), the frozen
model judged 10 samples (50 ms) ahead on the held-out third; highest mean fit. Prints
every setting's folds and mean, best last, and writes the best as a model TOML. The
validation record (pump-validate) is not read. Standard library only.

With --lagged the grid is the lagged structure's (`structure = "lagged"`, learned by
least squares sample by sample): output lags from 10 (a direct 10-step predictor, so
nothing is predicted from predictions) over na 4 / 8, input lags nb 10 / 20 / 30,
nonlinear lags 1 / 2, one pass; it chose models/pump-online-lagged.toml.

Usage: python3 tools/select/pump_online_cv.py [--lagged] [path/to/rhonn] [out.toml]
"""
import itertools, json, os, subprocess, sys, tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from folds import rank, write_thirds  # noqa: E402

lagged = "--lagged" in sys.argv
args = [a for a in sys.argv[1:] if a != "--lagged"]
exe = args[0] if len(args) > 0 else "target/release/rhonn"
out_toml = args[1] if len(args) > 1 else None
K = 10


def toml(c):
    if c.get("lagged"):
        return "\n".join([
            'structure = "lagged"',
            f"lags = {{ na = {c['na']}, nb = {c['nb']}, nk = 1, output_lag_start = {K}, "
            f"nonlinear_lags = {c['nl']} }}"]) + "\n"
    return "\n".join([
        f'inputs = "{c["inputs"]}"',
        f"filters_s = [{', '.join(str(v) for v in c['filters'])}]",
        f"a_per_s = {c['a']}", f"gain = {c['gain']}", f"epochs = {c['epochs']}"]) + "\n"


def score(c, thirds, d):
    spec = os.path.join(d, "spec.toml")
    open(spec, "w").write(toml(c))
    fits = []
    for f in range(3):
        train = [t for k, t in enumerate(thirds) if k != f]
        out = os.path.join(d, "o")
        subprocess.run(["rm", "-rf", out])
        args = [exe, "identify"] + sum([["--data", t] for t in train], []) + [
            "--inputs", "current,demand", "--outputs", "p_line_measured", "--model", spec,
            "--validate", thirds[f], "--steps-ahead", str(K), "--out", out]
        if subprocess.run(args, capture_output=True, text=True).returncode != 0:
            return None
        v = json.load(open(os.path.join(out, "summary.json")))["validation"][0]
        fits.append(v["ahead_fit_percent"])
    return fits


def main():
    grid = [dict(inputs=i, filters=f, a=a, gain=g, epochs=e)
            for i, f, a, g, e in itertools.product(
                ["hold", "linear"], [[], [0.01, 0.04], [0.005, 0.02, 0.08]],
                [3.0, 10.0, 30.0], [0.1, 0.5, 2.0], [1, 3])]
    if lagged:
        grid = [dict(lagged=True, na=na, nb=nb, nl=nl)
                for na, nb, nl in itertools.product([4, 8], [10, 20, 30], [1, 2])]
    with tempfile.TemporaryDirectory() as d:
        rec = os.path.join(d, "identify")
        subprocess.run([exe, "run", "pump-identify", "--out", rec], check=True, capture_output=True)
        thirds = write_thirds(os.path.join(rec, "trajectory.csv"), d)
        rank(grid, lambda c: score(c, thirds, d), toml, "{:.1f} %", True, out_toml)


main()
