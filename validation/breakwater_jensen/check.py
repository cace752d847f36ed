#!/usr/bin/python3
"""Solitary-wave run-up on smooth, rough and porous 1:1.5 breakwaters: Jensen et al. (2015), Kazemi's test case III
(issue 22, validation 7; cases/breakwater_jensen_{smooth,rough,porous}.yaml; Kazemi §5.4).

h0 = 0.40 m, H = 0.14 m, the breakwater's toe 13.55 m from the paddle, front slope 1:1.5. Smooth: an impermeable
slope. Rough: a porous armour one grain (38 mm) thick, porosity 0.4, on the impermeable slope. Porous: armour and core
one porous region (porosity 0.4, d = 38 mm). SPHAM with Ergun's c1 = 150, c2 = 1.75, Smagorinsky Cs = 0.15.
The crest and the LDA section are assumed (the case files say how); the measured records are not in the project.
Time origin as the experiment's: t' = 0 when the crest reaches the toe gauge.
What the thesis reports (§5.4, Fig. 5-32), gated here as orderings:
  1. each run reaches t_end, fluid mass conserved exactly;
  2. run-up: the rough and porous run-ups lie below the smooth one, by "only a few millimetres": each within
     10 % of the smooth R below it (R_rough <= R_smooth, R_porous <= R_smooth, and R_x >= 0.9 R_smooth);
  3. the slope-parallel velocity at section I varies most on the smooth slope, less on the rough one and least on the
     porous one: range (max - min over t' in [-2, 4] s) smooth > rough > porous, with the smooth probe 19 mm and the
     rough and porous probes 57 mm above the face, as in the thesis;
Information: the run-down (lowest waterline after the run-up) and the secondary run-up (highest waterline after the
run-down; the thesis: almost absent on the porous slope), the crest at the offshore and toe gauges.
Usage: /usr/bin/python3 validation/breakwater_jensen/check.py [--mode fine|coarse] [--out DIR] [--reuse] [--kinds smooth,rough]
(--kinds: the slopes of this call, smooth first when the ratios are wanted; default all three)
(fine: dx = 0.02 m, the cases' value; coarse: dx = 0.04 m, a smoke run that is not a validation).
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
CASES = os.path.normpath(os.path.join(HERE, "..", "..", "cases"))
NAME = "breakwater_jensen"
KINDS = ("smooth", "rough", "porous")
H0, HW = 0.40, 0.14
ALPHA = math.atan(1 / 1.5)
TANGENT = np.array([math.cos(ALPHA), math.sin(ALPHA)])
MODES = {"coarse": {"dx": 0.04, "end": 11.5}, "fine": {"dx": 0.02, "end": 11.5}}
PROBE = {"smooth": "u_low", "rough": "u_high", "porous": "u_high"}   # 19 mm and 57 mm above the face
RUNUP_BAND = 0.10


def series(out, name):
    hdr, rows = read_rows(os.path.join(out, "gauges", f"{name}.csv"))
    return {h: rows[:, k] for k, h in enumerate(hdr)}


def main():
    a = validation_args(NAME, __doc__, MODES, extra=lambda ap: ap.add_argument(
        "--kinds", default=",".join(KINDS), help="comma-separated slopes of this call (smooth, rough, porous)"))
    m = MODES[a.mode]
    rep = Report()
    res = {}
    kinds = [k for k in KINDS if k in a.kinds.split(",")]
    for kind in kinds:
        out = os.path.join(a.out, kind, f"dx{m['dx']:g}")
        sets = {"particles.dx": m["dx"], "time.end": m["end"], **parse_sets(a.set)}
        s, wall, rc = run_case(a.sphflume, os.path.join(CASES, f"breakwater_jensen_{kind}.yaml"), out, sets, a.threads, a.reuse)
        print(f"\n== {NAME} {kind} ({a.mode}: dx = {m['dx']} m, end {m['end']} s; run wall time {wall:.1f} s)")
        if s is None:
            rep.metric(f"{kind}: run exit code", rc, False, "0", "issue 22")
            continue
        run_metrics(rep, f"{kind}: ", s, m["end"])
        toe = series(out, "wg_toe")
        eta_toe = toe["level"] - toe["level"][0]
        k = int(np.argmax(eta_toe))
        t0 = float(toe["time"][k])
        off = series(out, "wg_off")
        eta_off = off["level"] - off["level"][0]
        ru = series(out, "runup")
        t = ru["time"] - t0
        r = ru["runup"]
        kmax = int(np.nanargmax(r))
        after = np.arange(len(r)) > kmax
        kdown = int(np.nanargmin(np.where(after, r, np.nan)))
        later = np.arange(len(r)) > kdown
        second = float(np.nanmax(np.where(later, r, np.nan))) if np.any(later) else float("nan")
        u = series(out, PROBE[kind])
        upar = u["ux"] * TANGENT[0] + u["uz"] * TANGENT[1]
        tu = u["time"] - t0
        w = (tu >= -2.0) & (tu <= 4.0) & np.isfinite(upar)
        res[kind] = dict(t=t, r=r, R=float(r[kmax]), t_R=float(t[kmax]), down=float(r[kdown]), t_down=float(t[kdown]),
                         second=second, tu=tu, upar=upar, range=float(np.ptp(upar[w])) if np.any(w) else float("nan"),
                         t_toe=toe["time"] - t0, eta_toe=eta_toe, crest_toe=float(eta_toe[k]), crest_off=float(np.max(eta_off)))
        info(f"{kind}: crest offshore (x = 6 m) / at the toe", f"{100 * res[kind]['crest_off']:.1f} / {100 * res[kind]['crest_toe']:.1f} cm",
             True, "-", f"generated H = {100 * HW:g} cm")
        info(f"{kind}: run-up R, run-down, secondary run-up (above SWL)",
             f"{1000 * res[kind]['R']:.0f} mm at t' = {res[kind]['t_R']:.2f} s, {1000 * res[kind]['down']:.0f} mm at "
             f"t' = {res[kind]['t_down']:.2f} s, {1000 * second:.0f} mm", True, "-", "thesis Fig. 5-32")
        print(f"  wall {wall:.1f} s, {s['steps']} steps, {s['particles']['total']} particles, "
              f"{s['particle_steps_per_second']:.3g} particle-steps/s")
    if "smooth" not in res:
        rep.finish(NAME, a.mode)
        return 1
    Rs = res["smooth"]["R"]
    for kind in [k for k in ("rough", "porous") if k in res]:
        q = res[kind]["R"] / Rs
        rep.metric(f"run-up {kind} / smooth", f"{q:.3f} ({1000 * (res[kind]['R'] - Rs):+.0f} mm)", 1 - RUNUP_BAND <= q <= 1.0,
                   "0.90 ... 1.00", "Kazemi §5.4: a few mm below the smooth slope's")
    rg = [res[k]["range"] if k in res else float("nan") for k in KINDS]
    if len(res) == len(KINDS):
        rep.metric("slope-parallel velocity range smooth > rough > porous", " > ".join(f"{v:.3f}" for v in rg) + " m/s",
                   rg[0] > rg[1] > rg[2], "strictly decreasing", "Kazemi §5.4, Fig. 5-32")
    if "porous" in res:
        info("secondary run-up porous vs smooth", f"{1000 * res['porous']['second']:.0f} vs {1000 * res['smooth']['second']:.0f} mm",
             res["porous"]["second"] < res["smooth"]["second"], "porous lower", "thesis: almost absent on the porous slope")

    fig, ax = plt.subplots(3, 1, figsize=(9, 9), sharex=True)
    for kind in res:
        d = res[kind]
        ax[0].plot(d["t_toe"], 100 * d["eta_toe"], label=kind)
        ax[1].plot(d["tu"], d["upar"], label=f"{kind} ({'19' if PROBE[kind] == 'u_low' else '57'} mm above the face)")
        ax[2].plot(d["t"], 1000 * d["r"], label=kind)
    ax[0].set_ylabel("eta at the toe [cm]")
    ax[1].set_ylabel("slope-parallel u, section I [m/s]")
    ax[2].set_ylabel("waterline above SWL [mm]")
    ax[2].set_xlabel("t' [s] (0: crest at the toe)")
    ax[2].set_xlim(-2, 4)
    for x in ax:
        x.legend(fontsize=8)
    ax[0].set_title(f"Jensen et al. (2015) breakwater, H/h0 = 0.35, dx = {m['dx']} m")
    fig.tight_layout()
    save_figure(fig, HERE, NAME, a.mode, a.out)
    rep.finish(NAME, a.mode)
    return 0


if __name__ == "__main__":
    sys.exit(main())
