#!/usr/bin/env python3
"""A measurement, not a model kind: can a Wiener-Hammerstein block structure whose initial
state is estimated from the start-up window lift the coupled drives' default figures?

The drives' test records (and the middle third of each training record, a held-out part of
the selection's folds) start mid-motion; `kind = "wiener-hammerstein"` starts G1 at rest and
G2 from the measured window, so its first samples are wrong. Here a linear encoder maps the
window (the first W inputs and outputs, normalised, and 1) to the filters' unknown past (G1's
past outputs and inputs, G2's past inputs), the way deep-encoder state-space models
(SUBNET) initialise theirs; it is fitted by Levenberg-Marquardt (scipy) on every window of
the training parts (horizon 60 samples, stride 2), the block structure itself trained by
`rhonn fit --model` and held fixed (or, with `joint`, refined with the encoder).

For each order given (poles, numerator, delay, degree), it prints the selection's folds
(thirds of each training record, free run from the window, RMS error over the training
output's standard deviation) at rest and with the encoder, the folds of the means with the
default selection's members (read from a default `rhonn fit` on the training records),
and the test records' RMS errors. The test figures are printed beside the folds', so they
are a ceiling, not a result.

Usage (numpy and scipy; from the repository root, after `cargo build --release`):
    python3 tools/select/drives_encoder.py [--joint] NA NB NK DEGREE [NA NB NK DEGREE ...]
"""
import glob
import gzip
import json
import os
import subprocess
import sys
import tempfile

import numpy as np
from scipy.optimize import least_squares

RHONN = os.environ.get("RHONN_BIN", "target/release/rhonn")
DATA = "data/benchmarks/coupled-electric-drives"
W = 4  # the benchmark's state-initialisation window
SETTLE = 5  # the selection's folds score from the model's first prediction
TMP = tempfile.mkdtemp(prefix="drives-encoder-")


def records(name):
    rows = np.genfromtxt(gzip.open(f"{DATA}/{name}.csv.gz", "rt"), delimiter=",", names=True)
    return [(rows["u"][rows["record"] == r], rows["y"][rows["record"] == r]) for r in (1, 2)]


def write(parts, d):
    os.makedirs(d, exist_ok=True)
    files = []
    for i, (u, y) in enumerate(parts):
        f = f"{d}/part{i}.csv"
        np.savetxt(f, np.c_[np.arange(len(u)) * 0.02, u, y], delimiter=",", header="t,u,y", comments="")
        files.append(f)
    return files


def fit(parts, d, spec=None):
    cmd = [RHONN, "fit", "--inputs", "u", "--outputs", "y", "--out", f"{d}/m", "--force"]
    if spec is not None:
        open(f"{d}.toml", "w").write(spec)
        cmd += ["--model", f"{d}.toml"]
    for f in write(parts, d):
        cmd += ["--data", f]
    subprocess.run(cmd, check=True, capture_output=True)
    return json.load(open(f"{d}/m/model.json"))


def predict(d, parts):
    out = []
    for i, f in enumerate(write(parts, f"{d}/held")):
        subprocess.run([RHONN, "predict", "--model", f"{d}/m/model.json", "--data", f, "--out",
                        f"{d}/p{i}", "--init-window", str(W)], check=True, capture_output=True)
        out.append(np.genfromtxt(glob.glob(f"{d}/p{i}/prediction.csv")[0], delimiter=",", names=True)["y_hat"])
    return out


def toml(spec):
    def val(v):
        return f'"{v}"' if isinstance(v, str) else str(v).lower() if isinstance(v, bool) else str(v)
    return "".join(f"{k} = {val(v)}\n" for k, v in spec.items() if v is not None)


class Block:
    """model.json's Wiener-Hammerstein weights, simulated over a batch of windows."""

    def __init__(self, m):
        w = m["weights"][0]
        n1, m1, n2, m2 = map(int, w[:4])
        self.nk, d = m["spec"]["nk"], m["spec"]["degree"]
        self.sizes = (m1, n1, d, m2, n2, 1)
        self.theta = np.array(w[4:4 + sum(self.sizes)])
        self.x_range = tuple(w[-2:])
        self.un, self.yn = m["input_norm"][0], m["output_norm"][0]
        lo, hi = m["output_range"][0]
        margin = (hi - lo) * m["spec"]["output_margin"]
        self.bounds = ((lo - margin - self.yn[0]) / self.yn[1], (hi + margin - self.yn[0]) / self.yn[1])
        self.n_past = n1 + (m2 - 1) + (m1 + self.nk - 1)

    def norm(self, u, y):
        return (u - self.un[0]) / self.un[1], (y - self.yn[0]) / self.yn[1]

    def run(self, theta, u, y, past):
        parts, o = [], 0
        for n in self.sizes:
            parts.append(theta[o:o + n])
            o += n
        b1, a1, c, b2, a2, (bias,) = parts
        n1, nk, (batch, t_len) = len(a1), self.nk, u.shape
        x = np.zeros((batch, t_len))
        for k in range(t_len):
            v = np.zeros(batch)
            for i, bi in enumerate(b1):
                v += bi * (u[:, k - nk - i] if k >= nk + i else past[:, n1 + len(b2) - 1 + nk + i - k - 1])
            for i, ai in enumerate(a1):
                v -= ai * (x[:, k - 1 - i] if k > i else past[:, i - k])
            x[:, k] = v
        x = np.clip(x, *self.x_range)
        prev, cur, inner = np.ones_like(x), x, np.zeros_like(x)
        for n, cn in enumerate(c):  # normalised probabilists' Hermite polynomials
            inner += cn * cur
            prev, cur = cur, (x * cur - np.sqrt(n + 1) * prev) / np.sqrt(n + 2)
        w = np.zeros((batch, t_len))
        for k in range(t_len):
            if k < W:
                w[:, k] = y[:, k] - bias
                continue
            s = np.zeros(batch)
            for i, bi in enumerate(b2):
                s += bi * (inner[:, k - i] if k >= i else past[:, n1 + i - k - 1])
            for i, ai in enumerate(a2):
                if k > i:
                    s -= ai * w[:, k - 1 - i]
            w[:, k] = np.clip(s, self.bounds[0] - bias, self.bounds[1] - bias)
        return w + bias


