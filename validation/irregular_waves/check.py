#!/usr/bin/python3
"""An irregular sea from a JONSWAP spectrum (issue 59, check 2; cases/irregular_waves.yaml).

JONSWAP, gamma = 3.3, Hm0 = 0.04 m, Tp = 1.5 s in h0 = 0.4 m (at the peak L_p = 2.62 m, kh = 0.96), made by a piston
with active absorption (the `irregular` law: 500 components over [0.5, 3]/Tp with seeded random phases, each through
the piston's transfer function; docs/numerics.md §15), a sponge over the last 4 m. The paddle writes the sea it makes
to motions/paddle.components.csv; the linear target at a gauge x is the sum of those components,
eta_T(x, t) = sum a cos(2 pi f (t - start) + phase - k x).
Metrics at eta_2L (x = 5.24 m, two peak wavelengths from the paddle; coarse: eta_1L), over the window that opens when the sea's ramp
has passed the gauge at the peak's group velocity (t0 = ramp + x/cg_p) and runs to the end:
  a. the run reaches t_end, fluid mass exact;
  b. the window holds at least 100 peak periods (fine mode);
  c. Hm0 (4 sqrt(m0) of the record) within 5 % of the target 0.04 m (issue 59 check 2);
  d. Tp (the peak of Welch's spectrum, parabola-refined) within 5 % of 1.5 s;
  e. (information) the same against the linear target's record over the same window (what the paddle's sea gives
     in that window: the statistical scatter of a finite record is taken out), H1/3, Hmax, the number of waves,
     the reflection coefficient from the three gauges at 4.98, 5.24, 5.63 m, and eta_1L (one wavelength).
The figure draws the measured spectrum over the target's (and the target record's), the record, and the paddle.
Modes: fine dx = 0.02 (h0/dx = 20) to 162.5 s (100 Tp at the gauge); coarse (CTest) dx = 0.03 (h0/dx = 13; the paddle
box is 5 dx thick) to 25 s, read at eta_1L (one wavelength, x = 2.62 m, about 11 Tp): a short record's Hm0 scatters by
several per cent about the spectrum's, so the coarse mode gates Hm0 against the linear target's record over the same
window, within 8 %: the fine gate's 5 % widened by the spacing's ratio 1.5 (the numerical damping falls about first order
in dx; validation/irregular_waves/README.md). Measured at h = 2.5 dx: -4.1 % (session 35); at the old h = 2 dx it was
-8.3 to -9.5 %, which this gate would catch.
Usage: /usr/bin/python3 validation/irregular_waves/check.py [--mode coarse|fine] [--sphflume PATH] [--out DIR] [--reuse]
"""
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "python"))
from common import Report, info, level_series, parse_sets, read_rows, run_case, run_metrics, save_figure, validation_args  # noqa: E402
import sphflume.waves as W  # noqa: E402

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
CASE = os.path.normpath(os.path.join(HERE, "..", "..", "cases", "irregular_waves.yaml"))
NAME = "irregular_waves"
H0, HM0, TP, GAMMA, RAMP = 0.4, 0.04, 1.5, 3.3, 7.5
XS = {"eta_a": 4.98, "eta_2L": 5.24, "eta_b": 5.63}
MODES = {"coarse": {"dx": 0.03, "end": 25.0, "tol": 0.08, "min_periods": 0, "gauge": ("eta_1L", 2.62)},
         "fine": {"dx": 0.02, "end": 162.5, "tol": 0.05, "min_periods": 100, "gauge": ("eta_2L", 5.24)}}


