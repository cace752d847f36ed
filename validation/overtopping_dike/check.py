#!/usr/bin/python3
"""Wave overtopping of a smooth 1:3 dike (issue 59, check 5; cases/overtopping_dike.yaml).

JONSWAP sea (gamma = 3.3, Hm0 = 0.06 m, Tp = 1.4 s) in h0 = 0.4 m from an absorbing piston; a smooth impermeable 1:3 dike
(toe 5 m from the paddle), freeboards Rc/Hm0 = 1.0 and 1.5 (crest at 0.46 and 0.49 m), a 0.1 m crest; the domain
ends at the crest's landward edge (a catch tank). The `overtopping` gauge gives the volume past that edge (including
what left the domain there); its slope over the window is the mean
discharge q (sphflume.waves.overtopping). The incident sea is separated at 2.5, 2.74, 3.13 m (Mansard & Funke 1980):
its Hm0 and spectral period Tm-1,0 enter the formula, as EurOtop prescribes (the incident wave at the toe).

EurOtop (2018, 2nd ed., eqs 5.10 and 5.11), mean value approach, smooth slope (all gamma factors 1):
  q / sqrt(g Hm0^3) = 0.023 / sqrt(tan a) xi exp(-(2.7 Rc / (xi Hm0))^1.3),  xi = tan a / sqrt(2 pi Hm0 / (g Tm-1,0^2)),
  with at most 0.09 exp(-(1.5 Rc / Hm0)^1.3);
the coefficients' standard deviations (0.003, 0.2; 0.0135, 0.15) give the 90 % band: q with every coefficient moved by
1.645 sigma towards less overtopping and towards more.
Metrics (each freeboard), over the window from t0 = 10 s (the sea's ramp and travel to the dike) to the end:
  a. the run reaches t_end, fluid mass exact;
  b. q within EurOtop's 90 % band at the measured incident Hm0 and Tm-1,0 (issue 59 check 5);
  c. (information) q against the formula's mean, the incident Hm0 and Tm-1,0 against the target, K_r of the dike,
     the number of waves, the wall time; with --mode fine the dx = 0.02 runs beside (the convergence).
Modes: fine dx = 0.01 (h0/dx = 40, Hm0/dx = 6) and dx = 0.02 for the convergence, 212.8 s (150 Tp); coarse dx = 0.02 to
60 s (a smoke run of the whole chain, about 40 waves: gated against the band all the same). Not in CTest (hours).
Usage: /usr/bin/python3 validation/overtopping_dike/check.py [--mode coarse|fine] [--dx DX] [--ratio R] [--sphflume PATH] [--out DIR] [--reuse]
"""
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "python"))
from common import Report, add_spacing_option, info, level_series, parse_sets, read_rows, run_case, run_metrics, save_figure, select_spacings, validation_args  # noqa: E402
import sphflume.waves as W  # noqa: E402

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
CASE = os.path.normpath(os.path.join(HERE, "..", "..", "cases", "overtopping_dike.yaml"))
NAME = "overtopping_dike"
G, H0, HM0, TP = 9.81, 0.4, 0.06, 1.4
TAN_A, TOE, CREST_W = 1.0 / 3.0, 5.0, 0.1
XS = {"eta_a": 2.5, "eta_b": 2.74, "eta_c": 3.13}
T0 = 10.0
MODES = {"coarse": {"runs": [(0.02, 1.0)], "end": 60.0},
         "fine": {"runs": [(0.01, 1.0), (0.01, 1.5), (0.02, 1.0), (0.02, 1.5)], "end": 212.8}}


def eurotop(hm0, tm, rc, shift=0.0):
    """q [m³/s/m] from EurOtop eqs 5.10/5.11 with every coefficient moved by `shift` standard deviations towards more
    overtopping (negative: less)."""
    s = 2 * math.pi * hm0 / (G * tm * tm)
    xi = TAN_A / math.sqrt(s)
    a, b = 0.023 + shift * 0.003, 2.7 - shift * 0.2
    c, d = 0.09 + shift * 0.0135, 1.5 - shift * 0.15
    q_b = a / math.sqrt(TAN_A) * xi * math.exp(-((b * rc / (xi * hm0)) ** 1.3))
    q_n = c * math.exp(-((d * rc / hm0) ** 1.3))
    return min(q_b, q_n) * math.sqrt(G * hm0 ** 3), xi


def options(ap):
    add_spacing_option(ap)
    ap.add_argument("--ratio", type=float, action="append", default=[],
                    help="only the mode's runs at this Rc/Hm0 (repeatable; the runs are hours long: one per call)")


