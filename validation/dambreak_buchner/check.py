#!/usr/bin/python3
"""2D dam break: the pressure on the downstream wall against Buchner's (2002) measurement (issue 60).

cases/dambreak_sphinxsys.yaml: a water column H high and 2H long in a tank 5.366 H long (H = 1, g = 1: times are
t sqrt(g/H), pressures p/(rho g H)), the dual integrator, dummy walls. Its `p_sensor` gauge reads the wall pressure at
(5.366 H, 0.2 H) as a lab sensor does: the mean over a face 0.03 H across, averaged over the last 0.02 sqrt(H/g).
Reference: Buchner (2002), the pressure at that point, digitised (data/README.md).

Metrics, the same rules applied to the run and to the measurement:
  a. the run reaches t_end, fluid mass exact;
  b. the impact: the last time the pressure is at or below 0.2 rho g H before it first reaches the measured
     post-impact mean (c). Threshold: within the measurement's own rise time, from its impact to that first reading
     (both read from the data);
  c. the post-impact mean over t sqrt(g/H) in [2.8, 7] (bench/vs_sphinxsys.py's window; the measurement's mean is the
     time mean of its points): within the measurement's scatter there, the standard deviation of its points.
  d. (information) the point gauge `p_wall`, the change with dp (convergence), the pressure's scatter.
Modes: fine dp = 0.025, 0.0125, 0.00625 (the finest gated; about 2 min on 2 threads in all); coarse dp = 0.025.
Not in CTest while (b) fails (validation/dambreak_buchner/README.md).
Usage: /usr/bin/python3 validation/dambreak_buchner/check.py [--mode coarse|fine] [--dp DP] [--set KEY=VALUE] [--sphflume PATH]
       [--out DIR] [--reuse]
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from common import Report, add_spacing_option, info, parse_sets, read_rows, run_case, run_metrics, save_figure, select_spacings, validation_args  # noqa: E402

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
CASE = os.path.normpath(os.path.join(HERE, "..", "..", "cases", "dambreak_sphinxsys.yaml"))
NAME = "dambreak_buchner"
END = 7.0
WINDOW = (2.8, 7.0)
MODES = {"coarse": {"dps": [0.025]}, "fine": {"dps": [0.025, 0.0125, 0.00625]}}


def impact(t, p, top, level=0.2):
    """The impact and the rise: the last time p is at or below `level` before it first reaches `top` (the
    post-impact mean), and the time from there to that first reading (NaN if p never reaches `top`). The
    measurement's points are sparse and noisy before the impact (up to 0.16 rho g H), and its digitised rise is
    nearly vertical with points out of order: this rule reads them and a run's gauge alike."""
    up = np.nonzero(p >= top)[0]
    if not len(up):
        return float("nan"), float("nan")
    below = np.nonzero(p[:up[0]] <= level)[0]
    t0 = float(t[below[-1]]) if len(below) else float(t[0])
    return t0, float(t[up[0]]) - t0


def time_mean(t, p, lo, hi):
    """The time mean of p over [lo, hi] (trapezoids over the points inside) and the points' standard deviation."""
    w = (t >= lo) & (t <= hi)
    tw, pw = t[w], p[w]
    return float(np.trapz(pw, tw) / (tw[-1] - tw[0])), float(np.std(pw, ddof=1))


def measurement():
    h, rows = read_rows(os.path.join(HERE, "data", "buchner_2002_p0.csv"))
    order = np.argsort(rows[:, 0], kind="stable")
    t, p = rows[order, 0], rows[order, 1]
    mean, sd = time_mean(t, p, *WINDOW)
    t_hit, rise = impact(t, p, mean)
    return dict(t=t, p=p, impact=t_hit, mean=mean, sd=sd, rise=rise)


