#!/usr/bin/python3
"""Solitary-wave run-up on a 1:2.08 solid slope: Tsurudome's Flume A (issue 22, validation 4; cases/runup_flume_a.yaml).

A Rayleigh solitary wave (h0 = 0.21 m) runs 2.07 m over a flat bed and up a smooth impermeable 1:2.08 slope. The
run-up R is the `runup` gauge's maximum: the highest fluid particle within 1.5 dx of the slope's surface line with at
least 4 fluid neighbours within 2 dx, above the still-water level (after Tsurudome §5.5.1: "the highest point").
Reference: Li & Raichlen (2001), non-breaking (Tsurudome §5.2, eq 5.2.3):
    R/h0 = 2.831 sqrt(cot phi) (H/h0)^(5/4) + 0.293 (cot phi)^(3/2) (H/h0)^(9/4),   cot phi = 2.08,
the law that fits the experiments best (Tsurudome §5.3; his ISPH overshoots it by 7 % at H/h0 = 0.163 and 11.5 %
at 0.25). Also printed: Synolakis's R/h0 = 2.831 sqrt(cot phi) (H/h0)^(5/4) and the thesis's ISPH values.
Metrics:
  1. R/h0 within 5 % of Li & Raichlen at each H/h0 run (issue 22; fine: dx = 0.005, the thesis's d0);
     coarse (dx = 0.01): within 12 % (a looser tolerance at twice the thesis's d0);
  2. the run reaches time.end, fluid mass conserved exactly.
Drawn: the surface profiles at H/h0 = 0.163 at t* = t sqrt(g/h0) = 8.2, 10.2, 12.2, 14.2 (the thesis's frames against
Li & Raichlen's data, which are not in the project), t* = 10.2 put at the maximum run-up (the thesis's origin is not
stated), from the snapshots nearest those times.
Options: --ratios (comma-separated H/h0 among 0.10, 0.163, 0.25, 0.30; default 0.163 in coarse mode, all four in fine).
Usage: /usr/bin/python3 validation/runup_flume_a/check.py [--mode coarse|fine] [--ratios 0.163,0.25] [--out DIR]
"""
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from common import Report, fluid_snapshots, info, parse_sets, read_rows, run_case, run_metrics, save_figure, validation_args  # noqa: E402

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
CASE = os.path.normpath(os.path.join(HERE, "..", "..", "cases", "runup_flume_a.yaml"))
NAME = "runup_flume_a"
G, H0, COT = 9.81, 0.21, 2.08
MODES = {"coarse": {"dx": 0.01, "tol": 0.12, "ratios": "0.163"},
         "fine": {"dx": 0.005, "tol": 0.05, "ratios": "0.10,0.163,0.25,0.30"}}
THESIS = {0.163: 0.469, 0.25: 0.848}
TOE, SHORE = 2.07, 2.07 + 2.08 * 0.21
PROFILE_TSTAR = (8.2, 10.2, 12.2, 14.2)   # Tsurudome Fig. 5.x against Li & Raichlen's profiles, H/h0 = 0.163


def surface_profiles(out, t_toe, dx):
    """[(t*, x/h0, y/h0)] of the free surface (highest fluid particle per dx column) in the snapshots nearest
    t* = PROFILE_TSTAR, t* = (t - t_toe) sqrt(g/h0) (t_toe: the time origin), x/h0 from the still-water shoreline,
    y/h0 from the SWL."""
    snaps = fluid_snapshots(out, [])
    if not snaps:
        return []
    times = np.array([v[0] for v in snaps])
    res = []
    for ts in PROFILE_TSTAR:
        k = int(np.argmin(np.abs(times - (t_toe + ts * math.sqrt(H0 / G)))))
        d = snaps[k][1]
        cols = np.floor(d["x"] / dx).astype(int)
        xs, zs = [], []
        for c in np.unique(cols):
            m = cols == c
            xs.append((c + 0.5) * dx)
            zs.append(d["z"][m].max())
        res.append(((times[k] - t_toe) / math.sqrt(H0 / G), (np.array(xs) - SHORE) / H0, np.array(zs) / H0 - 1.0))
    return res


def li_raichlen(r):
    return 2.831 * math.sqrt(COT) * r ** 1.25 + 0.293 * COT ** 1.5 * r ** 2.25


def synolakis(r):
    return 2.831 * math.sqrt(COT) * r ** 1.25


def args():
    return validation_args(NAME, __doc__, MODES, extra=lambda ap: ap.add_argument("--ratios", default=None, help="comma-separated H/h0 values"))


