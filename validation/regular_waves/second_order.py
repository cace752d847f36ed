#!/usr/bin/python3
"""The second-order paddle (Schäffer 1996, `second_order: true`) against the first-order one in the regular-wave flume
(cases/regular_waves.yaml: h0 = 0.4 m, T = 1.2 s, H = 0.04 m, kh = 1.30; issue 59).

A first-order piston sheds a free second harmonic (angular frequency 2ω, wave number K of the dispersion relation,
L = 0.56 m) beside the bound one that travels with the wave (2k, L/2 = 0.97 m); the two beat along the flume over
2π/(K − 2k) = 1.34 m. Theory puts the free wave at about 0.50 mm here (c(Kh) |X2|, X2 = 0.25 mm the stroke that
cancels it). Both paddles run with 41 water-level gauges from x = 1 to 5 m; at each gauge the complex amplitudes at ω
and 2ω are taken over 8 periods from one period after the ramp's end passes (at the group velocity), and the 2ω
amplitudes along x are fitted (least squares) by a bound part that follows the first harmonic's square (its phase and
its decay) and a free part B_f e^{-iKx}. Reported: the bound coefficient against Stokes' second harmonic of the
measured first harmonic at x = 1 m, and the free amplitude of each paddle.
Gates: the bound part within 5 % of Stokes' for both paddles (the second order of the SPH wave itself); the free part
smaller with second_order than without (the correction's purpose). The free amplitudes themselves are information:
SPH damps the 0.56 m free wave (28 dx at dx = 0.02) well below theory's 0.50 mm within a metre.
Usage: /usr/bin/python3 validation/regular_waves/second_order.py [--sphflume PATH] [--out DIR] [--threads N] [--reuse]
       [--set particles.dx=0.02]   (two runs of about 4 min each on 2 threads at dx = 0.02)
"""
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from common import Report, info, parse_sets, read_rows, run_case, run_metrics, save_figure, validation_args  # noqa: E402

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
CASE = os.path.normpath(os.path.join(HERE, "..", "..", "cases", "regular_waves.yaml"))
G, H0, T, HW, RAMP, END = 9.81, 0.4, 1.2, 0.04, 2.4, 18.0
XS = [1.0 + 0.1 * i for i in range(41)]
BOUND_TOL = 0.05


def wavenumber(w):
    k = w * w / G
    for _ in range(100):
        k -= (G * k * math.tanh(k * H0) - w * w) / (G * math.tanh(k * H0) + G * k * H0 / math.cosh(k * H0) ** 2)
    return k


def write_case(out):
    """The flume with the gauges along it (snapshots off)."""
    with open(CASE) as f:
        text = f.read()
    gauges = "".join(f"  - {{name: g{i:03d}, type: water_level, x: {x:.2f}}}\n" for i, x in enumerate(XS))
    anchor = "  - {name: eta_sponge, type: water_level, x: 6.0}\n"
    assert anchor in text, "cases/regular_waves.yaml changed: its eta_sponge gauge line is the anchor"
    text = text.replace(anchor, anchor + gauges).replace("snapshot_interval: 1.0", "snapshot_interval: 100.0")
    os.makedirs(out, exist_ok=True)
    path = os.path.join(out, "regular_waves_gauges.yaml")
    with open(path, "w") as f:
        f.write(text)
    return path


def harmonics(run, w, cg):
    c1, c2 = [], []
    for i, x in enumerate(XS):
        hdr, rows = read_rows(os.path.join(run, "gauges", f"g{i:03d}.csv"))
        t, e = rows[:, hdr.index("time")], rows[:, hdr.index("level")]
        t0 = RAMP + x / cg + T
        m = (t >= t0) & (t < t0 + 8 * T - 1e-9)
        tt, ee = t[m], e[m] - np.mean(e[m])
        c1.append(2 * np.mean(ee * np.exp(-1j * w * tt)))
        c2.append(2 * np.mean(ee * np.exp(-2j * w * tt)))
    return np.array(c1), np.array(c2)