def features(u, y):
    return np.c_[u[:, :W], y[:, :W], np.ones(len(u))]


def train_encoder(block, parts, joint, horizon=60, stride=2):
    us, ys = [], []
    for u, y in (block.norm(u, y) for u, y in parts):
        for s in range(0, len(u) - horizon + 1, stride):
            us.append(u[s:s + horizon])
            ys.append(y[s:s + horizon])
    u, y = np.array(us), np.array(ys)
    z, n_theta = features(u, y), len(block.theta)
    n_enc = block.n_past * z.shape[1]

    def residuals(p):
        theta = p[:n_theta] if joint else block.theta
        past = z @ p[-n_enc:].reshape(block.n_past, -1).T
        return (block.run(theta, u, y, past)[:, W:] - y[:, W:]).ravel()

    p0 = np.r_[block.theta if joint else [], np.zeros(n_enc)]
    p = least_squares(residuals, p0, method="lm", max_nfev=3000 if joint else 400).x
    return (p[:n_theta] if joint else block.theta), p[-n_enc:].reshape(block.n_past, -1)


def runs(block, theta, enc, parts):
    out = []
    for u, y in parts:
        un, yn = block.norm(u, y)
        un, yn = un[None], yn[None]
        past = features(un, yn) @ enc.T if enc is not None else np.zeros((1, block.n_past))
        out.append(block.run(theta, un, yn, past)[0] * block.yn[1] + block.yn[0])
    return out


def rms(pred, y, first):
    return np.sqrt(np.mean((pred[first:] - y[first:]) ** 2))


def main(args):
    joint = "--joint" in args
    orders = [int(a) for a in args if a != "--joint"]
    train, test = records("train"), records("test")
    default = fit(train, f"{TMP}/default")
    members = [default["model"]["spec"]] + [m["spec"] for m in default.get("members", [])]
    folds = []
    for f in range(3):
        fit_parts, held = [], []
        for u, y in train:
            n = len(u)
            for g in range(3):
                (held if g == f else fit_parts).append((u[g * n // 3:(g + 1) * n // 3], y[g * n // 3:(g + 1) * n // 3]))
        member_runs = []
        for j, spec in enumerate(members):
            fit(fit_parts, f"{TMP}/f{f}m{j}", toml(spec))
            member_runs.append(predict(f"{TMP}/f{f}m{j}", held))
        folds.append((fit_parts, held, member_runs))
    default_test = predict(f"{TMP}/default", test)
    for o in range(0, len(orders), 4):
        na, nb, nk, degree = orders[o:o + 4]
        spec = (f'kind = "wiener-hammerstein"\nna = {na}\nnb = {nb}\nnk = {nk}\n'
                f'degree = {degree}\nlaw = "simulation-error"\nepochs = 50\n')
        name = f"poles {na} numerator {nb} delay {nk} degree {degree}"
        rest, encoded, with_members = [], [], []
        for f, (fit_parts, held, member_runs) in enumerate(folds):
            block = Block(fit(fit_parts, f"{TMP}/f{f}wh{o}", spec)["model"])
            sd = block.yn[1]
            theta, enc = train_encoder(block, fit_parts, joint)
            at_rest = runs(block, block.theta, None, held)
            mine = runs(block, theta, enc, held)
            rest.append(np.mean([rms(p, y, SETTLE) / sd for p, (_, y) in zip(at_rest, held)]))
            encoded.append(np.mean([rms(p, y, SETTLE) / sd for p, (_, y) in zip(mine, held)]))
            ens = [np.mean([r[i] for r in member_runs] + [mine[i]], axis=0) for i in range(len(held))]
            with_members.append(np.mean([rms(p, y, SETTLE) / sd for p, (_, y) in zip(ens, held)]))
        block = Block(fit(train, f"{TMP}/all{o}", spec)["model"])
        theta, enc = train_encoder(block, train, joint)
        mine = runs(block, theta, enc, test)
        at_rest = runs(block, block.theta, None, test)
        k = len(members)
        ens = [(k * d + m) / (k + 1) for d, m in zip(default_test, mine)]
        print(f"{name}: folds at rest {np.mean(rest):.4g} {np.round(rest, 3)}, with the encoder "
              f"{np.mean(encoded):.4g} {np.round(encoded, 3)}, mean with the default's members "
              f"{np.mean(with_members):.4g} {np.round(with_members, 3)}")
        print("  test (a ceiling, not a result): at rest "
              + " / ".join(f"{rms(p, y, W):.4g}" for p, (_, y) in zip(at_rest, test))
              + ", with the encoder " + " / ".join(f"{rms(p, y, W):.4g}" for p, (_, y) in zip(mine, test))
              + ", mean with the default's members " + " / ".join(f"{rms(p, y, W):.4g}" for p, (_, y) in zip(ens, test))
              + ", the default " + " / ".join(f"{rms(p, y, W):.4g}" for p, (_, y) in zip(default_test, test)))


if __name__ == "__main__":
    main(sys.argv[1:])
