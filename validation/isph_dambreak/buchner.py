#!/usr/bin/python3
"""Buchner's (2002) wall pressure under both schemes (issue 57, check 2): cases/dambreak_sphinxsys.yaml (a column
2H x H in a tank 5.366H long, g = 1, rho0 = 1, H = 1) run under WCSPH as it is (the dual integrator) and under ISPH
(`scheme.type: isph, scheme.formulation: lind`), to t = 7.5, the sensor gauge `p_sensor` (a face of 0.03 H at
z = 0.2 H on the downstream wall, the mean of the last 0.02 time units) against Buchner's measured history
(data/buchner_2002.csv, with its source), T = t sqrt(g/H), P = p/(rho g H).

Printed for each scheme, beside each other (information: the issue asks for the histories side by side; the
impact's time and the pressure after it are what issue 60 investigates for WCSPH):
  - the rise: the first output with P >= 0.3 (Buchner: 2.61);
  - the mean P over T in [3, 5.5] (after the impact, before the reflected wave returns) and [5.5, 7.3] (the
    plunging return), each against Buchner's mean over the same window (his points, linear between them);
  - the RMS of P_sim - P_exp at Buchner's points with T in [2, 7.36].
Gated: both runs reach t = 7.5 with the fluid mass exact.
Modes: fine dx = 0.0125 (the case's, SPHinXsys's resolution), coarse dx = 0.025.
Usage: /usr/bin/python3 validation/isph_dambreak/buchner.py [--mode coarse|fine] [--out DIR]
"""
import os
import sys

import numpy as np
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from common import Report, parse_sets, read_rows, run_case, save_figure, validation_args  # noqa: E402

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
CASE = os.path.normpath(os.path.join(HERE, "..", "..", "cases", "dambreak_sphinxsys.yaml"))
DATA = os.path.join(HERE, "data", "buchner_2002.csv")
NAME = "isph_dambreak_buchner"
MODES = {"coarse": {"dx": 0.025}, "fine": {"dx": 0.0125}}
END = 7.5
WINDOWS = ((3.0, 5.5), (5.5, 7.3))
SCHEMES = {"wcsph": {}, "isph": {"scheme.type": "isph", "scheme.formulation": "lind"}}


def window_mean(t, p, lo, hi):
    """The time mean of a piecewise-linear history over [lo, hi]."""
    tt = np.linspace(lo, hi, 2001)
    return float(np.mean(np.interp(tt, t, p)))


def main():
    a = validation_args(NAME, __doc__, MODES)
    m = MODES[a.mode]
    os.makedirs(a.out, exist_ok=True)
    _, e = read_rows(DATA)
    te, pe = e[:, 0], e[:, 1]
    rep = Report()
    hist = {}
    for k, extra in SCHEMES.items():
        out = os.path.join(a.out, f"{k}_dx{m['dx']:g}")
        s, wall, rc = run_case(a.sphflume, CASE, out, {"particles.dx": m["dx"], "time.end": END,
                                                       "time.output_interval": 0.02, **extra, **parse_sets(a.set)},
                               a.threads, a.reuse)
        ok = s is not None and s["simulated_time"] >= END * (1 - 1e-6) and abs(s["mass"]["relative_error"]) <= 1e-12
        rep.metric(f"{k}: run reached t = {END} with the fluid mass exact", f"exit {rc}", ok, "exit 0, |mass error| <= 1e-12", "run")
        if s is None:
            continue
        h, g = read_rows(os.path.join(out, "gauges", "p_sensor.csv"))
        t, p = g[:, 0], np.nan_to_num(g[:, h.index("pressure")])
        hist[k] = (t, p, wall, s["steps"])
    print(f"\n== {NAME} ({a.mode}: dx = {m['dx']} H)")
    rise_e = float(te[np.argmax(pe >= 0.3)])
    print(f"  Buchner: rise (P >= 0.3) at T = {rise_e:.2f}; " + ", ".join(
        f"mean P over [{lo}, {hi}] = {window_mean(te, pe, lo, hi):.3f}" for lo, hi in WINDOWS))
    for k, (t, p, wall, steps) in hist.items():
        rise = float(t[np.argmax(p >= 0.3)]) if np.any(p >= 0.3) else float("nan")
        sel = (te >= 2.0) & (te <= min(7.36, t[-1]))
        rms = float(np.sqrt(np.mean((np.interp(te[sel], t, p) - pe[sel]) ** 2)))
        means = ", ".join(f"[{lo}, {hi}]: {window_mean(t, p, lo, hi):.3f} (Buchner {window_mean(te, pe, lo, hi):.3f})"
                          for lo, hi in WINDOWS)
        print(f"  (info) {k}: rise at T = {rise:.2f} (Buchner {rise_e:.2f}); mean P {means}; RMS vs Buchner over "
              f"T in [2, 7.36] = {rms:.3f} rho g H; {steps} steps, {wall:.1f} s wall")
    fig, ax = plt.subplots(figsize=(9, 4.5))
    ax.plot(te, pe, "ko", ms=3, label="Buchner (2002)")
    for k, (t, p, _, _) in hist.items():
        ax.plot(t, p, "-", lw=1, label=f"SPHFlume {k}{' (lind)' if k == 'isph' else ''}")
    ax.set_xlabel("t sqrt(g/H)")
    ax.set_ylabel("p / (rho g H)")
    ax.set_title(f"downstream wall, z = 0.2 H, dx = {m['dx']} H (sensor face 0.03 H)")
    ax.set_xlim(0, END)
    ax.legend()
    fig.tight_layout()
    save_figure(fig, HERE, NAME, a.mode, a.out)
    rep.finish(NAME, a.mode)


if __name__ == "__main__":
    main()
