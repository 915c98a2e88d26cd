#!/usr/bin/env python3
"""Choose the online identifier's settings for the cascaded tanks on estimation.csv alone,
by 3-fold cross-validation over contiguous thirds: `rhonn identify` on two thirds (two
records, in time order, every pass over both), the frozen model run free on the held-out
third; lowest mean free-run RMS error. A single split (the last third held out) chose
`models/tanks-online.toml`'s earlier settings; folds judge every part of the record.
Prints every setting's folds and mean, best last, and writes the best as a model TOML.
validation.csv is not read. Standard library only.

With --lagged the grid is the lagged structure's (`structure = "lagged"`, learned by
least squares sample by sample, one pass): na and nb 1..4, degree 2 or 3, nonlinear lags
all or 1 (64 settings); it chose models/tanks-online-lagged.toml.

With --cascade the grid is the cascade structure's (`structure = "cascade"`, extended
Kalman filters from seeded starts): starts 16 or 32, passes 2, 4 or 8, pass_var 1e-3,
1e-2 or 1e-1, measurement_var 1e-3 or 1e-2 (36 settings); it chose
models/tanks-online-cascade.toml.

Usage: python3 tools/select/tanks_online_cv.py [--lagged|--cascade] [path/to/rhonn] [out.toml]
"""
import itertools, json, os, subprocess, sys, tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from folds import rank, write_thirds  # noqa: E402

lagged = "--lagged" in sys.argv
cascade = "--cascade" in sys.argv
args = [a for a in sys.argv[1:] if a not in ("--lagged", "--cascade")]
exe = args[0] if len(args) > 0 else "target/release/rhonn"
out_toml = args[1] if len(args) > 1 else None
here = os.path.dirname(os.path.abspath(__file__))
data = os.path.join(here, "..", "..", "data", "cascaded-tanks", "estimation.csv")


def toml(c):
    if c.get("cascade"):
        return "\n".join([
            'structure = "cascade"', f"epochs = {c['epochs']}",
            f"cascade = {{ starts = {c['starts']}, pass_var = {c['pass_var']}, "
            f"measurement_var = {c['r']} }}"]) + "\n"
    if c.get("lagged"):
        nl = f", nonlinear_lags = {c['nl']}" if c["nl"] else ""
        return "\n".join([
            'structure = "lagged"', f"degree = {c['degree']}",
            f"lags = {{ na = {c['na']}, nb = {c['nb']}, nk = 1{nl} }}"]) + "\n"
    lines = [f"filters_s = [{', '.join(f'{v:.1f}' for v in c['filters'])}]",
             f"a_per_s = {c['a']}", f"epochs = {c['epochs']}",
             f"output_terms = {str(c['output_terms']).lower()}"]
    if c["law"] == "ls":
        lines.append('law = { kind = "filtered-regressor-ls", p0 = [10.0] }')
    else:
        lines.append(f"gain = {c['gain']}")
    return "\n".join(lines) + "\n"


def run(c, thirds, d):
    spec = os.path.join(d, "spec.toml")
    open(spec, "w").write(toml(c))
    errs = []
    for f in range(3):
        train = [t for k, t in enumerate(thirds) if k != f]
        out = os.path.join(d, "o")
        args = [exe, "identify"] + sum([["--data", t] for t in train], []) + [
            "--inputs", "u", "--outputs", "y", "--model", spec,
            "--validate", thirds[f], "--out", out]
        subprocess.run(["rm", "-rf", out])
        p = subprocess.run(args, capture_output=True, text=True)
        if p.returncode != 0:
            return None
        v = json.load(open(os.path.join(out, "summary.json")))["validation"][0]
        errs.append(v["free_run_rms_error"])
    return errs


def main():
    grid = []
    for filters, a, ot in itertools.product(
            [[], [40.0], [20.0, 80.0, 320.0], [10.0, 40.0, 160.0, 640.0]],
            [0.01, 0.05, 0.1], [True, False]):
        for law, gain in [("fe", 0.03), ("fe", 0.1), ("fe", 0.5), ("ls", None)]:
            grid.append(dict(filters=filters, a=a, output_terms=ot, law=law, gain=gain, epochs=10))
    if lagged:
        grid = [dict(lagged=True, na=na, nb=nb, degree=dg, nl=nl)
                for na, nb, dg, nl in itertools.product([1, 2, 3, 4], [1, 2, 3, 4], [2, 3], [None, 1])]
    if cascade:
        grid = [dict(cascade=True, starts=st, epochs=ep, pass_var=pv, r=r)
                for st, ep, pv, r in itertools.product([16, 32], [2, 4, 8], [1e-3, 1e-2, 1e-1], [1e-3, 1e-2])]
    with tempfile.TemporaryDirectory() as d:
        thirds = write_thirds(data, d)
        rank(grid, lambda c: run(c, thirds, d), toml, "{:.3f} V", False, out_toml)


main()
