#!/usr/bin/python3
"""Still tank with a refined block (issue 42, check 1; cases/still_tank_refined.yaml).

1.0 m x 0.5 m of water at rest; the fluid in x = 0.3 ... 0.7 m above z = 0.1 m starts at level 1
(dx/2, h/2, a quarter of the mass), so the level interface runs vertically, horizontally and up to
the free surface. Run for t = 30 sqrt(H/g) = 6.77 s. Metrics (closed form p = rho g (H - z), u = 0;
issue 42):
  1. pressure gauges inside the refined block (p_fine, x = 0.5) and in the level-0 water (p_coarse,
     x = 0.15), both at z = 0.25 m, averaged over the last second: within 1 % of rho g (H - z)
     (fine, dx = 0.01; 2 % coarse, dx = 0.02: the first-order wall error doubles);
  2. max |u| of the fluid in the last snapshot < 0.01 sqrt(g H);
  3. no jump at the level interface: the mean pressure error of the particles on either side of
     it (within one level-0 spacing of the block's faces, 0.1 < z < 0.4) differs by less than the
     pressure threshold (information: the whole profile is drawn);
  4. fluid mass (initial - final)/initial within 1e-12; particles are neither split nor merged
     during the run (the levels are fixed at set-up).
Usage: /usr/bin/python3 validation/still_tank_refined/check.py [--mode coarse|fine] [--sphflume PATH] [--out DIR]
"""
import math
import os
import sys

import h5py
import numpy as np
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from common import Report, parse_sets, read_rows, run_case, save_figure, validation_args  # noqa: E402

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
CASE = os.path.normpath(os.path.join(HERE, "..", "..", "cases", "still_tank_refined.yaml"))
NAME = "still_tank_refined"

RHO, G, H = 1000.0, 9.81, 0.5
X0, X1, Z0 = 0.3, 0.7, 0.1  # the refined block (cases/still_tank_refined.yaml)
MODES = {
    "coarse": {"dx": 0.02, "end": 6.77, "p_tol": 0.02},
    "fine": {"dx": 0.01, "end": 6.77, "p_tol": 0.01},
}
WINDOW = 1.0
U_TOL = 0.01 * math.sqrt(G * H)


