#!/usr/bin/env python3
"""Independent high-accuracy reference for the pump of pump-model.md section 1 (thesis-ch3),
and with --ch5 for the thesis's RHONN identifier of pump-model.md section 2 (thesis-ch5).

Written from pump-model.md alone, sharing no code with the Rust solver: scipy's DOP853 at
rtol 1e-12 integrates between events; every mode change (valve branch s >= 0 / s < 0,
sign of the pilot pressure drop, a state reaching or leaving a bound, the breakpoints
of the current profile) is located by scipy's own event finder and the integration is
restarted there. Output: t [s], p_line [Pa], stroke [m] every 1 ms, on stdout as CSV.

Usage: python3 tools/reference/pump_reference.py > crates/rhonn/tests/data/thesis_ch3_reference.csv
       python3 tools/reference/pump_reference.py --ch5 > crates/rhonn/tests/data/thesis_ch5_reference.csv
With --ch5 the state is [P_l, x, xhat_1, xhat_2, w_11, w_12, w_21, w_22]:
dxhat_i = -a_i xhat_i + w_i . z, dw_i = -gamma_i z e_i (- sigma_i gamma_i w_i while |w_i| > M_i),
z = [logistic(P_l), logistic(x)], e_i = xhat_i - chi_i, A = (120, 41), gamma = (1e4, 30).
Needs numpy and scipy; it is not part of the test command (its output is committed).
"""
import sys
import numpy as np
from scipy.integrate import solve_ivp

V0, beta, alpha_v, Pmax = 0.25e-3, 1.2e9, 0.04e-6, 25e6
kl, omega, Q0 = 0.6e-3, 200.0, 0.13e-3
Aa, xmax, mu1, mu2 = 5e-4, 0.024, 78e-6, 78e-6
phi, Kc, Ka, K, Fu, gam, P0 = 28.0, 27300.0, 1300.0, 8300.0, 400.0, 0.2, 0.4e6


def current(t):
    if t <= 15.0:
        i = 0.8 * t / 15.0
    elif t <= 25.0:
        i = 0.8
    elif t <= 40.0:
        i = 0.8 * (40.0 - t) / 15.0
    else:
        i = 0.0
    return min(max(i, 0.0), 0.8)


def pilot(t, y, branch):
    P, x = y[0], y[1]
    s = (phi * current(t) - Ka * x) / (Kc + Ka)
    if branch >= 0:
        dPa = gam * P + (Fu - K * x) / Aa - P0
    else:
        dPa = (1 - gam) * P - (Fu - K * x) / Aa
    Qa = np.sign(dPa) * s * (mu1 + mu2 * abs(s)) * np.sqrt(abs(dPa))
    return s, dPa, Qa


CH5 = "--ch5" in sys.argv
A_ID, GAMMA, M_ID, SIGMA = (120.0, 41.0), (1e4, 30.0), (1e10, 10.0), (0.01, 0.01)


def logistic(v):
    return 1.0 / (1.0 + np.exp(-v)) if v > -700 else 0.0


def unclamped(t, y, branch):
    P, x = y[0], y[1]
    s, dPa, Qa = pilot(t, y, branch)
    leak = abs(Qa) if branch < 0 else 0.0
    Vl = V0 * (1 + alpha_v * P)
    dP = beta / Vl * (kl * omega * x - 0.0 - Q0 - leak)
    dx = Qa / Aa
    if not CH5:
        return np.array([dP, dx])
    z = np.array([logistic(P), logistic(x)])
    out = [dP, dx, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]
    for i in range(2):
        w = np.array(y[4 + 2 * i: 6 + 2 * i])
        e = y[2 + i] - y[i]
        out[2 + i] = -A_ID[i] * y[2 + i] + w @ z
        dw = -GAMMA[i] * z * e
        if np.linalg.norm(w) > M_ID[i]:
            dw = dw - SIGMA[i] * GAMMA[i] * w
        out[4 + 2 * i: 6 + 2 * i] = dw
    return np.array(out)


def modes_at(t, y, branch_hint):
    s, _, _ = pilot(t, y, 0)
    if s > 0:
        branch = 1
    elif s < 0:
        branch = -1
    else:
        branch = branch_hint
    f = unclamped(t, y, branch)
    held = []
    for i, (lo, hi) in enumerate([(0.0, Pmax), (0.0, xmax)]):
        if y[i] <= lo and f[i] <= 0:
            held.append(-1)
        elif y[i] >= hi and f[i] >= 0:
            held.append(1)
        else:
            held.append(0)
    return branch, held