def main():
    a = validation_args(NAME, __doc__, MODES, options)  # (the runs are hours long: one spacing per call)
    m = MODES[a.mode]
    rep = Report()
    fig, ax = plt.subplots(2, 1, figsize=(10, 8))
    results = {}
    runs = select_spacings(m["runs"], a.only_spacings, key=lambda r: r[0])
    runs = [r for r in runs if not a.ratio or any(math.isclose(r[1], x) for x in a.ratio)]
    if not runs:
        raise SystemExit(f"--ratio {a.ratio}: no run at that freeboard (the mode's: {sorted({r[1] for r in m['runs']})})")
    for dx, ratio in runs:
        rc = ratio * HM0
        top = H0 + rc
        back = TOE + top / TAN_A + CREST_W
        sets = {"particles.dx": dx, "time.end": m["end"], "geometry.2.top": f"{top:.4f}", "geometry.2.back": f"{back:.4f}",
                "gauges.6.x": f"{back:.4f}", "domain.max": f"[{back:.4f}, 1.6]", **parse_sets(a.set)}
        out = os.path.join(a.out, f"rc{ratio:g}_dx{dx:g}")
        print(f"\nRc/Hm0 = {ratio}: crest z = {top:.3f} m, landward edge x = {back:.3f} m, dx = {dx}")
        s, wall, rc_ = run_case(a.sphflume, CASE, out, sets, a.threads, a.reuse)
        label = f"Rc/Hm0 {ratio:g}, dx {dx:g}"
        if s is None:
            rep.metric(f"{label}: run exit code", rc_, False, "0", "the run")
            continue
        run_metrics(rep, f"{label}: ", s, m["end"])
        series = {}
        for g in XS:
            series[g] = level_series(out, g)
        t = series["eta_a"][0]
        w = t >= T0
        fp = 1 / TP
        rr = W.reflection(t[w], [series[g][1][w] for g in XS], list(XS.values()), H0, fmin=0.5 * fp, fmax=3 * fp)
        f, SI = rr["f"], rr["S_I"]
        used = rr["used"]
        m0 = np.sum(SI[used]) * (f[1] - f[0])
        mm1 = np.sum(SI[used] / f[used]) * (f[1] - f[0])
        hm0_i, tm = 4 * math.sqrt(m0), mm1 / m0
        h, r = read_rows(os.path.join(out, "gauges", "over.csv"))
        ov = W.overtopping(r[:, 0], r[:, h.index("volume")], T0, r[-1, 0])
        q = ov["q"]
        q_mean, xi = eurotop(hm0_i, tm, rc)
        q_lo, _ = eurotop(hm0_i, tm, rc, -1.645)
        q_hi, _ = eurotop(hm0_i, tm, rc, +1.645)
        gate = dx == min(d for d, _ in runs)  # the finest spacing run (with --dx, the one asked for)
        (rep.metric if gate else info)(f"{label}: mean overtopping discharge q", f"{1000 * q:.4f} l/s/m (EurOtop mean "
                                       f"{1000 * q_mean:.4f}, {q / q_mean:.2f} x)", q_lo <= q <= q_hi,
                                       f"in EurOtop's 90 % band [{1000 * q_lo:.4f}, {1000 * q_hi:.4f}] l/s/m",
                                       "issue 59 check 5; EurOtop 2018 eqs 5.10-5.11")
        info(f"{label}: incident Hm0, Tm-1,0 (separated), xi", f"{1000 * hm0_i:.1f} mm ({100 * (hm0_i / HM0 - 1):+.1f} %), "
             f"{tm:.3f} s, {xi:.2f}; K_r {100 * rr['Kr']:.0f} %", True, "-", "the sea at the dike's toe")
        info(f"{label}: overtopped volume over the window", f"{1000 * (ov['volume'][-1] - np.interp(T0, ov['time'], ov['volume'])):.2f} l/m"
             f" ({(ov['window'][1] - ov['window'][0]) / TP:.0f} Tp); wall {wall:.0f} s", True, "-", "statistics")
        results[(dx, ratio)] = (q, q_lo, q_mean, q_hi)
        ax[0].plot(ov["time"], 1000 * ov["volume"], label=label)
    for (dx, ratio), (q, lo, mean, hi) in results.items():
        ax[1].errorbar([ratio + (0.02 if dx > 0.01 else 0)], [1000 * mean], yerr=[[1000 * (mean - lo)], [1000 * (hi - mean)]],
                       fmt="ks", capsize=4)
        ax[1].plot([ratio + (0.02 if dx > 0.01 else 0)], [1000 * q], "o", label=f"SPHFlume dx {dx:g}, Rc/Hm0 {ratio:g}")
    ax[0].set_xlabel("t [s]")
    ax[0].set_ylabel("overtopped volume [l/m]")
    ax[0].legend(fontsize=8)
    ax[1].set_yscale("log")
    ax[1].set_xlabel("Rc/Hm0")
    ax[1].set_ylabel("q [l/s/m] (black: EurOtop mean and 90 % band)")
    ax[1].legend(fontsize=8)
    fig.tight_layout()
    save_figure(fig, HERE, NAME, a.mode, a.out)
    rep.finish(NAME, a.mode)
    return 0


if __name__ == "__main__":
    sys.exit(main())