def main():
    a = validation_args(NAME, __doc__, MODES)
    m = MODES[a.mode]
    out = os.path.join(a.out, f"dx{m['dx']:g}")
    sets = {"particles.dx": m["dx"], "time.end": m["end"], **parse_sets(a.set)}
    s, wall, rc = run_case(a.sphflume, CASE, out, sets, a.threads, a.reuse)
    print(f"\n== {NAME} ({a.mode}: dx = {m['dx']} m, end {m['end']} s; run wall time {wall:.1f} s)")
    if s is None:
        print(f"[FAIL] run exit code = {rc}   (threshold: 0)")
        return 2
    rep = Report()
    run_metrics(rep, "", s, m["end"])
    fp = 1 / TP
    kp = W.wave_number(fp, H0)[0]
    cg = 0.5 * (2 * math.pi * fp / kp) * (1 + 2 * kp * H0 / math.sinh(2 * kp * H0))
    print(f"peak: L = {2 * math.pi / kp:.3f} m, kh = {kp * H0:.3f}, cg = {cg:.3f} m/s")
    hdr, comp = read_rows(os.path.join(out, "motions", "paddle.components.csv"))
    cf, ca, ck, cph = (comp[:, hdr.index(k)] for k in ("frequency", "amplitude", "wave_number", "phase"))

    def target(x, t):
        return np.sum(ca[:, None] * np.cos(2 * np.pi * cf[:, None] * t[None, :] + cph[:, None] - ck[:, None] * x), axis=0)

    GAUGE, XG = m["gauge"]
    t0 = RAMP + XG / cg
    print(f"gauge {GAUGE} (x = {XG} m): window from {t0:.2f} s")
    t, eta = level_series(out, GAUGE)
    w = t >= t0
    npk = (t[w][-1] - t[w][0]) / TP
    if m["min_periods"]:
        rep.metric("window length", f"{npk:.1f} Tp", npk >= m["min_periods"], f">= {m['min_periods']} Tp", "issue 59 check 2")
    f, S = W.spectrum(t[w], eta[w])
    st = W.spectral_stats(f, S)
    eT = target(XG, t[w])
    fT, ST = W.spectrum(t[w], eT)
    stT = W.spectral_stats(fT, ST)
    err = st["Hm0"] / HM0 - 1
    errT = st["Hm0"] / stT["Hm0"] - 1
    if a.mode == "fine":
        rep.metric(f"{GAUGE} (x = {XG} m): Hm0", f"{1000 * st['Hm0']:.2f} mm ({100 * err:+.1f} %)", abs(err) <= m["tol"],
                   f"within {100 * m['tol']:g} % of {1000 * HM0:g} mm", "issue 59 check 2")
        rep.metric(f"{GAUGE}: Tp", f"{st['Tp']:.3f} s ({100 * (st['Tp'] / TP - 1):+.1f} %)",
                   abs(st["Tp"] / TP - 1) <= m["tol"], f"within {100 * m['tol']:g} % of {TP} s", "issue 59 check 2")
        info(f"{GAUGE}: Hm0 against the linear target's record over the window", f"{100 * errT:+.1f} % (target record "
             f"{1000 * stT['Hm0']:.2f} mm)", abs(errT) <= m["tol"], "-", "the paddle's sea at the gauge, linear theory")
    else:
        rep.metric(f"{GAUGE}: Hm0 against the linear target's record over the same window",
                   f"{1000 * st['Hm0']:.2f} against {1000 * stT['Hm0']:.2f} mm ({100 * errT:+.1f} %)", abs(errT) <= m["tol"],
                   f"within {100 * m['tol']:g} %", "issue 59 check 2 (coarse: a short record)")
        info(f"{GAUGE}: Hm0 against the spectrum's", f"{1000 * st['Hm0']:.2f} mm ({100 * err:+.1f} %)", abs(err) <= 0.05,
             "5 %", "a short record scatters")
        info(f"{GAUGE}: Tp", f"{st['Tp']:.3f} s (target record {stT['Tp']:.3f} s)", True, "-", "a short record")
    zc = W.zero_crossing(t[w], eta[w])
    zT = W.zero_crossing(t[w], eT)
    info(f"{GAUGE}: H1/3, Hmax, waves (target record's)", f"{1000 * zc['H1/3']:.1f}, {1000 * zc['Hmax']:.1f} mm, "
         f"{zc['N']} ({1000 * zT['H1/3']:.1f}, {1000 * zT['Hmax']:.1f} mm, {zT['N']})", True, "-", "zero down-crossing")
    info(f"{GAUGE}: Tm-1,0, Tm02", f"{st['Tm-1,0']:.3f}, {st['Tm02']:.3f} s (target record {stT['Tm-1,0']:.3f}, "
         f"{stT['Tm02']:.3f} s)", True, "-", "spectral periods")
    ser = {}
    for g in XS:
        ser[g] = level_series(out, g)[1]
    rr = W.reflection(t[w], [ser[g][w] for g in XS], list(XS.values()), H0, fmin=0.5 * fp, fmax=3 * fp)
    info("reflection coefficient at 5.24 m (Mansard & Funke, [0.5, 3] fp)", f"{100 * rr['Kr']:.1f} % (incident Hm0 "
         f"{1000 * rr['Hm0_I']:.2f} mm)", True, "-", "sponge and paddle")
    e1 = level_series(out, "eta_1L")[1]
    w1 = t >= RAMP + 2.62 / cg
    st1 = W.spectral_stats(*W.spectrum(t[w1], e1[w1]))
    info("eta_1L (x = 2.62 m): Hm0", f"{1000 * st1['Hm0']:.2f} mm ({100 * (st1['Hm0'] / HM0 - 1):+.1f} %)", True, "-",
         "one wavelength from the paddle")

    fig, ax = plt.subplots(3, 1, figsize=(11, 10))
    band = (cf.min() - 1e-9, cf.max() + 1e-9)
    fs = np.linspace(0.01, 3 * fp * 1.2, 600)
    Sj = W.jonswap(fs, fp, GAMMA)
    inb = (fs >= band[0]) & (fs <= band[1])
    Sj *= (HM0 / 4) ** 2 / np.trapz(Sj[inb], fs[inb])
    Sj[~inb] = 0
    ax[0].plot(fs, Sj, "k--", label=f"target JONSWAP (Hm0 {1000 * HM0:g} mm, Tp {TP} s, γ {GAMMA})")
    ax[0].plot(fT, ST, color="0.6", label=f"linear target's record at {XG} m (Hm0 {1000 * stT['Hm0']:.1f} mm)")
    ax[0].plot(f, S, color="C0", label=f"measured at {XG} m (Hm0 {1000 * st['Hm0']:.1f} mm, Tp {st['Tp']:.2f} s)")
    ax[0].set_xlim(0, 3.5 * fp)
    ax[0].set_xlabel("f [Hz]")
    ax[0].set_ylabel("S [m²/Hz]")
    ax[0].legend(fontsize=8)
    ax[0].set_title(f"irregular waves, dx = {m['dx']} m (window {t[w][0]:.1f}-{t[w][-1]:.1f} s, {npk:.0f} Tp)")
    ax[1].plot(t, 1000 * eta, lw=0.6, label="measured")
    ax[1].plot(t[w], 1000 * eT, lw=0.6, alpha=0.7, label="linear target")
    ax[1].set_xlim(t0, min(t0 + 30, t[-1]))
    ax[1].set_ylabel(f"eta at {XG} m [mm]")
    ax[1].legend(fontsize=8)
    hp, rp = read_rows(os.path.join(out, "gauges", "paddle.csv"))
    ax[2].plot(rp[:, 0], 1000 * rp[:, hp.index("displacement")], lw=0.6)
    ax[2].set_ylabel("paddle [mm]")
    ax[2].set_xlabel("t [s]")
    fig.tight_layout()
    save_figure(fig, HERE, NAME, a.mode, a.out)
    print(f"  wall {wall:.1f} s, {s['steps']} steps, {s['particles']['total']} particles, "
          f"{s['particle_steps_per_second']:.3g} particle-steps/s")
    rep.finish(NAME, a.mode)
    return 0


if __name__ == "__main__":
    sys.exit(main())
