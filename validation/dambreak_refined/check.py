#!/usr/bin/python3
"""Dam break with a fine zone at the impact wall (issue 42, check 2; cases/dambreak_2d.yaml with a `resolution`
region set on the command line).

Martin & Moyce's 2D dam break (a = 0.146 m) run three ways with the symplectic integrator: uniform coarse (dx),
uniform fine (dx/2), and coarse with a level-1 box over the downstream part of the tank (x >= 0.38 m, up to 0.8 m,
so the run-up jet stays in it), where the surge is split as it enters and the wall's particles are split at set-up.
Metrics (issue 58, check 2: the refined run against the uniform fine run):
  1. every run reaches t_end, fluid mass conserved to 1e-12;
  2. the front x(t) where it runs inside the fine zone (the fine run's front at 0.38 <= x < 0.55 m):
     max |x_refined / x_fine - 1| <= 2 % (over its whole path below 0.55 m: information);
  3. the horizontal pressure force on the downstream wall below 0.3 m (gauge F_wall_right: the wall particles'
     pressure integrated over their faces) averaged over t = 0.3 ... 0.6 s (after the impact at about 0.27 s; rows
     every 1 ms): within 2 % of the fine run's, or within two standard errors of the difference where that is larger
     (both reported; the se of the paired series F(t) - F_fine(t) over the window, with its effective sample count
     from the lag-1 autocorrelation, common.band);
Information: the wall pressure sensor (0.584, 0.0146) over the same window (issue 42's metric: its mean has a standard
error of about 20 % of itself), splits, merges, particle counts, wall times and the refined run's cost.
Information: splits, merges, particle counts, wall times and the refined run's cost against the fine one.
Modes: fine = dx 0.0073 (a/20) refined to a/40 against a/40; coarse = dx 0.0146 against a/20.
Usage: /usr/bin/python3 validation/dambreak_refined/check.py [--mode fine|coarse] [--out DIR] [--reuse]
"""
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from common import Report, band, fmt_band, info, parse_sets, read_rows, run_case, save_figure, validation_args  # noqa: E402

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
CASE = os.path.normpath(os.path.join(HERE, "..", "..", "cases", "dambreak_2d.yaml"))
NAME = "dambreak_refined"
REGION = "{regions: [{shape: box, min: [0.38, 0.0], max: [0.6, 0.8], level: 1}]}"
MODES = {"fine": {"dx": 0.0073}, "coarse": {"dx": 0.0146}}
END, TOL, FRONT_MAX, WINDOW = 0.6, 0.02, 0.55, (0.3, 0.6)
ZONE = 0.38  # the fine zone's upstream face (REGION)
GAUGE_DT = 0.001  # gauge rows every 1 ms (snapshots every 20 ms): the sensor's mean to a few per cent
RGH = 1000.0 * 9.81 * 0.292  # rho g H, H = 2a


