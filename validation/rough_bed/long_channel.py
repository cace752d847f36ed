#!/usr/bin/python3
"""Kazemi's in/out channel with unknown discharge, long enough for friction control (issue 20, decision 3).

The thesis's 4H channel cannot show friction control: its whole slope head S0 L (0.8 mm for S004H50) is below
dx/2, so any boundary-pressure inconsistency of that size sets the discharge (README.md). Here the channel is
long enough for the slope head to span at least 4 dx: L = max(40 H, 4 dx / S0) rounded up to a whole number of H
(S004H50 at H/dx = 10: 100 H = 5.0 m; at H/dx = 20: 50 H). Inflow: Kazemi's averaged (unknown-discharge) inflow;
outlet: a tailgate, the tailwater stage H + R_d imposed as hydrostatic pressure with a zero-gradient velocity
(flows.py, outlet "tailwater"), as a flume's tailgate is set to the measured depth. Start from U0 = 0.2 m/s (the
thesis's), so the discharge has to find its value. The reference is the periodic channel at the same dx (the
model's developed uniform flow; check.py's verification run), run beside it.

Gates (decision 3), over the window (the last third of the run):
  - discharge (mid-channel flux gauge) within 3 % of the periodic channel's;
  - depth uniform within 2 % ((max - min) / mean of the time-mean depth at 9 stations over the middle 80 %);
  - |V_out - V_in| / V_in < 0.5 % over every 10 s window of the window (issue 40, decision 3; Kazemi eq 3.19,
    boundary volume gauge); the same per 1 s is printed (it measures the insertion's granularity too).
Modes: coarse H/dx = 10, medium 15, fine 20.
Reported: the thesis's 4H channel with the same inflow and its frozen outlet (check.py's in/out run).
Not in CTest (a 12 k particle run of 40 s takes about 15 min on 2 cores); results in README.md.
Usage: /usr/bin/python3 validation/rough_bed/long_channel.py [--mode coarse|medium|fine] [--reuse] [--out DIR]
       [--set flows=S004H50] [--set t_end=40]
"""
import math
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, ".."))
sys.path.insert(0, HERE)
from common import Report, run_case, validation_args  # noqa: E402
import flows  # noqa: E402
from check import ode, read_csv, window_mean, worst_volume_imbalance  # noqa: E402

NAME = "rough_bed_long"
# medium: H/dx = 15, decision 3's run to see whether the depth's fall converges
MODES = {"coarse": {"dx_per_h": 10, "t_end": 40.0}, "medium": {"dx_per_h": 15, "t_end": 40.0},
         "fine": {"dx_per_h": 20, "t_end": 40.0}}
U0 = 0.2


def length_h(fid, dx_per_h):
    _, _, s0, h, _, _ = flows.flow(fid)
    dx = flows.dx_of(fid, dx_per_h)
    return float(max(40, math.ceil(4.0 * dx / s0 / h)))


def run(a, fid, kind, cfg, t_end, threads):
    dx = flows.dx_of(fid, cfg["dx_per_h"])
    if kind == "long":
        text = flows.case_yaml(fid, cfg["dx_per_h"], t_end, u0=U0, outlet="tailwater",
                               length_h=length_h(fid, cfg["dx_per_h"]), output=0.5)
    else:
        text = flows.case_yaml(fid, cfg["dx_per_h"], t_end, u0=round(ode(fid)[1], 4), periodic=True)
    out = os.path.join(a.out, f"{fid}_{kind}")
    os.makedirs(a.out, exist_ok=True)
    with open(out + ".yaml", "w") as f:
        f.write(text)
    return run_case(a.sphflume, out + ".yaml", out, {"particles.dx": dx, "time.end": t_end}, threads, a.reuse), out


def main():
    a = validation_args(NAME, __doc__, MODES)
    cfg = MODES[a.mode]
    sets = dict(kv.split("=", 1) for kv in a.set)
    t_end = float(sets.get("t_end", cfg["t_end"]))
    t0, t1 = t_end * 2.0 / 3.0, t_end
    rep = Report()
    for fid in sets.get("flows", "S004H50").split(","):
        _, _, s0, h, _, _ = flows.flow(fid)
        rd = flows.rd_of(fid, "table")
        dx = flows.dx_of(fid, cfg["dx_per_h"])
        lh = length_h(fid, cfg["dx_per_h"])
        print(f"== {fid}: H/dx = {h / dx:.2f}, L = {lh:g} H = {lh * h:.3f} m, S0 L = {1000 * s0 * lh * h:.2f} mm "
              f"= {s0 * lh * h / dx:.2f} dx; window {t0:g}-{t1:g} s", flush=True)
        (sp, _, rcp), outp = run(a, fid, "periodic", cfg, t_end, a.threads)
        (sl, _, rcl), outl = run(a, fid, "long", cfg, t_end, a.threads)
        for kind, rc in (("periodic", rcp), ("long", rcl)):
            rep.metric(f"{fid} {kind} run completes", f"exit {rc}", rc == 0, "exit 0", "robustness")
        if rcp or rcl:
            continue
        _, qp = read_csv(os.path.join(outp, "gauges", "q_mid.csv"))
        _, ql = read_csv(os.path.join(outl, "gauges", "q_mid.csv"))
        qpm, qlm = window_mean(qp, t0, t1)[0], window_mean(ql, t0, t1)[0]
        rep.metric(f"{fid} long channel discharge vs the periodic channel's {qpm:.5f} m2/s", f"{qlm:.5f} "
                   f"({100 * (qlm / qpm - 1):+.2f} %)", abs(qlm / qpm - 1) <= 0.03, "within 3 %",
                   "issue 20 decision 3")
        for ta in (t0 - 10, t0 - 5, t0):
            if ta > 0:
                print(f"       discharge over [{ta - 1:g}, {ta:g}] s: {window_mean(ql, ta - 1, ta)[0]:.5f} m2/s")
        _, dep = read_csv(os.path.join(outl, "gauges", "depth.csv"))
        dm = window_mean(dep, t0, t1)
        unif = (dm.max() - dm.min()) / dm.mean()
        rep.metric(f"{fid} depth non-uniformity over the middle 80 % (9 stations)", f"{100 * unif:.2f} % "
                   f"(mean {1000 * dm.mean():.2f} mm, H + R_d = {1000 * (h + rd):.2f} mm; stations "
                   + " ".join(f"{1000 * d:.1f}" for d in dm) + ")", unif <= 0.02, "<= 2 %", "issue 20 decision 3")
        # decision 3 (issue 40): the balance over 10 s windows (every window of the averaging window, 1 s apart);
        # over 1 s it also measures the insertion's granularity (a row of inflow particles at a time): printed
        width = min(10.0, t1 - t0)
        worst = worst_volume_imbalance(outl, t0, t1, width)
        rep.metric(f"{fid} worst |V_out - V_in| / V_in over {width:g} s windows", f"{100 * worst:.3f} %", worst < 0.005,
                   "< 0.5 %", "issue 40 decision 3; Kazemi eq 3.19")
        print(f"       (info) the same per 1 s: {100 * worst_volume_imbalance(outl, t0, t1, 1.0):.3f} %")
        mb = sl["mass"]
        print(f"       long channel: {sl['particles']['total']} particles, {sl['steps']} steps, "
              f"{sl.get('wall_seconds', float('nan')):.0f} s wall; mass balance {mb['relative_error']:.1e}")
    rep.finish(NAME, a.mode)


if __name__ == "__main__":
    main()
