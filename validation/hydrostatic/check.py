#!/usr/bin/python3
"""Hydrostatic tank validation (cases/hydrostatic.yaml).

A 0.5 m x 0.5 m water column at rest in a closed tank is run for t = 50 sqrt(H/g) = 11.29 s.
Metrics (closed-form solution p = rho g (H - z), u = 0):
  1. bottom pressure from the kernel-interpolated gauge p_bottom, averaged over the output rows of the last
     second (t >= t_end - 1 s: the gauge is steady there, the average removes the residual acoustic noise),
     against rho g H: relative error <= 1 % (fine, dx = 0.01, the issue's threshold);
     <= 2 % in coarse mode (dx = 0.02): the wall-boundary error of dummy particles is first order in dx,
     so the 1 % allowed at dx = 0.01 doubles at dx = 0.02;
  2. max |u| of the fluid particles in the last snapshot < 0.01 sqrt(g H) (both modes);
  3. particle count constant: particles.fluid == particles.initial_fluid and mass.removed == 0, and the mass
     balance (initial - removed - final)/initial within 1e-12 (round-off) (both modes).
Usage: /usr/bin/python3 validation/hydrostatic/check.py [--mode coarse|fine] [--sphflume PATH] [--out DIR]
"""
import csv
import math
import os
import sys

import h5py
import numpy as np
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from common import Report, band, fmt_band, parse_sets, run_case, save_figure, validation_args  # noqa: E402

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
CASE = os.path.normpath(os.path.join(HERE, "..", "..", "cases", "hydrostatic.yaml"))
NAME = "hydrostatic"

RHO, G, H = 1000.0, 9.81, 0.5
T_END = 50.0 * math.sqrt(H / G)  # 11.29 s
MODES = {
    # only resolution and end time differ between the modes
    "coarse": {"dx": 0.02, "end": 11.29, "p_tol": 0.02},
    "fine": {"dx": 0.01, "end": 11.29, "p_tol": 0.01},
}
AVERAGE_WINDOW = 1.0  # s: the bottom pressure is averaged over the output rows with t >= t_end - 1 s
U_TOL = 0.01 * math.sqrt(G * H)


def read_gauge(path):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    return {k: np.array([float(r[k]) for r in rows]) for k in rows[0]}


def last_snapshot(out):
    snaps = sorted(os.listdir(os.path.join(out, "snapshots")))
    return os.path.join(out, "snapshots", snaps[-1])