def main():
    a = validation_args(NAME, __doc__, MODES)
    m = MODES[a.mode]
    os.makedirs(a.out, exist_ok=True)
    out = os.path.join(a.out, f"dx{m['dx']:g}")
    s, wall, rc = run_case(a.sphflume, CASE, out, {"particles.dx": m["dx"], "time.end": m["end"], **parse_sets(a.set)},
                           a.threads, a.reuse)
    rep = Report()
    print(f"\n== {NAME} ({a.mode}: dx = {m['dx']} m, t_end = {m['end']} s; run wall time {wall:.1f} s)")
    if s is None:
        print(f"[FAIL] run exit code = {rc}   (threshold: 0)")
        return 2
    rep.metric("run reached t_end (s)", f"{s['simulated_time']:.4f}", s["simulated_time"] >= m["end"] * (1 - 1e-6),
               f">= {m['end']}", "issue 42")
    gauges = {}
    for g in ("p_fine", "p_coarse"):
        _, rows = read_rows(os.path.join(out, "gauges", f"{g}.csv"))
        t, p = rows[:, 0], rows[:, 1]
        win = t >= t[-1] - WINDOW - 1e-9
        gauges[g] = (t, p)
        ref = RHO * G * (H - 0.25)
        err = float(np.mean(p[win])) / ref - 1.0
        rep.metric(f"{g} (z = 0.25 m) mean over the last {WINDOW:g} s vs rho g (H - z)", f"{100 * err:+.2f} %",
                   abs(err) <= m["p_tol"], f"|.| <= {100 * m['p_tol']:g} %", "issue 42 (hydrostatic within 1 %)")

    snaps = sorted(os.listdir(os.path.join(out, "snapshots")))
    with h5py.File(os.path.join(out, "snapshots", snaps[-1]), "r") as f:
        kind, pos, vel, pres, lev = f["kind"][:], f["position"][:], f["velocity"][:], f["pressure"][:], f["level"][:]
        t_snap = float(f.attrs["time"])
    fl = kind == 0
    x, z = pos[:, 0], pos[:, 2]
    speed = np.linalg.norm(vel, axis=1)
    umax = float(np.max(speed[fl]))
    i = int(np.argmax(np.where(fl, speed, -1)))
    rep.metric(f"max |u| of fluid at t = {t_snap:.2f} s (m/s)", f"{umax:.3e} at ({x[i]:.3f}, {z[i]:.3f}), level {int(lev[i])}",
               umax < U_TOL, f"< 0.01 sqrt(gH) = {U_TOL:.4e}", "issue 42 (quiet)")
    err = (pres - RHO * G * (H - z)) / (RHO * G * H)
    face = fl & (z > Z0 + m["dx"]) & (z < 0.4)
    near = face & (np.minimum(np.abs(x - X0), np.abs(x - X1)) < m["dx"])
    inside, outside = near & (lev > 0), near & (lev == 0)
    jump = float(np.mean(err[inside]) - np.mean(err[outside])) if inside.any() and outside.any() else float("nan")
    rep.metric("pressure error beside the vertical faces, level 1 minus level 0 (of rho g H)", f"{100 * jump:+.2f} %",
               abs(jump) <= m["p_tol"], f"|.| <= {100 * m['p_tol']:g} %", "issue 42 (no jump at the interface)")
    moved = int(np.sum(fl & (lev > 0) & ((x < X0 - 2 * m["dx"]) | (x > X1 + 2 * m["dx"]) | (z < Z0 - 2 * m["dx"]))))
    print(f"  (info) refined particles more than 2 level-0 spacings outside the block: {moved}")
    rep.metric("fluid mass (initial - final) / initial", f"{s['mass']['relative_error']:.1e}",
               abs(s["mass"]["relative_error"]) <= 1e-12, "|.| <= 1e-12", "issue 42 (conservation)")
    print(f"  (info) wall {s['wall_seconds']:.1f} s, {s['particles']['fluid']} fluid particles, {s['steps']} steps")

    fig, ax = plt.subplots(1, 3, figsize=(17, 4.6))
    for g, (t, p) in gauges.items():
        ax[0].plot(t, p / (RHO * G * (H - 0.25)), "o-", ms=3, label=g)
    ax[0].axhspan(1 - m["p_tol"], 1 + m["p_tol"], color="g", alpha=0.15)
    ax[0].set_xlabel("t (s)")
    ax[0].set_ylabel("p / rho g (H - z)")
    ax[0].legend(fontsize=8)
    ax[0].set_title("gauges at z = 0.25 m")
    for lvl, col in ((0, "C0"), (1, "C3")):
        sel = fl & (lev == lvl) & (np.abs(x - 0.5 if lvl else x - 0.15) < 0.05)
        ax[1].plot(pres[sel], z[sel], ".", ms=3, color=col, label=f"level {lvl} particles near x = {0.5 if lvl else 0.15}")
    zz = np.linspace(0, H, 50)
    ax[1].plot(RHO * G * (H - zz), zz, "k-", lw=1, label="rho g (H - z)")
    ax[1].axhline(Z0, color="0.6", lw=0.8, ls="--")
    ax[1].set_xlabel("p (Pa)")
    ax[1].set_ylabel("z (m)")
    ax[1].legend(fontsize=8)
    ax[1].set_title(f"pressure profiles, t = {t_snap:.2f} s")
    sc = ax[2].scatter(x[fl], z[fl], c=speed[fl], s=np.where(lev[fl] > 0, 2, 8), cmap="viridis")
    plt.colorbar(sc, ax=ax[2], label="|u| (m/s)")
    ax[2].plot([X0, X0, X1, X1], [H, Z0, Z0, H], "r-", lw=0.8)
    ax[2].set_aspect("equal")
    ax[2].set_title(f"|u|; max {umax:.3f} m/s (limit {U_TOL:.3f})")
    save_figure(fig, HERE, NAME, a.mode, a.out)
    return rep.finish(NAME, a.mode)


if __name__ == "__main__":
    sys.exit(main())
