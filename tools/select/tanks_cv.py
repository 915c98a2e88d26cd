#!/usr/bin/env python3
"""Choose the cascaded-tanks model on estimation.csv alone: 3-fold cross-validation over
contiguous thirds (train on two thirds as two records, run free on the held-out third),
lowest mean free-run RMS error, over a grid of structures (ARX, lagged RHONNs, and
continuous-time `cascade` RHONNs with hidden states); then over ensembles of the k best
structures (k = 2..5, the mean of their free runs), judged by the same folds. Prints
every candidate's folds and mean and writes the best (a structure or an ensemble) as a
model TOML. validation.csv is not read. Standard library only.

Usage: python3 tools/select/tanks_cv.py [path/to/rhonn] [out.toml]
"""
import json, os, subprocess, sys, tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from folds import write_thirds  # noqa: E402

exe = sys.argv[1] if len(sys.argv) > 1 else "target/release/rhonn"
out_toml = sys.argv[2] if len(sys.argv) > 2 else None
here = os.path.dirname(os.path.abspath(__file__))
data = os.path.join(here, "..", "..", "..", "shared", "data", "cascaded-tanks", "estimation.csv")


def toml(c):
    if c["kind"] == "cascade":
        return "\n".join([
            'kind = "cascade"', f'neurons = {c["neurons"]}',
            f'free_exponents = {str(c["free_exponents"]).lower()}', f'settle = {c["settle"]}',
            f'starts = {c["starts"]}', f'epochs = {c["epochs"]}']) + "\n"
    lines = [f'kind = "{c["kind"]}"', f'na = {c["na"]}', f'nb = {c["nb"]}', "nk = 1",
             f'law = "{c["law"]}"', "ridge = 1e-6"]
    if c["kind"] == "rhonn":
        lines += [f'degree = {c["degree"]}', f'max_factors = {c["mf"]}']
    if c["filters"]:
        lines.append(f'input_filters_s = [{", ".join(f"{v:.1f}" for v in c["filters"])}]')
    return "\n".join(lines) + "\n"


def ensemble_toml(cs):
    return "\n".join("[[members]]\n" + toml(c) for c in cs)


def grid():
    for filters in ([], [40.0], [20.0, 80.0], [10.0, 40.0, 160.0]):
        for na in (1, 2, 3, 4):
            for nb in (1, 2, 3):
                yield dict(kind="arx", na=na, nb=nb, law="batch-ls", filters=filters)
                for degree, mf in ((2, 2), (3, 2), (3, 3)):
                    for law in ("batch-ls", "simulation-error"):
                        yield dict(kind="rhonn", na=na, nb=nb, degree=degree, mf=mf, law=law,
                                   filters=filters)
    for neurons in (2, 3):
        for free in (True, False):
            for settle in (5, 10):
                for starts in (16, 32, 64):
                    yield dict(kind="cascade", neurons=neurons, free_exponents=free,
                               settle=settle, starts=starts, epochs=50)


def main():
    with tempfile.TemporaryDirectory() as d:
        thirds = write_thirds(data, d)
        def cv(text):
            spec = os.path.join(d, "m.toml")
            open(spec, "w").write(text)
            errs = []
            try:
                for f in range(3):
                    m, p = os.path.join(d, "model"), os.path.join(d, "pred")
                    args = ["fit"]
                    for g in range(3):
                        if g != f:
                            args += ["--data", thirds[g]]
                    subprocess.run([exe, *args, "--inputs", "u", "--outputs", "y", "--model", spec,
                                    "--out", m], check=True, capture_output=True, text=True)
                    subprocess.run([exe, "predict", "--model", os.path.join(m, "model.json"),
                                    "--data", thirds[f], "--out", p], check=True,
                                   capture_output=True, text=True)
                    s = json.load(open(os.path.join(p, "summary.json")))
                    errs.append(s["outputs"][0]["rms_error"])
            except subprocess.CalledProcessError as e:
                return None, e.stderr.strip()
            return errs, None

        scored = []
        for c in grid():
            errs, why = cv(toml(c))
            if errs is None:
                print(f"{json.dumps(c)}: failed: {why}", flush=True)
                continue
            mean = sum(errs) / 3
            print(f"{json.dumps(c)}: folds {' / '.join(f'{v:.3f}' for v in errs)}; mean {mean:.4f} V",
                  flush=True)
            scored.append((mean, c))
        scored.sort(key=lambda s: s[0])
        best = (scored[0][0], toml(scored[0][1]), "the best structure")
        for k in range(2, 6):
            text = ensemble_toml([c for _, c in scored[:k]])
            errs, why = cv(text)
            if errs is None:
                print(f"ensemble of the {k} best: failed: {why}", flush=True)
                continue
            mean = sum(errs) / 3
            print(f"ensemble of the {k} best: folds {' / '.join(f'{v:.3f}' for v in errs)}; "
                  f"mean {mean:.4f} V", flush=True)
            if mean < best[0]:
                best = (mean, text, f"the ensemble of the {k} best structures")
        print(f"chosen: {best[2]}, mean free-run RMS error {best[0]:.4f} V")
        print(best[1])
        if out_toml:
            open(out_toml, "w").write(best[1])


if __name__ == "__main__":
    main()