def main():
    a = validation_args("regular_waves second order", __doc__, ["fine"])
    sets = parse_sets(a.set)
    dx = float(sets.pop("particles.dx", 0.02))
    case = write_case(a.out)
    w = 2 * math.pi / T
    k, K = wavenumber(w), wavenumber(2 * w)
    kh = k * H0
    cg = 0.5 * w / k * (1 + 2 * kh / math.sinh(2 * kh))
    rep = Report()
    res = {}
    for name, extra in (("first", {}), ("second", {"motions.0.second_order": "true"})):
        out = os.path.join(a.out, f"{name}_dx{dx:g}")
        s, wall, rc = run_case(a.sphflume, case, out, {"particles.dx": dx, "time.end": END, **extra, **sets}, a.threads, a.reuse)
        if s is None:
            rep.metric(f"{name}-order paddle: run", f"exit code {rc}", False, "0", "the run")
            continue
        run_metrics(rep, f"{name}-order paddle: ", s, END)
        c1, c2 = harmonics(out, w, cg)
        # 2ω amplitudes along x: bound part ∝ c1² (phase 2(ωt − kx), decaying as the wave does) + free part e^{−iKx}
        scale = abs(c1[0]) ** 2
        M = np.stack([c1 ** 2 / scale, np.exp(-1j * K * np.array(XS))], 1)
        sol = np.linalg.lstsq(M, c2, rcond=None)[0]
        resid = float(np.sqrt(np.mean(np.abs(c2 - M @ sol) ** 2)))
        stokes = k * scale / 4 * math.cosh(kh) * (2 + math.cosh(2 * kh)) / math.sinh(kh) ** 3
        bound, free = abs(sol[0]), abs(sol[1])
        res[name] = (np.abs(c2), np.abs(c1), free)
        rep.metric(f"{name}-order paddle: bound second harmonic / Stokes' of the measured first harmonic at x = 1 m - 1",
                   f"{100 * (bound / stokes - 1):+.2f} % ({1000 * bound:.3f} vs {1000 * stokes:.3f} mm)",
                   abs(bound / stokes - 1) <= BOUND_TOL, f"within {100 * BOUND_TOL:g} %", "Stokes (Dean & Dalrymple 1991 eq. 11.48)")
        info(f"{name}-order paddle: free second harmonic |B_f| (fit residual rms)", f"{1000 * free:.3f} mm ({1000 * resid:.3f} mm)",
             True, "-", "theory at the paddle without correction: 0.50 mm")
        print(f"  wall {wall:.1f} s")
    if len(res) == 2:
        f1, f2 = res["first"][2], res["second"][2]
        rep.metric("free second harmonic: second-order / first-order paddle", f"{f2 / f1:.2f} ({1000 * f2:.3f} / {1000 * f1:.3f} mm)",
                   f2 < f1, "< 1", "Schäffer (1996): the correction cancels the free wave")
        fig, ax = plt.subplots(figsize=(9, 4.2))
        for name, lab in (("first", "first-order paddle"), ("second", "second_order: true (Schäffer 1996)")):
            ax.plot(XS, 1000 * res[name][0], "o-", ms=4, label=lab)
        a1 = res["second"][1]
        ax.plot(XS, 1000 * k * a1 ** 2 / 4 * math.cosh(kh) * (2 + math.cosh(2 * kh)) / math.sinh(kh) ** 3, "k--",
                label="bound (Stokes) of the measured first harmonic")
        ax.set_xlabel("x [m]")
        ax.set_ylabel("second-harmonic amplitude [mm]")
        ax.set_title(f"H = 0.04 m, T = 1.2 s, h = 0.4 m, dx = {dx:g}: the second harmonic along the flume")
        ax.grid(alpha=0.3)
        ax.legend()
        fig.tight_layout()
        save_figure(fig, HERE, "second_order", "fine", a.out)
    rep.finish("regular_waves second order", "(fine)")


if __name__ == "__main__":
    main()
