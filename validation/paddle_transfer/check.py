#!/usr/bin/python3
"""The paddles' transfer functions (issue 59, check 1; cases/paddle_transfer.yaml).

A first-order piston and a flap hinged at the bed (law: regular, with active absorption) in h0 = 0.4 m make a regular
wave at kh = 0.5, 1 and 2 (T = 2.639, 1.454, 0.914 s; L = 5.03, 2.51, 1.26 m); the stroke is H/m1(kh), the piston's
m1 = 2 (cosh 2kh - 1)/(sinh 2kh + 2kh) (Biesel), the flap's m1 = 4 sinh kh (kh sinh kh - cosh kh + 1)/(kh (sinh 2kh +
2kh)) (Dean & Dalrymple 1991 §6.3; docs/numerics.md §15). Each flume is 3 L long with a sponge over its second half's 1.5 L; the wave
height is read one wavelength from the paddle. Heights: H = 0.02 m at kh = 0.5 (Ursell number H L²/h³ = 7.9), 0.03 m
at kh = 1 and 2 (H/L = 0.012 and 0.024).
Metrics for each kh, over the 10 periods after the fully grown wave arrives (t0 = ramp + L/cg, the ramp 2 T):
  a. the run reaches t_end, fluid mass exact;
  b. the mean of the 10 period heights (max - min) within 5 % of H (issue 59 check 1), at h0/dx = 20 (fine) or 13
     (coarse: 10 %);
  c. (information) the mean level's drift over the window, the mean zero-crossing period.
Modes: fine dx = 0.02 (h0/dx = 20), both paddles; coarse dx = 0.03 (h0/dx = 13, the paddle box 4 dx thick; kh = 1,
the flap only: validation/regular_waves covers the piston in CTest).
Usage: /usr/bin/python3 validation/paddle_transfer/check.py [--mode coarse|fine] [--sphflume PATH] [--out DIR] [--reuse]
"""
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "python"))
from common import Report, info, level_series, parse_sets, run_case, run_metrics, save_figure, validation_args  # noqa: E402
import sphflume.waves as W  # noqa: E402

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
CASE = os.path.normpath(os.path.join(HERE, "..", "..", "cases", "paddle_transfer.yaml"))
NAME = "paddle_transfer"
G, H0 = 9.81, 0.4
WAVES = {0.5: 0.02, 1.0: 0.03, 2.0: 0.03}  # kh: H
MODES = {"coarse": {"dx": 0.03, "tol": 0.10, "runs": [("flap", 1.0)]},
         "fine": {"dx": 0.02, "tol": 0.05, "runs": [(p, kh) for p in ("piston", "flap") for kh in (0.5, 1.0, 2.0)]}}
PERIODS = 10


def transfer(kh, paddle):
    if paddle == "flap":
        return 4 * math.sinh(kh) * (kh * math.sinh(kh) - math.cosh(kh) + 1) / (kh * (math.sinh(2 * kh) + 2 * kh))
    return 2 * (math.cosh(2 * kh) - 1) / (math.sinh(2 * kh) + 2 * kh)