def main():
    a = validation_args(NAME, __doc__, MODES, lambda ap: add_spacing_option(ap, "--dp"))
    dps = select_spacings(MODES[a.mode]["dps"], a.only_spacings, "--dp")
    rep = Report()
    exp = measurement()
    print(f"Buchner (2002): impact {exp['impact']:.3f}, rise to the post-impact mean {exp['rise']:.3f}, "
          f"post-impact mean {exp['mean']:.3f} (sd of the points {exp['sd']:.3f})")
    fig, ax = plt.subplots(1, 1, figsize=(10, 4.5))
    ax.plot(exp["t"], exp["p"], "ko", ms=3, label="Buchner (2002)")
    res = {}
    for dp in dps:
        out = os.path.join(a.out, f"dp{dp:g}")
        sets = {"particles.dx": dp, "time.end": END, "time.output_interval": 0.01, "time.snapshot_interval": END,
                **parse_sets(a.set)}
        s, wall, rc = run_case(a.sphflume, CASE, out, sets, a.threads, a.reuse)
        label = f"dp {dp:g}"
        if s is None:
            rep.metric(f"{label}: run exit code", rc, False, "0", "the run")
            continue
        run_metrics(rep, f"{label}: ", s, END)
        h, r = read_rows(os.path.join(out, "gauges", "p_sensor.csv"))
        t, p = r[:, 0], np.nan_to_num(r[:, h.index("pressure")])
        hp, rp = read_rows(os.path.join(out, "gauges", "p_wall.csv"))
        pt = np.nan_to_num(rp[:, hp.index("pressure")])
        res[dp] = dict(impact=impact(t, p, exp["mean"])[0], mean=time_mean(t, p, *WINDOW),
                       point=(impact(rp[:, 0], pt, exp["mean"])[0], time_mean(rp[:, 0], pt, *WINDOW)))
        gate = dp == min(dps)
        d_hit = res[dp]["impact"] - exp["impact"]
        (rep.metric if gate else info)(f"{label}: impact at the sensor", f"{res[dp]['impact']:.3f} ({d_hit:+.3f})",
                                       abs(d_hit) <= exp["rise"], f"Buchner {exp['impact']:.3f} +- {exp['rise']:.3f} (its rise time)",
                                       "issue 60; Buchner 2002")
        m = res[dp]["mean"][0]
        (rep.metric if gate else info)(f"{label}: post-impact mean, t in [2.8, 7]",
                                       f"{m:.3f} ({100 * (m / exp['mean'] - 1):+.1f} %; sd {res[dp]['mean'][1]:.3f})",
                                       abs(m - exp["mean"]) <= exp["sd"], f"Buchner {exp['mean']:.3f} +- {exp['sd']:.3f} (its scatter)",
                                       "issue 60; Buchner 2002")
        pi, (pm, psd) = res[dp]["point"]
        info(f"{label}: the point gauge p_wall: impact, post-impact mean", f"{pi:.3f}, {pm:.3f} (sd {psd:.3f})", True, "-", "the gauge")
        print(f"  wall {wall:.1f} s, {s['steps']} steps, {s['particles']['total']} particles")
        ax.plot(t, p, "-", lw=1, label=f"SPHFlume, sensor, dp {dp:g}")
    ax.axvspan(*WINDOW, color="0.92", zorder=0)
    ax.set_xlim(0, END)
    ax.set_xlabel("t sqrt(g/H)")
    ax.set_ylabel("p / (rho g H) at (5.366 H, 0.2 H)")
    ax.legend(fontsize=8)
    fig.tight_layout()
    save_figure(fig, HERE, NAME, a.mode, a.out)
    if len(res) > 1:
        ks = sorted(res, reverse=True)
        print("convergence: impact " + " -> ".join(f"{res[k]['impact']:.3f}" for k in ks) +
              "; post-impact mean " + " -> ".join(f"{res[k]['mean'][0]:.3f}" for k in ks))
    rep.finish(NAME, a.mode)
    return 0


if __name__ == "__main__":
    sys.exit(main())