def main():
    a = validation_args(NAME, __doc__, MODES)
    dx = MODES[a.mode]["dx"]
    extra = parse_sets(a.set)
    # (--set resolution.multirate=true: the refined run sub-cycles its fine level; the uniform runs have no levels)
    multirate = str(extra.pop("resolution.multirate", "false")).lower() == "true"
    region = REGION[:-1] + ", multirate: true}" if multirate else REGION
    runs = {"coarse": ({"particles.dx": dx}, f"uniform dx = {dx:g}"),
            "fine": ({"particles.dx": dx / 2}, f"uniform dx = {dx / 2:g}"),
            "refined": ({"particles.dx": dx, "resolution": region},
                        f"dx = {dx:g}, level 1 at x >= 0.38 m" + (", multirate" if multirate else ""))}
    rep = Report()
    res = {}
    for tag, (sets, label) in runs.items():
        out = os.path.join(a.out, tag, f"dx{dx:g}")
        s, wall, rc = run_case(a.sphflume, CASE, out, {**sets, "scheme.integrator": "symplectic", "time.end": END,
                                                       "time.output_interval": GAUGE_DT, "time.snapshot_interval": 0.02,
                                                       **extra}, a.threads, a.reuse)
        if s is None:
            print(f"[FAIL] {tag} ({label}): run exit code = {rc}   (threshold: 0)")
            return 2
        rep.metric(f"{tag} ({label}): reached t_end, fluid mass error", f"{s['simulated_time']:.3f} s, {s['mass']['relative_error']:.1e}",
                   s["simulated_time"] >= END * (1 - 1e-6) and abs(s["mass"]["relative_error"]) <= 1e-12,
                   "t_end, |.| <= 1e-12", "issue 42 (conservation)")
        hf, front = read_rows(os.path.join(out, "gauges", "front.csv"))
        hp, pw = read_rows(os.path.join(out, "gauges", "p_wall_right.csv"))
        hF, Fw = read_rows(os.path.join(out, "gauges", "F_wall_right.csv"))
        res[tag] = (front[:, 0], front[:, 1], pw[:, 0], np.nan_to_num(pw[:, 1]), s, wall, label, Fw[:, 0], Fw[:, 1])
        r = s.get("resolution", {})
        print(f"  {tag}: wall {wall:.1f} s, {s['steps']} steps, {s['particles']['fluid']} fluid particles"
              + (f", splits {r.get('splits')}, merges {r.get('merges')}, fluid per level {r.get('fluid_per_level')}" if r else ""))
    tf, xf, tpf, pf, *_, tFf, Ff = res["fine"]
    win_f = (tpf >= WINDOW[0]) & (tpf <= WINDOW[1])
    ref = band(pf[win_f])
    refF = band(Ff[(tFf >= WINDOW[0]) & (tFf <= WINDOW[1])])
    for tag in ("refined", "coarse"):
        t, x, tp, p, s, wall, label, tF, F = res[tag]
        n = min(len(t), len(tf))
        m = (xf[:n] < FRONT_MAX) & (tf[:n] > 0.0)
        err = float(np.max(np.abs(x[:n][m] / xf[:n][m] - 1)))
        mz = m & (xf[:n] >= ZONE)
        err_zone = float(np.max(np.abs(x[:n][mz] / xf[:n][mz] - 1)))
        b = band(p[(tp >= WINDOW[0]) & (tp <= WINDOW[1])])
        q = b["mean"] / ref["mean"] - 1
        bF = band(F[(tF >= WINDOW[0]) & (tF <= WINDOW[1])])
        qF = bF["mean"] / refF["mean"] - 1
        # the difference's standard error from the paired series F(t) - F_fine(t) on the common rows (the slow decay
        # both share cancels; the two means' own standard errors, dominated by it, would overstate it)
        nF = min(len(tF), len(tFf))
        wF = (tFf[:nF] >= WINDOW[0]) & (tFf[:nF] <= WINDOW[1])
        if not np.allclose(tF[:nF], tFf[:nF]):
            raise SystemExit(f"{tag}: the force rows are not at the fine run's times")
        bd = band(F[:nF][wF] - Ff[:nF][wF])
        se_d = bd["se"] / refF["mean"]
        gate = max(TOL, 2 * se_d)
        name_z = f"{tag}: front inside the fine zone ({ZONE} <= x < {FRONT_MAX} m) vs the fine run, max relative difference"
        name_f = f"{tag}: front over its whole path (x < {FRONT_MAX} m) vs the fine run, max relative difference"
        name_F = (f"{tag}: wall force below 0.3 m, mean over t = {WINDOW[0]}-{WINDOW[1]} s vs the fine run's "
                  f"({refF['mean']:.1f} N/m = {refF['mean'] / (0.5 * RGH * 0.292):.3f} x 1/2 rho g H^2)")
        name_p = f"{tag}: wall sensor mean over t = {WINDOW[0]}-{WINDOW[1]} s vs the fine run's ({ref['mean'] / RGH:.3f} rho g H)"
        vF = (f"{100 * qF:+.2f} % (se of the paired difference {100 * se_d:.2f} %, n_eff {bd['n_eff']:.0f}; "
              f"{tag} {fmt_band(bF, unit=' N/m')}, fine {fmt_band(refF, unit=' N/m')})")
        if tag == "refined":
            rep.metric(name_z, f"{100 * err_zone:.2f} %", err_zone <= TOL, f"<= {100 * TOL:g} %", "issue 58, check 2")
            info(name_f, f"{100 * err:.2f} %", err <= TOL, f"<= {100 * TOL:g} %", "issue 42's gate: the front upstream of the zone runs in the coarse part")
            rep.metric(name_F, vF, abs(qF) <= gate, f"|.| <= max(2 %, 2 se) = {100 * gate:.2f} %", "issue 58, check 2")
            info(name_p, f"{100 * q:+.1f} % {fmt_band(b, unit=' rho g H', scale=1 / RGH)}", abs(q) <= TOL,
                 f"|.| <= {100 * TOL:g} %", "issue 42's check 2")
        else:
            info(name_z, f"{100 * err_zone:.2f} %", err_zone <= TOL, f"<= {100 * TOL:g} %", "the uniform coarse run, for comparison")
            info(name_F, vF, abs(qF) <= gate, f"|.| <= {100 * gate:.2f} %", "the uniform coarse run, for comparison")
            info(name_p, f"{100 * q:+.1f} %", abs(q) <= TOL, f"|.| <= {100 * TOL:g} %", "the uniform coarse run, for comparison")
    sr, sf = res["refined"][4], res["fine"][4]
    info("refined run's wall time / the fine run's", f"{res['refined'][5] / res['fine'][5]:.2f} "
         f"({sr['particles']['fluid']} vs {sf['particles']['fluid']} fluid particles at the end)", True, "reported", "issue 42")

    fig, ax = plt.subplots(1, 3, figsize=(16, 4.2))
    for tag, col in (("coarse", "C0"), ("fine", "k"), ("refined", "C3")):
        t, x, tp, p, s, wall, label, tF, F = res[tag]
        ax[0].plot(t, x, color=col, label=label)
        ax[1].plot(tp, p / RGH, color=col, label=label, lw=0.9)
        ax[2].plot(tF, F / (0.5 * RGH * 0.292), color=col, label=label, lw=0.9)
    ax[0].set_xlabel("t (s)")
    ax[0].set_ylabel("front x (m)")
    ax[0].legend(fontsize=8)
    ax[1].axvspan(*WINDOW, color="0.9")
    ax[1].set_xlabel("t (s)")
    ax[1].set_ylabel("p / rho g H at (0.584, 0.0146)")
    ax[1].legend(fontsize=8)
    ax[0].axhspan(ZONE, FRONT_MAX, color="0.9")
    ax[2].axvspan(*WINDOW, color="0.9")
    ax[2].set_xlabel("t (s)")
    ax[2].set_ylabel("wall force below 0.3 m / (1/2 rho g H^2)")
    ax[2].legend(fontsize=8)
    save_figure(fig, HERE, NAME, a.mode, a.out)
    return rep.finish(NAME, a.mode)


if __name__ == "__main__":
    sys.exit(main())