def main():
    a = validation_args(NAME, __doc__, MODES)
    m = MODES[a.mode]
    rep = Report()
    fig, axes = plt.subplots(len(m["runs"]), 1, figsize=(11, 2.2 * len(m["runs"]) + 1), squeeze=False)
    for ax, (paddle, kh) in zip(axes[:, 0], m["runs"]):
        H = WAVES[kh]
        k = kh / H0
        w = math.sqrt(G * k * math.tanh(kh))
        T, L = 2 * math.pi / w, 2 * math.pi / k
        cg = 0.5 * (w / k) * (1 + 2 * kh / math.sinh(2 * kh))
        ramp = 2 * T
        t0 = ramp + L / cg
        end = t0 + (PERIODS + 1) * T
        sets = {"particles.dx": m["dx"], "time.end": f"{end:.4f}", "motions.0.period": f"{T:.6f}",
                "motions.0.height": H, "motions.0.ramp": f"{ramp:.4f}",
                "geometry.0.max": f"[{3 * L:.4f}, 0.7]", "geometry.2.max": f"[{3 * L:.4f}, 0.4]",
                "forces.0.start": f"{1.5 * L:.4f}", "forces.0.end": f"{3 * L:.4f}", "forces.0.rate": f"{10 / T:.4f}",
                "gauges.2.x": f"{L:.4f}", **parse_sets(a.set)}
        if paddle == "flap":
            sets.update({"motions.0.paddle": "flap", "motions.0.hinge": "[0.0, 0.0]"})
        out = os.path.join(a.out, f"{paddle}_kh{kh:g}_dx{m['dx']:g}")
        print(f"\n{paddle}, kh = {kh}: T = {T:.4f} s, L = {L:.4f} m, cg = {cg:.4f} m/s, H = {H} m, stroke H/m1 = "
              f"{1000 * H / transfer(kh, paddle):.2f} mm; window from {t0:.2f} s")
        s, wall, rc = run_case(a.sphflume, CASE, out, sets, a.threads, a.reuse)
        if s is None:
            rep.metric(f"{paddle}, kh = {kh}: run exit code", rc, False, "0", "the run")
            continue
        run_metrics(rep, f"{paddle}, kh = {kh}: ", s, float(sets["time.end"]))
        t, eta = level_series(out, "eta_L")
        seg = [(t >= t0 + i * T) & (t < t0 + (i + 1) * T) for i in range(PERIODS)]
        hs = np.array([eta[q].max() - eta[q].min() for q in seg])
        pm = np.array([eta[q].mean() for q in seg])
        Hm = float(hs.mean())
        err = Hm / H - 1
        rep.metric(f"{paddle}, kh = {kh}: wave height one wavelength from the paddle (mean of {PERIODS} periods)",
                   f"{1000 * Hm:.2f} mm ({100 * err:+.1f} %)", abs(err) <= m["tol"],
                   f"within {100 * m['tol']:g} % of {1000 * H:g} mm", "issue 59 check 1: the transfer function")
        drift = np.polyfit(t0 + (np.arange(PERIODS) + 0.5) * T, pm, 1)[0] * PERIODS * T
        info(f"{paddle}, kh = {kh}: mean-level drift over the window", f"{1000 * drift:+.2f} mm", abs(drift) <= 0.05 * H, "5 % of H",
             "no drift")
        wz = (t >= t0) & (t < t0 + PERIODS * T)
        zc = W.zero_crossing(t[wz], eta[wz])
        info(f"{paddle}, kh = {kh}: mean zero-crossing period", f"{zc['Tz']:.4f} s ({100 * (zc['Tz'] / T - 1):+.2f} %)",
             abs(zc["Tz"] / T - 1) <= 0.01, "1 % of T", "the paddle's period")
        info(f"{paddle}, kh = {kh}: wall time", f"{wall:.0f} s ({s['particles']['total']} particles, {s['steps']} steps)", True, "-", "cost")
        ax.plot(t, 1000 * eta, lw=0.8)
        ax.axvspan(t0, t0 + PERIODS * T, color="0.9")
        for v in (H / 2, -H / 2):
            ax.axhline(1000 * v, color="k", ls=":", lw=0.8)
        ax.set_ylabel(f"{paddle}\nkh = {kh}\neta [mm]")
    axes[-1, 0].set_xlabel("t [s]")
    axes[0, 0].set_title(f"paddle transfer functions at x = L, h0 = {H0} m, dx = {m['dx']} m (grey: the {PERIODS}-period windows; "
                         "dotted: ±H/2)")
    fig.tight_layout()
    save_figure(fig, HERE, NAME, a.mode, a.out)
    rep.finish(NAME, a.mode)
    return 0


if __name__ == "__main__":
    sys.exit(main())
