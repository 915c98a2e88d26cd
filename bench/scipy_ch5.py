#!/usr/bin/env python3
"""thesis-ch5 (the pump and the thesis's RHONN identifier, 40 s) with scipy's
solve_ivp(RK45) at rhonn's tolerances (rtol 1e-6; atol 1 Pa, 1e-9 m, 1e-9 for the
identifier's states), timed, against `rhonn bench` on the same model (training run
only), in 5 interleaved rounds; prints the best time of each and the ratio. Not part of the test command.

Usage: python3 bench/scipy_ch5.py [path/to/rhonn] [--json FILE]   (default
target/release/rhonn; needs numpy, scipy, and a release build: cargo build --release).
With --json FILE it also writes both timings as a comparison file for
`rhonn bench --out DIR --compare FILE` (bars side by side in DIR/bench.svg).

The scipy model is written as a user would: the limited integrators as derivatives
zeroed at the bounds, the valve branch chosen inside the right-hand side (no event
location, so scipy steps across the switchings; rhonn locates them, and still wins).
"""
import json, subprocess, sys, tempfile, time, os
import numpy as np
np.seterr(over="ignore")  # logistic(-large) overflows exp to inf: the value 0 is right
from scipy.integrate import solve_ivp

V0, beta, alpha_v, Pmax = 0.25e-3, 1.2e9, 0.04e-6, 25e6
kl, omega, Q0 = 0.6e-3, 200.0, 0.13e-3
Aa, xmax, mu1, mu2 = 5e-4, 0.024, 78e-6, 78e-6
phi, Kc, Ka, K, Fu, gam, P0 = 28.0, 27300.0, 1300.0, 8300.0, 400.0, 0.2, 0.4e6
A = np.array([120.0, 41.0]); G = np.array([1e4, 30.0]); M = np.array([1e10, 10.0]); SIG = 0.01


def current(t):
    i = 0.8 * t / 15 if t <= 15 else 0.8 if t <= 25 else 0.8 * (40 - t) / 15 if t <= 40 else 0.0
    return min(max(i, 0.0), 0.8)


def logistic(v):
    return 1.0 / (1.0 + np.exp(-v))


def rhs(t, y):
    p, x = y[0], y[1]
    s = (phi * current(t) - Ka * x) / (Kc + Ka)
    dpa = gam * p + (Fu - K * x) / Aa - P0 if s >= 0 else (1 - gam) * p - (Fu - K * x) / Aa
    qa = np.sign(dpa) * s * (mu1 + mu2 * abs(s)) * np.sqrt(abs(dpa))
    vl = V0 * (1 + alpha_v * p)
    dp = beta / vl * (kl * omega * x - Q0 - (abs(qa) if s < 0 else 0.0))
    dx = qa / Aa
    if (p <= 0 and dp < 0) or (p >= Pmax and dp > 0):
        dp = 0.0
    if (x <= 0 and dx < 0) or (x >= xmax and dx > 0):
        dx = 0.0
    z = np.array([logistic(p), logistic(x)])
    xh = y[2:4]
    w = y[4:8].reshape(2, 2)
    e = xh - np.array([p, x])
    dxh = -A * xh + w @ z
    dw = np.empty((2, 2))
    for i in range(2):
        dw[i] = -G[i] * z * e[i]
        if np.linalg.norm(w[i]) > M[i]:
            dw[i] -= SIG * G[i] * w[i]
    return np.concatenate(([dp, dx], dxh, dw.ravel()))


def scipy_once():
    y0 = np.array([2e6, 0.0, 0, 0, 0, 0, 0, 0])
    atol = np.array([1.0, 1e-9] + [1e-9] * 6)
    t0 = time.perf_counter()
    sol = solve_ivp(rhs, (0.0, 40.0), y0, method="RK45", rtol=1e-6, atol=atol, max_step=0.1)
    return time.perf_counter() - t0, sol.nfev, sol.y[:, -1]


def rhonn_once(exe, path):
    out = subprocess.run([exe, "bench", path, "--json", "--seconds", "0.5"], check=True,
                         capture_output=True, text=True).stdout
    b = json.loads(out)[0]
    return b["median_s"], b["rhs_evaluations"]


def main():
    args = sys.argv[1:]
    json_out = None
    if "--json" in args:
        i = args.index("--json")
        if i + 1 >= len(args):
            sys.exit("scipy_ch5.py: --json needs a file name")
        json_out = args[i + 1]
        del args[i : i + 2]
    exe = args[0] if args else "target/release/rhonn"
    toml = subprocess.run([exe, "show", "thesis-ch5"], check=True, capture_output=True, text=True).stdout
    toml = toml.replace("validate = true", "validate = false")
    # Interleaved rounds, the best of each side (shared machines change speed over
    # seconds; interleaving lets both sides see the same conditions).
    ts = tr = float("inf")
    with tempfile.TemporaryDirectory() as d:
        path = os.path.join(d, "ch5-training.toml")
        open(path, "w").write(toml)
        for _ in range(5):
            t, nfev, yf = scipy_once()
            ts = min(ts, t)
            t, nr = rhonn_once(exe, path)
            tr = min(tr, t)
    print(f"scipy solve_ivp(RK45) rtol 1e-6: {ts * 1e3:.1f} ms, {nfev} rhs evaluations "
          f"(final p_line {yf[0] / 1e6:.3f} MPa, stroke {yf[1] * 1e3:.4f} mm)")
    print(f"rhonn (event-locating DOPRI5, same tolerances): {tr * 1e3:.3f} ms, {nr} rhs evaluations")
    print(f"ratio: {ts / tr:.0f}x (best of 5 interleaved rounds each)")
    if json_out:
        run = "thesis-ch5 training (40 s), best of 5 rounds"
        rows = [
            {"run": run, "tool": "scipy solve_ivp(RK45), rtol 1e-6", "median_s": ts, "rhs_evaluations": int(nfev)},
            {"run": run, "tool": "rhonn (event-locating DOPRI5), rtol 1e-6", "median_s": tr, "rhs_evaluations": int(nr)},
        ]
        tmp = json_out + ".partial"
        with open(tmp, "w") as f:
            json.dump(rows, f, indent=1)
        os.replace(tmp, json_out)
        print(f"wrote {json_out}")


if __name__ == "__main__":
    main()
