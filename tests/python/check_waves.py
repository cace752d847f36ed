#!/usr/bin/python3
"""sphflume.waves (issue 59) against signals whose answers are known in closed form.

Usage: check_waves.py

1. Spectrum: a sum of 500 random-phase components of a JONSWAP spectrum (γ = 3.3, Hm0 = 0.1 m,
   Tp = 1.5 s) at whole multiples of 1/(200 Tp): Hm0 from the spectrum within 1 % (Parseval: the
   record's variance is Σ a²/2) and Tp within one Welch bin of 1.5 s.
2. Zero crossing: a regular wave of height 0.08 m and period 1.2 s gives H1/3 = Hmax = 0.08 m
   (sampling at T/60: the crest read within 1 − cos(π/60) = 0.14 %) and Tz = 1.2 s within 0.1 %.
3. Reflection (Mansard & Funke 1980): an incident JONSWAP sea and its reflection with K_r = 0.35
   and a phase shift, at three gauges of spacings 0.19 and 0.5 m in 0.4 m of water: K_r within 0.01
   and the incident Hm0 within 1 %; the same with K_r = 0 gives below 0.01.
4. Overtopping: a volume rising at q = 2e-4 m³/s/m after 5 s gives q over [5, 20] s to 1e-12.
5. analyse() on a folder written like a run's gauges: waves.json holds the same numbers and a
   PNG per gauge is written.
Exit 0 when every check passes, 1 otherwise."""
import json
import os
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "python"))
import sphflume.waves as W  # noqa: E402


def sea(t, hm0, tp, x=0.0, depth=0.4, seed=3, kr=0.0, shift=0.7):
    """η at x of an incident sea travelling +x and its reflection (travelling −x) of ratio kr; the
    components at whole multiples of 1/(record's length), so the record's variance is Σ a²/2."""
    rng = np.random.default_rng(seed)
    fp = 1 / tp
    span = t[-1] - t[0] + (t[1] - t[0])
    f = np.arange(np.ceil(0.5 * fp * span), np.floor(3 * fp * span) + 1) / span
    n = len(f)
    df = 1 / span
    S = W.jonswap(f, fp)
    S *= (hm0 / 4) ** 2 / np.sum(S * df)
    a = np.sqrt(2 * S * df)
    ph = rng.uniform(0, 2 * np.pi, n)
    k = W.wave_number(f, depth)
    w = 2 * np.pi * f
    eta = np.zeros_like(t)
    for ai, wi, ki, pi in zip(a, w, k, ph):
        eta += ai * np.cos(wi * t - ki * x + pi)
        if kr:
            eta += kr * ai * np.cos(wi * t + ki * x + pi + shift)
    return eta


def main():
    failures = []

    def check(ok, what):
        print(("[PASS] " if ok else "[FAIL] ") + what)
        if not ok:
            failures.append(what)

    tp, hm0 = 1.5, 0.1
    t = np.arange(0, 200 * tp, 0.02)
    eta = sea(t, hm0, tp)
    f, S = W.spectrum(t, eta)
    st = W.spectral_stats(f, S)
    check(abs(st["Hm0"] / hm0 - 1) < 0.01, f"Welch Hm0 {st['Hm0']:.5f} m within 1 % of {hm0}")
    check(abs(st["Tp"] - tp) < tp * tp * (f[1] - f[0]), f"Tp {st['Tp']:.4f} s within one bin of {tp} s")

    T, H = 1.2, 0.08
    tr = np.arange(0, 30, T / 60)
    zc = W.zero_crossing(tr, 0.5 * H * np.cos(2 * np.pi * tr / T))
    check(abs(zc["H1/3"] / H - 1) < 2e-3 and abs(zc["Hmax"] / H - 1) < 2e-3,
          f"regular wave: H1/3 {zc['H1/3']:.5f}, Hmax {zc['Hmax']:.5f} m (H = {H})")
    check(abs(zc["Tz"] / T - 1) < 1e-3, f"regular wave: Tz {zc['Tz']:.5f} s (T = {T})")

    xs = [2.3, 2.49, 2.8]
    for kr in (0.35, 0.0):
        etas = [sea(t, hm0, tp, x=x, kr=kr) for x in xs]
        rr = W.reflection(t, etas, xs, 0.4)
        check(abs(rr["Kr"] - kr) < 0.01, f"Mansard & Funke: Kr {rr['Kr']:.4f} (true {kr})")
        check(abs(rr["Hm0_I"] / hm0 - 1) < 0.01, f"Mansard & Funke: incident Hm0 {rr['Hm0_I']:.5f} m (true {hm0})")

    tv = np.arange(0, 20.0001, 0.1)
    vol = 0.3 + 2e-4 * np.maximum(tv - 5.0, 0.0)
    ov = W.overtopping(tv, vol, 5.0, 20.0)
    check(abs(ov["q"] - 2e-4) < 1e-12, f"overtopping q {ov['q']:.6g} m³/s/m (true 2e-4)")

    with tempfile.TemporaryDirectory() as d:
        os.makedirs(os.path.join(d, "gauges"))
        with open(os.path.join(d, "summary.json"), "w") as fs:
            fs.write("{}")
        for name, x in zip(["eta_1", "eta_2", "eta_3"], xs):
            e = sea(t, hm0, tp, x=x, kr=0.35)
            np.savetxt(os.path.join(d, "gauges", name + ".csv"), np.column_stack([t, e]), delimiter=",",
                       header="time,level", comments="")
        np.savetxt(os.path.join(d, "gauges", "over.csv"), np.column_stack([tv, vol]), delimiter=",",
                   header="time,volume", comments="")
        rep = W.analyse(d, depth=0.4, reflection_gauges=dict(zip(["eta_1", "eta_2", "eta_3"], xs)), t0=5.0)
        with open(os.path.join(d, "plots", "waves.json")) as fj:
            js = json.load(fj)
        check(abs(js["reflection"]["Kr"] - 0.35) < 0.01, f"analyse(): waves.json Kr {js['reflection']['Kr']:.4f}")
        check(abs(js["gauges"]["over"]["q"] - 2e-4) < 1e-9, "analyse(): waves.json overtopping q")
        check(len(rep["figures"]) == 3 and all(os.path.getsize(p) > 10000 for p in rep["figures"]),
              "analyse(): a PNG (> 10 kB) per level gauge")
    print(f"{len(failures)} failure(s)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
