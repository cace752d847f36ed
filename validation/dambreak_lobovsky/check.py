#!/usr/bin/python3
"""3D dam break: wall pressures against Lobovsky et al. (2014) (issue 60, "3D against experiments").

cases/dambreak_lobovsky.yaml: a column 600 x 150 x 300 mm (H = 0.3 m) in a tank 1610 mm long, SPHinXsys's 3D dam
break at the experiment's scale. Three `pressure` gauges with the sensors' 8.37 mm faces on the downstream wall's
centreline, 3, 30 and 80 mm above the bed, each the mean of its last 0.02 sqrt(H/g). Reference: the measured
pressures at those sensors, digitised (data/README.md). Times in sqrt(H/g), pressures in rho g H.

Metrics for each sensor, the same rule applied to the run and to the measurement:
  a. the run reaches t_end, fluid mass exact;
  b. the impact: the first reading above 0.1 rho g H (the measurement reads below 0.03 before it);
  c. the peak over the impact's first sqrt(H/g) (information: a single impact's peak scatters widely between
     repetitions, Lobovsky et al. 2014);
  d. the mean over t in [3.5, 5.5] (after the impact's transient, before the wave that comes back from the upstream
     wall), with the scatter of the measured points there;
  e. (information) convergence over the spacings.
Thresholds: none yet beyond (a): the metrics are printed (the paper's repetition statistics, the bands to use, are not in
the project; README).
Modes: fine dx = H/20 and H/40 (about 1 and 8 min on 2 threads); coarse H/20.
Usage: /usr/bin/python3 validation/dambreak_lobovsky/check.py [--mode coarse|fine] [--dx DX] [--sphflume PATH] [--out DIR]
       [--reuse]
"""
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from common import Report, add_spacing_option, info, parse_sets, read_rows, run_case, run_metrics, save_figure, select_spacings, validation_args  # noqa: E402

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
CASE = os.path.normpath(os.path.join(HERE, "..", "..", "cases", "dambreak_lobovsky.yaml"))
NAME = "dambreak_lobovsky"
H, G, RHO = 0.3, 9.81, 1000.0
TS = math.sqrt(H / G)  # the time scale sqrt(H/g)
END = 7.0
WINDOW = (3.5, 5.5)
SENSORS = {"p1_3mm": "3 mm", "p3_30mm": "30 mm", "p4_80mm": "80 mm"}
MODES = {"coarse": {"dxs": [H / 20]}, "fine": {"dxs": [H / 20, H / 40]}}


def metrics(t, p):
    """impact (first p > 0.1), peak over the following 1.0, mean and sd of the points over WINDOW."""
    hit = np.nonzero(p > 0.1)[0]
    t0 = float(t[hit[0]]) if len(hit) else float("nan")
    after = (t >= t0) & (t <= t0 + 1.0)
    w = (t >= WINDOW[0]) & (t <= WINDOW[1])
    return dict(impact=t0, peak=float(p[after].max()) if after.any() else float("nan"),
                mean=float(np.trapz(p[w], t[w]) / (t[w][-1] - t[w][0])) if w.sum() > 1 else float("nan"),
                sd=float(np.std(p[w], ddof=1)) if w.sum() > 1 else float("nan"))


def measured(name):
    h, rows = read_rows(os.path.join(HERE, "data", f"lobovsky_2014_{name}.csv"))
    order = np.argsort(rows[:, 0], kind="stable")
    return rows[order, 0], rows[order, 1]


def main():
    a = validation_args(NAME, __doc__, MODES, add_spacing_option)
    dxs = select_spacings(MODES[a.mode]["dxs"], a.only_spacings)
    rep = Report()
    exp = {s: metrics(*measured(s)) for s in SENSORS}
    for s, lab in SENSORS.items():
        e = exp[s]
        print(f"Lobovsky et al. (2014), {lab}: impact {e['impact']:.3f}, peak {e['peak']:.3f}, "
              f"mean over {WINDOW} {e['mean']:.3f} (sd {e['sd']:.3f})")
    fig, axs = plt.subplots(len(SENSORS), 1, figsize=(10, 9), sharex=True)
    for ax, s in zip(axs, SENSORS):
        ax.plot(*measured(s), "k.-", ms=3, lw=0.8, label="Lobovsky et al. (2014)")
    for dx in dxs:
        out = os.path.join(a.out, f"dx{dx:.4g}")
        sets = {"particles.dx": f"{dx:.6g}", "time.end": f"{END * TS:.6g}", **parse_sets(a.set)}
        s, wall, rc = run_case(a.sphflume, CASE, out, sets, a.threads, a.reuse)
        label = f"dx H/{H / dx:.0f}"
        if s is None:
            rep.metric(f"{label}: run exit code", rc, False, "0", "the run")
            continue
        run_metrics(rep, f"{label}: ", s, END * TS)
        for ax, (g, lab) in zip(axs, SENSORS.items()):
            hdr, r = read_rows(os.path.join(out, "gauges", f"{g}.csv"))
            t, p = r[:, 0] / TS, np.nan_to_num(r[:, hdr.index("pressure")]) / (RHO * G * H)
            m, e = metrics(t, p), exp[g]
            info(f"{label}, {lab}: impact", f"{m['impact']:.3f} ({m['impact'] - e['impact']:+.3f})", True, "-", "Lobovsky et al. 2014")
            info(f"{label}, {lab}: peak in the impact's first sqrt(H/g)", f"{m['peak']:.3f} (measured {e['peak']:.3f})", True, "-",
                 "Lobovsky et al. 2014")
            info(f"{label}, {lab}: mean over t in [3.5, 5.5]", f"{m['mean']:.3f} ({100 * (m['mean'] / e['mean'] - 1):+.1f} %; "
                 f"sd {m['sd']:.3f})", abs(m["mean"] - e["mean"]) <= e["sd"], f"measured {e['mean']:.3f} +- {e['sd']:.3f}",
                 "Lobovsky et al. 2014")
            ax.plot(t, p, "-", lw=1, label=f"SPHFlume {label}")
        print(f"  wall {wall:.1f} s, {s['steps']} steps, {s['particles']['total']} particles")
    for ax, lab in zip(axs, SENSORS.values()):
        ax.set_ylabel(f"p/(rho g H), {lab}")
        ax.axvspan(*WINDOW, color="0.92", zorder=0)
        ax.legend(fontsize=8)
    axs[-1].set_xlim(0, END)
    axs[-1].set_xlabel("t sqrt(g/H)")
    fig.tight_layout()
    save_figure(fig, HERE, NAME, a.mode, a.out)
    rep.finish(NAME, a.mode)
    return 0


if __name__ == "__main__":
    sys.exit(main())