def main():
    a = validation_args(NAME, __doc__, MODES)
    m = MODES[a.mode]
    os.makedirs(a.out, exist_ok=True)
    out = os.path.join(a.out, f"dx{m['dx']:g}")
    s, wall, rc = run_case(a.sphflume, CASE, out, {"particles.dx": m["dx"], "time.end": m["end"], **parse_sets(a.set)}, a.threads, a.reuse)
    rep = Report()
    print(f"\n== {NAME} ({a.mode}: dx = {m['dx']} m, t_end = {m['end']} s; run wall time {wall:.1f} s)")
    if s is None:
        print(f"[FAIL] run exit code = {rc}   (threshold: 0)")
        return 2
    rep.metric("run reached t_end (s)", f"{s['simulated_time']:.4f}", s["simulated_time"] >= m["end"] * (1 - 1e-6),
               f">= {m['end']}", "issue: t = 50 sqrt(H/g)")

    # 1. bottom pressure
    pg = read_gauge(os.path.join(out, "gauges", "p_bottom.csv"))
    t, p = pg["time"], pg["pressure"]
    p_ref = RHO * G * H
    win = t >= t[-1] - AVERAGE_WINDOW - 1e-9
    n_nan = int(np.sum(~np.isfinite(p)))
    p_avg = float(np.mean(p[win]))
    err = abs(p_avg - p_ref) / p_ref
    pb = band(p[win])
    print(f"  p_bottom: last row t = {t[-1]:.3f} s: {p[-1]:.2f} Pa; mean of {win.sum()} rows t in "
          f"[{t[win][0]:.2f}, {t[win][-1]:.2f}] s: {p_avg:.2f} Pa; rho g H = {p_ref:.2f} Pa; NaN rows: {n_nan}")
    print(f"  p_bottom band vs rho g H: {fmt_band(pb, p_ref, digits=3)}")
    rep.metric("bottom pressure |p - rho g H| / (rho g H)", f"{100 * err:.3f} %", err <= m["p_tol"] and n_nan == 0,
               f"<= {100 * m['p_tol']:g} % ({'issue' if a.mode == 'fine' else 'issue 1 % at dx=0.01, x2 for first order at dx=0.02'})",
               "closed form p = rho g H, gauge p_bottom (linear-MLS interpolation at (0.25, 0))")
    pm = read_gauge(os.path.join(out, "gauges", "p_mid.csv"))
    win_m = pm["time"] >= pm["time"][-1] - AVERAGE_WINDOW - 1e-9
    pm_avg = float(np.mean(pm["pressure"][win_m]))
    print(f"  (info) p_mid at z = 0.25: {pm_avg:.2f} Pa vs rho g H/2 = {p_ref / 2:.2f} Pa "
          f"({fmt_band(band(pm['pressure'][win_m]), p_ref / 2, digits=3)})")
    lv = read_gauge(os.path.join(out, "gauges", "level.csv"))
    print(f"  (info) water level at x = 0.25: {lv['level'][-1]:.5f} m (H = {H} m)")

    # 2. residual velocity
    snap = last_snapshot(out)
    with h5py.File(snap, "r") as f:
        kind = f["kind"][:]
        pos, vel, pres = f["position"][:], f["velocity"][:], f["pressure"][:]
        t_snap = float(f.attrs["time"])
    fl = kind == 0
    umax = float(np.max(np.linalg.norm(vel[fl], axis=1)))
    with h5py.File(snap, "r") as f:
        rho_f, m_f = f["density"][:][fl], f["mass"][:][fl]
    slope, icpt = np.polyfit(pos[fl, 2], pres[fl], 1)
    rho_mean = float(m_f.sum() / np.sum(m_f / rho_f))
    print(f"  (info) particle pressures, linear fit: dp/dz = {slope:.1f} Pa/m (-rho_mean g = {-rho_mean * G:.1f}, "
          f"{100 * (slope / (-rho_mean * G) - 1):+.2f} %), p(z=0) = {icpt:.1f} Pa; weight per unit width M g / W = "
          f"{m_f.sum() * G / 0.5:.1f} Pa (what the bed must carry)")
    rep.metric(f"max |u| of fluid at t = {t_snap:.2f} s (m/s)", f"{umax:.3e}", umax < U_TOL,
               f"< 0.01 sqrt(gH) = {U_TOL:.4e}", "issue (closed form u = 0)")

    # 3. particle count
    P = s["particles"]
    ok = P["fluid"] == P["initial_fluid"] and s["mass"]["removed"] == 0
    rep.metric("fluid particles final / initial, mass removed", f"{P['fluid']} / {P['initial_fluid']}, {s['mass']['removed']}",
               ok, "equal, 0", "issue (closed tank)")
    rep.metric("fluid mass (initial - removed - final) / initial", f"{s['mass']['relative_error']:.1e}",
               abs(s["mass"]["relative_error"]) <= 1e-12, "|.| <= 1e-12 (round-off)", "issue (mass conserved in closed cases)")
    print(f"  (info) wall {s['wall_seconds']} s, "
          f"{s['particle_steps_per_second']:.3g} particle-steps/s")

    # plot
    fig, ax = plt.subplots(1, 2, figsize=(11, 4.5))
    ax[0].plot(t, p / p_ref, "o-", ms=3, label="p_bottom gauge / (rho g H)")
    ax[0].axhspan(1 - m["p_tol"], 1 + m["p_tol"], color="g", alpha=0.15, label=f"±{100 * m['p_tol']:g} %")
    ax[0].axhline(1.0, color="k", lw=0.8)
    ax[0].axvspan(t[win][0], t[-1], color="0.85", label="averaging window")
    ax[0].fill_between(t[win], (pb["mean"] - pb["sd"]) / p_ref, (pb["mean"] + pb["sd"]) / p_ref, color="C1", alpha=0.4,
                       label=f"window mean ± sd ({100 * pb['sd'] / p_ref:.3f} %)")
    ax[0].set_xlabel("t (s)")
    ax[0].set_ylabel("p / (rho g H)")
    ax[0].set_title(f"bottom pressure, dx = {m['dx']} m: error {100 * err:.2f} %")
    ax[0].legend(fontsize=8)
    z = pos[fl, 2]
    ax[1].plot(pres[fl], z, ".", ms=2, label=f"fluid particles, t = {t_snap:.2f} s")
    zz = np.linspace(0, H, 50)
    ax[1].plot(RHO * G * (H - zz), zz, "k-", lw=1, label="rho g (H - z)")
    ax[1].set_xlabel("p (Pa)")
    ax[1].set_ylabel("z (m)")
    ax[1].set_title(f"pressure vs depth; max |u| = {umax:.2e} m/s")
    ax[1].legend(fontsize=8)
    fig.tight_layout()
    save_figure(fig, HERE, NAME, a.mode, a.out)

    if rep.failed:
        print(f"\n{NAME} {a.mode}: FAILED: {', '.join(rep.failed)}")
        return 1
    print(f"\n{NAME} {a.mode}: all metrics pass")
    return 0


if __name__ == "__main__":
    sys.exit(main())
