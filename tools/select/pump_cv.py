#!/usr/bin/env python3
"""Choose the direct RHONN predictor of the pump (models/pump-direct.toml; the grey box of
models/pump.toml is chosen by `cargo run --release -p rhonn-report --example pump_models --
select`) on the identification record alone: 3-fold
cross-validation over contiguous thirds of pump-identify (train on two thirds, given as
two records, judge the held-out third 10 steps ahead), over a grid of structures.
Prints every structure's mean fit and writes the best as a model TOML. The validation
record (pump-validate) is not read. Standard library only.

Usage: python3 tools/select/pump_cv.py [path/to/rhonn] [out.toml]
"""
import json, os, subprocess, sys, tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from folds import write_thirds  # noqa: E402

exe = sys.argv[1] if len(sys.argv) > 1 else "target/release/rhonn"
out_toml = sys.argv[2] if len(sys.argv) > 2 else None
K = 10


def run(*args):
    subprocess.run([exe, *args], check=True, capture_output=True, text=True)


def toml(c):
    lines = [f'kind = "{c["kind"]}"', f'na = {c["na"]}', f'nb = {c["nb"]}', "nk = 1",
             f'output_lag_start = {K}', 'law = "batch-ls"', "ridge = 1e-6"]
    if c["kind"] == "rhonn":
        lines += [f'degree = {c["degree"]}', "max_factors = 2", f'nonlinear_lags = {c["nl"]}']
    return "\n".join(lines) + "\n"


def main():
    with tempfile.TemporaryDirectory() as d:
        rec = os.path.join(d, "identify")
        run("run", "pump-identify", "--out", rec)
        thirds = write_thirds(os.path.join(rec, "trajectory.csv"), d)
        grid = [dict(kind="arx", na=na, nb=nb) for na in (1, 2, 4, 8) for nb in (10, 20, 30, 40)]
        grid += [dict(kind="rhonn", na=na, nb=nb, degree=2, nl=nl)
                 for na in (2, 4, 8) for nb in (20, 30, 40) for nl in (1, 2, 3)]
        best = None
        for c in grid:
            spec = os.path.join(d, "m.toml")
            open(spec, "w").write(toml(c))
            fits = []
            for f in range(3):
                train = [thirds[g] for g in range(3) if g != f]
                m, p = os.path.join(d, "model"), os.path.join(d, "pred")
                args = ["fit"]
                for t in train:
                    args += ["--data", t]
                run(*args, "--inputs", "current,demand", "--outputs", "p_line_measured", "--model", spec,
                    "--out", m)
                run("predict", "--model", os.path.join(m, "model.json"), "--data", thirds[f],
                    "--out", p, "--steps-ahead", str(K))
                s = json.load(open(os.path.join(p, "summary.json")))
                fits.append(s["outputs"][0]["fit_percent"])
            mean = sum(fits) / 3
            print(f"{json.dumps(c)}: folds {', '.join(f'{v:.1f}' for v in fits)}; mean {mean:.2f} %",
                  flush=True)
            if best is None or mean > best[0]:
                best = (mean, c)
        print(f"best: {json.dumps(best[1])}, mean fit {best[0]:.2f} % 10 steps ahead")
        if out_toml:
            open(out_toml, "w").write(toml(best[1]))


if __name__ == "__main__":
    main()