def simulate(t_end=40.0):
    breaks = [0.0, 15.0, 25.0, 40.0]
    t, y = 0.0, np.array([2e6, 0.0] + ([0.0] * 6 if CH5 else []))
    branch, held = modes_at(t, y, 1)
    nev = 0
    stalls = 0
    dpa_sign = 1 if pilot(t, y, branch)[1] >= 0 else -1
    bounds = [(0.0, Pmax), (0.0, xmax)]
    while t < t_end - 1e-15:
        t_next = min(b for b in breaks + [t_end] if b > t + 1e-15)
        br, hd = branch, list(held)

        def rhs(tt, yy):
            f = unclamped(tt, yy, br)
            for i in range(2):
                if hd[i] != 0:
                    f[i] = 0.0
            return f

        # each event: (function, direction, transition)
        evs = []

        def ev_s(tt, yy):
            return pilot(tt, yy, br)[0]
        ev_s.direction = -1 if br > 0 else 1
        evs.append((ev_s, ("branch", -br)))

        def ev_dpa(tt, yy):
            return pilot(tt, yy, br)[1]
        ev_dpa.direction = -dpa_sign
        evs.append((ev_dpa, ("dpa",)))
        for i, (lo, hi) in enumerate(bounds):
            if hd[i] == 0:
                f_lo = lambda tt, yy, i=i, lo=lo: yy[i] - lo
                f_lo.direction = -1
                evs.append((f_lo, ("held", i, -1)))
                f_hi = lambda tt, yy, i=i, hi=hi: yy[i] - hi
                f_hi.direction = 1
                evs.append((f_hi, ("held", i, 1)))
            else:
                f_l = lambda tt, yy, i=i: unclamped(tt, yy, br)[i]
                f_l.direction = 1 if hd[i] < 0 else -1
                evs.append((f_l, ("held", i, 0)))
        for f, _ in evs:
            f.terminal = True
        atol = [1e-6, 1e-15] + ([1e-6, 1e-15, 1e-3, 1e-3, 1e-12, 1e-12] if CH5 else [])
        sol = solve_ivp(rhs, (t, t_next), y, method="DOP853", rtol=1e-12, atol=atol,
                        events=[f for f, _ in evs], dense_output=True, max_step=0.01)
        tn = sol.t[-1]
        yn = sol.y[:, -1].copy()
        segs.append(sol.sol)
        seg_t.append((sol.t[0], tn))
        if sol.status == 1:
            nev += 1
            for k, (f, tr) in enumerate(evs):
                if len(sol.t_events[k]) > 0:
                    if tr[0] == "branch":
                        branch = tr[1]
                        dpa_sign = 1 if pilot(tn, yn, branch)[1] >= 0 else -1
                    elif tr[0] == "dpa":
                        dpa_sign = -dpa_sign
                    elif tr[0] == "held":
                        held[tr[1]] = tr[2]
                        if tr[2] != 0:
                            yn[tr[1]] = bounds[tr[1]][0 if tr[2] < 0 else 1]
                    break
        else:
            branch, held = modes_at(tn, yn, branch)
            dpa_sign = 1 if pilot(tn, yn, branch)[1] >= 0 else -1
        stalls = stalls + 1 if tn <= t else 0
        if stalls > 4:
            raise RuntimeError(f"no progress at t={t}")
        t, y = tn, yn
    return nev


segs, seg_t = [], []


def main():
    nev = simulate()
    grid = np.round(np.arange(0, 40000 + 1) * 1e-3, 9)
    out = sys.stdout
    out.write("t,p_line,stroke" + (",p_line_hat,stroke_hat" if CH5 else "") + "\n")
    k = 0
    for tt in grid:
        while k + 1 < len(seg_t) and tt > seg_t[k][1]:
            k += 1
        y = segs[k](tt)
        p = min(max(y[0], 0.0), Pmax)
        x = min(max(y[1], 0.0), xmax)
        extra = f",{y[2]:.6f},{y[3]:.12e}" if CH5 else ""
        out.write(f"{tt:.3f},{p:.6f},{x:.12e}{extra}\n")
    print(f"segments: {len(seg_t)}, events: {nev}", file=sys.stderr)


if __name__ == "__main__":
    main()
