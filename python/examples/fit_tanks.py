"""Fit the cascaded tanks benchmark with rhonn from Python and plot measured against
predicted (free run on the validation record), as `rhonn fit` / `rhonn predict` do.

    pip install ./python matplotlib
    python python/examples/fit_tanks.py            # writes out/python/fit_tanks.png
"""

import pathlib
import sys

import numpy as np

import rhonn

ROOT = pathlib.Path(__file__).resolve().parents[2]


def load(name):
    d = np.loadtxt(ROOT / "data/cascaded-tanks" / name, delimiter=",", skiprows=1)
    return d[:, 0], d[:, 1], d[:, 2]  # t [s], u [V], y [V]


def main():
    t_e, u_e, y_e = load("estimation.csv")
    t_v, u_v, y_v = load("validation.csv")
    model = rhonn.fit(u_e, y_e, dt=4.0, model=ROOT / "models/cascaded-tanks.toml", inputs=["u"], outputs=["y"])
    y_hat = model.predict(u_v, y_v)[:, 0]
    score = model.score(u_v, y_v)[0]  # the figures `rhonn predict` gives
    fit = score["fit_percent"]
    print(f"free run on validation.csv: RMS error {score['rms_error']:.4f} V, fit {fit:.1f} %")
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("matplotlib is not installed: no plot (pip install matplotlib)")
        return 0
    fig, ax = plt.subplots(figsize=(9, 4))
    ax.plot(t_v, y_v, color="0.2", label="measured")
    ax.plot(t_v, y_hat, color="tab:blue", label=f"RHONN free run (fit {fit:.1f} %)")
    ax.set_xlabel("t [s]")
    ax.set_ylabel("lower tank level y [V]")
    ax.set_title("Cascaded tanks, validation record")
    ax.legend()
    out = ROOT / "out/python"
    out.mkdir(parents=True, exist_ok=True)
    fig.tight_layout()
    fig.savefig(out / "fit_tanks.png", dpi=100)
    print(f"wrote {out / 'fit_tanks.png'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