def main():
    a = args()
    m = MODES[a.mode]
    ratios = [float(v) for v in (a.ratios or m["ratios"]).split(",")]
    rep = Report()
    results = []
    for r in ratios:
        H = r * H0
        c = math.sqrt(G * (H0 + H))
        beta = math.sqrt(3 * r / (1 + r)) / H0
        # the crest passes the paddle at t_s, reaches the toe (2.07 m) 2.07/c later; the run-up and the first
        # rundown are over within 1.5 s after that
        t_s = (7.6 / beta + 2 * r / beta) / c
        end = round(t_s + 2.07 / c + 1.5, 1)
        out = os.path.join(a.out, f"ratio{r:g}", f"dx{m['dx']:g}")
        sets = {"particles.dx": m["dx"], "time.end": end, "motions.0.height": H, **parse_sets(a.set)}
        s, wall, rc = run_case(a.sphflume, CASE, out, sets, a.threads, a.reuse)
        print(f"\n== {NAME} H/h0 = {r:g} ({a.mode}: dx = {m['dx']} m, end {end} s; run wall time {wall:.1f} s)")
        if s is None:
            print(f"[FAIL] run exit code = {rc}   (threshold: 0)")
            return 2
        run_metrics(rep, f"H/h0 = {r:g}: ", s, end)
        hdr, rows = read_rows(os.path.join(out, "gauges", "runup.csv"))
        t, ru = rows[:, hdr.index("time")], rows[:, hdr.index("runup")]
        R = float(np.nanmax(ru))
        ref = li_raichlen(r)
        err = R / H0 / ref - 1
        rep.metric(f"H/h0 = {r:g}: R/h0 vs Li & Raichlen (2001)", f"{R / H0:.4f} vs {ref:.4f} ({100 * err:+.1f} %)",
                   abs(err) <= m["tol"], f"within {100 * m['tol']:g} %",
                   "issue 22, validation 4 (fine: 5 %; coarse dx = 0.01: 12 %)")
        info(f"H/h0 = {r:g}: against Synolakis (1986)", f"{100 * (R / H0 / synolakis(r) - 1):+.1f} %", True, "-",
             "the non-breaking law, lower than Li & Raichlen")
        if r in THESIS:
            info(f"H/h0 = {r:g}: against Tsurudome's ISPH R/h0 = {THESIS[r]}", f"{100 * (R / H0 / THESIS[r] - 1):+.1f} %",
                 True, "-", "thesis §5.3")
        print(f"  wall {wall:.1f} s, {s['steps']} steps, {s['particles']['total']} particles, "
              f"{s['particle_steps_per_second']:.3g} particle-steps/s")
        # the profiles' time origin: the thesis does not state its t* origin (the data to align it on are not
        # in the project); its frames show run-up at t* = 8.2 and 10.2 and rundown at 12.2 and
        # 14.2, so t* = 10.2 is put at this run's maximum run-up
        t0 = float(t[int(np.nanargmax(ru))]) - 10.2 * math.sqrt(H0 / G)
        results.append((r, R / H0, t, ru, surface_profiles(out, t0, m["dx"]) if abs(r - 0.163) < 1e-9 else []))

    fig, ax = plt.subplots(1, 3, figsize=(16, 4))
    rr = np.linspace(0.05, 0.32, 100)
    ax[0].plot(rr, [li_raichlen(v) for v in rr], "k-", label="Li & Raichlen (2001)")
    ax[0].plot(rr, [synolakis(v) for v in rr], "k:", label="Synolakis (1986)")
    ax[0].plot(list(THESIS), list(THESIS.values()), "s", mfc="none", label="Tsurudome ISPH")
    ax[0].plot([v[0] for v in results], [v[1] for v in results], "o", label=f"SPHFlume, dx = {m['dx']} m")
    ax[0].set_xlabel("H/h0")
    ax[0].set_ylabel("R/h0")
    ax[0].set_title("run-up on the 1:2.08 slope")
    ax[0].legend()
    for r, _, t, ru, _ in results:
        ax[1].plot(t, ru / H0, label=f"H/h0 = {r:g}")
    ax[1].set_xlabel("t [s]")
    ax[1].set_ylabel("waterline above SWL / h0")
    ax[1].legend()
    xs = np.linspace(-4, 2.5, 10)
    ax[2].plot(xs, np.maximum(xs / 2.08, -1.0), "k-", lw=1)
    for _, _, _, _, prof in results:
        for ts, x, y in prof:
            ax[2].plot(x, y, lw=0.9, label=f"t* = {ts:.1f}")
    ax[2].set_xlim(-4, 2.5)
    ax[2].set_ylim(-0.3, 1.0)
    ax[2].set_xlabel("x/h0 (0: still-water shoreline)")
    ax[2].set_ylabel("y/h0 (0: SWL)")
    ax[2].set_title("H/h0 = 0.163: surface profiles (t* = 10.2 at the maximum run-up)", fontsize=9)
    if any(v[4] for v in results):
        ax[2].legend(fontsize=7)
    fig.tight_layout()
    save_figure(fig, HERE, NAME, a.mode, a.out)
    rep.finish(NAME, a.mode)
    return 0


if __name__ == "__main__":
    sys.exit(main())
