#!/usr/bin/python3
"""A dam-break bore against a tall square column: Yeh & Petroff's experiment (issue 60, "3D against experiments").

cases/bore_yeh_petroff.yaml: a water column 0.4 x 0.61 x 0.3 m released over a wet bed (1 cm) in a tank 1.6 m long;
a column 0.12 x 0.12 m centred 0.96 m downstream. Gauges: u at the experiment's probe (0.814 m, 0.026 m above the
bed, centreline) and the pressure force on the column's upstream and downstream faces, whose difference is the
streamwise force the experiment measured. Reference: the measured u and F, digitised (data/README.md). The two
measured records do not share a time origin, so each is read from its own onset, the run's by the same rule:
  velocity onset: the time of the largest u (the bore's front at the probe; the measured record starts there);
  force onset: the first F above 5 N (over the measured record's noise, within +-4.4 N before the impact).
Metrics:
  a. the run reaches t_end, fluid mass exact;
  b. the force's peak within 0.5 s of its onset (also of the run's force averaged over the measured record's median
     sample spacing, as a sensor of that bandwidth would read it) and its impulse over the onset's first 1.0 s;
  c. the velocity's peak and its mean over the 0.5 s after it;
  d. (information) convergence over the spacings.
Thresholds: not set yet (README); the check gates the run's health and prints the metrics beside the measured ones.
Modes: fine dx = H/25 (PySPH's) and H/40 (0.0075 m); coarse H/25.
Usage: /usr/bin/python3 validation/bore_yeh_petroff/check.py [--mode coarse|fine] [--dx DX] [--sphflume PATH] [--out DIR]
       [--reuse]
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
CASE = os.path.normpath(os.path.join(HERE, "..", "..", "cases", "bore_yeh_petroff.yaml"))
NAME = "bore_yeh_petroff"
END = 1.4
MODES = {"coarse": {"dxs": [0.012]}, "fine": {"dxs": [0.012, 0.0075]}}


def force_metrics(t, f):
    hit = np.nonzero(f > 5.0)[0]
    if not len(hit):
        return dict(onset=float("nan"), peak=float("nan"), impulse=float("nan"))
    t0 = float(t[hit[0]])
    w = (t >= t0) & (t <= t0 + 1.0)
    return dict(onset=t0, peak=float(f[(t >= t0) & (t <= t0 + 0.5)].max()), impulse=float(np.trapz(f[w], t[w])),
                span=float(t[w][-1] - t0))


def velocity_metrics(t, u):
    k = int(np.argmax(u))
    t0 = float(t[k])
    w = (t >= t0) & (t <= t0 + 0.5)
    return dict(onset=t0, first=float(u[k]),
                mean=float(np.trapz(u[w], t[w]) / (t[w][-1] - t[w][0])) if w.sum() > 1 else float("nan"))


def measured(name):
    h, rows = read_rows(os.path.join(HERE, "data", f"yeh_petroff_{name}.csv"))
    order = np.argsort(rows[:, 0], kind="stable")
    return rows[order, 0], rows[order, 1]


def main():
    a = validation_args(NAME, __doc__, MODES, add_spacing_option)
    dxs = select_spacings(MODES[a.mode]["dxs"], a.only_spacings)
    rep = Report()
    vt, v = measured("velocity")
    ft, f = measured("force")
    ev, ef = velocity_metrics(vt, v), force_metrics(ft, f)
    spacing = float(np.median(np.diff(ft)))  # the measured force record's sample spacing
    print(f"Yeh & Petroff: force onset {ef['onset']:.3f} s, peak {ef['peak']:.1f} N, impulse over 1 s {ef['impulse']:.2f} N s; "
          f"velocity peak {ev['first']:.2f} m/s, mean over the 0.5 s after it {ev['mean']:.2f} m/s")
    fig, ax = plt.subplots(2, 1, figsize=(10, 7))
    ax[0].plot(vt - ev["onset"], v, "k^", ms=3, label="Yeh & Petroff")
    ax[1].plot(ft - ef["onset"], f, "k.", ms=3, label="Yeh & Petroff")
    for dx in dxs:
        out = os.path.join(a.out, f"dx{dx:g}")
        sets = {"particles.dx": dx, "time.end": END, **parse_sets(a.set)}
        s, wall, rc = run_case(a.sphflume, CASE, out, sets, a.threads, a.reuse)
        label = f"dx {dx:g}"
        if s is None:
            rep.metric(f"{label}: run exit code", rc, False, "0", "the run")
            continue
        run_metrics(rep, f"{label}: ", s, END)
        hu, ru = read_rows(os.path.join(out, "gauges", "u_probe.csv"))
        tu, u = ru[:, 0], np.nan_to_num(ru[:, hu.index("ux")])
        mv = velocity_metrics(tu, u)
        h1, r1 = read_rows(os.path.join(out, "gauges", "F_front.csv"))
        h2, r2 = read_rows(os.path.join(out, "gauges", "F_back.csv"))
        tf = r1[:, 0]
        fx = np.nan_to_num(r1[:, h1.index("force")]) - np.nan_to_num(r2[:, h2.index("force")])
        mf = force_metrics(tf, fx)
        k = max(1, int(round(spacing / float(np.median(np.diff(tf))))))
        smooth = np.convolve(fx, np.ones(k) / k, mode="same")  # (a running mean over the measured spacing)
        ms = force_metrics(tf, smooth)
        info(f"{label}: force peak", f"{mf['peak']:.1f} N ({100 * (mf['peak'] / ef['peak'] - 1):+.0f} %); averaged over "
             f"{1000 * spacing:.1f} ms: {ms['peak']:.1f} N ({100 * (ms['peak'] / ef['peak'] - 1):+.0f} %)", True, "-", "Yeh & Petroff")
        info(f"{label}: force impulse over 1 s from the onset", f"{mf['impulse']:.2f} N s ({100 * (mf['impulse'] / ef['impulse'] - 1):+.0f} %;"
             f" over {mf.get('span', float('nan')):.2f} s)", True, "-", "Yeh & Petroff")
        info(f"{label}: velocity at the probe: peak, mean over the 0.5 s after it", f"{mv['first']:.2f}, {mv['mean']:.2f} m/s "
             f"({100 * (mv['mean'] / ev['mean'] - 1):+.0f} %); peak at {mv['onset']:.3f} s, force onset {mf['onset']:.3f} s",
             True, "-", "Yeh & Petroff")
        print(f"  wall {wall:.1f} s, {s['steps']} steps, {s['particles']['total']} particles")
        ax[0].plot(tu - mv["onset"], u, "-", lw=1, label=f"SPHFlume {label}")
        ax[1].plot(tf - mf["onset"], fx, "-", lw=1, label=f"SPHFlume {label}")
    ax[0].set_xlabel("t - the time of the velocity's peak at the probe [s]")
    ax[0].set_ylabel("u at the probe [m/s]")
    ax[1].set_xlabel("t - the force's onset [s]")
    ax[1].set_ylabel("streamwise force on the column [N]")
    for x in ax:
        x.set_xlim(-0.2, 1.3)
        x.legend(fontsize=8)
    fig.tight_layout()
    save_figure(fig, HERE, NAME, a.mode, a.out)
    rep.finish(NAME, a.mode)
    return 0


if __name__ == "__main__":
    sys.exit(main())
