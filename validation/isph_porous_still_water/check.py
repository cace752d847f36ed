#!/usr/bin/python3
"""Still water with a saturated porous block under ISPH (issue 21, validation 2; cases/porous_still_water_isph.yaml).

The ISPH still tank (0.5 m wide, h = 0.21 m) with a block of porosity 0.49, grain 15.9 mm, over the right half of
its floor (0.1 m high), run twice: with Tsurudome's porous particles (porous.field: particles) and with the
porosity field of the WCSPH cases (porous.field: smoothed). For each, over the snapshots and gauge rows with
t >= 2 s (issue 21):
  1. pressure probes inside the block (bottom, middle), on its top and side faces and in the clear water beside it
     (bottom, middle): time-mean within 2 % of rho g (h - z) (fine, dx = 0.005); 4 % at dx = 0.01 (coarse: the
     probes' error is first order in dx);
  2. no fluid particle inside the block (porosity < 0.99) flagged as free surface;
  3. number density inside the block / in the clear water within 10 % of the porosity 0.49;
  4. fluid mass exact.
Information: the probe above the block (z = 0.15 m, close to the surface), max |u| at the end.
Usage: /usr/bin/python3 validation/isph_porous_still_water/check.py [--mode coarse|fine] [--sphflume PATH] [--out DIR]
"""
import glob
import os
import sys

import h5py
import numpy as np
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from common import Report, band, fmt_band, parse_sets, read_rows, run_case, save_figure, validation_args  # noqa: E402

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
CASE = os.path.normpath(os.path.join(HERE, "..", "..", "cases", "porous_still_water_isph.yaml"))
NAME = "isph_porous_still_water"
RHO, G, H, PHI = 1000.0, 9.81, 0.21, 0.49
MODES = {
    # only resolution and end time differ between the modes
    "coarse": {"dx": 0.01, "end": 3.0, "p_tol": 0.04},
    "fine": {"dx": 0.005, "end": 3.0, "p_tol": 0.02},
}
T_AVG = 2.0
PROBES = {"p_block_bottom": 0.02, "p_block_mid": 0.05, "p_block_top_face": 0.1, "p_block_side_face": 0.05,
          "p_clear_bottom": 0.02, "p_clear_mid": 0.05}
BLOCK = (0.25, 0.5, 0.0, 0.1)  # x0, x1, z0, z1 of the block inside the tank
INNER = (0.27, 0.48, 0.01, 0.08)  # counting windows away from the faces
CLEAR = (0.02, 0.23, 0.01, 0.08)


def inside(x, z, box):
    return (x > box[0]) & (x < box[1]) & (z > box[2]) & (z < box[3])


def main():
    a = validation_args(NAME, __doc__, MODES)
    m = MODES[a.mode]
    os.makedirs(a.out, exist_ok=True)
    rep = Report()
    fig, ax = plt.subplots(1, 3, figsize=(16, 4.5))
    for v, field in enumerate(("particles", "smoothed")):
        out = os.path.join(a.out, f"{field}_dx{m['dx']:g}")
        s, wall, rc = run_case(a.sphflume, CASE, out, {"particles.dx": m["dx"], "time.end": m["end"],
                                                       "porous.field": field, **parse_sets(a.set)}, a.threads, a.reuse)
        print(f"\n== {NAME}, porous.field: {field} ({a.mode}: dx = {m['dx']} m; run wall time {wall:.1f} s)")
        if s is None:
            rep.metric(f"{field}: run", f"exit {rc}", False, "exit 0", "issue 21")
            continue
        worst, bands = 0.0, []
        for name, z in PROBES.items():
            hdr, rows = read_rows(os.path.join(out, "gauges", f"{name}.csv"))
            t, p = rows[:, 0], rows[:, hdr.index("pressure")]
            bands.append(band(p[t >= T_AVG - 1e-9]))
            pm = bands[-1]["mean"]
            ph = RHO * G * (H - z)
            worst = max(worst, abs(pm / ph - 1))
            print(f"  {name:18s} z = {z:.2f} m: {pm:8.1f} Pa vs {ph:8.1f} Pa ({fmt_band(bands[-1], ph)})")
        rep.metric(f"{field}: pressure probes in, on and beside the block, max |p - p_h| / p_h (t >= 2 s)", f"{100 * worst:.2f} %",
                   worst <= m["p_tol"], f"<= {100 * m['p_tol']:g} %", "issue 21" + ("" if a.mode == "fine" else " (x2 at twice dx)"))
        hdr, rows = read_rows(os.path.join(out, "gauges", "p_above_block.csv"))
        pa = band(rows[rows[:, 0] >= T_AVG - 1e-9, hdr.index("pressure")])
        print(f"  (info) p_above_block z = 0.15 m: {pa['mean']:.1f} Pa vs {RHO * G * (H - 0.15):.1f} Pa "
              f"({fmt_band(pa, RHO * G * (H - 0.15))})")
        flagged, ratios = 0, []
        for f in sorted(glob.glob(os.path.join(out, "snapshots", "*.h5"))):
            with h5py.File(f, "r") as h:
                if float(h.attrs["time"]) < T_AVG - 1e-9:
                    continue
                fl = h["kind"][:] == 0
                x, z = h["position"][:][fl, 0], h["position"][:][fl, 2]
                phi = h["porosity"][:][fl]
                flagged += int(np.sum((h["free_surface"][:][fl] > 0.5) & (phi < 0.99)))
                ratios.append(np.sum(inside(x, z, INNER)) / np.sum(inside(x, z, CLEAR)))
        ratio = float(np.mean(ratios))
        rep.metric(f"{field}: fluid particles inside the block flagged as free surface (t >= 2 s)", str(flagged), flagged == 0,
                   "0", "issue 21")
        rep.metric(f"{field}: number density inside / outside, over the porosity", f"{ratio / PHI:.3f}", abs(ratio / PHI - 1) <= 0.1,
                   "within 10 % of 1", "issue 21")
        rep.metric(f"{field}: fluid mass balance", f"{s['mass']['relative_error']:.1e}", abs(s["mass"]["relative_error"]) <= 1e-12,
                   "|.| <= 1e-12", "closed tank")
        with h5py.File(sorted(glob.glob(os.path.join(out, "snapshots", "*.h5")))[-1], "r") as h:
            fl = h["kind"][:] == 0
            pos, pres, vel = h["position"][:][fl], h["pressure"][:][fl], h["velocity"][:][fl]
            phi = h["porosity"][:][fl]
        umax = float(np.max(np.linalg.norm(vel, axis=1)))
        print(f"  (info) max |u| at the end {umax:.3e} m/s (0.01 sqrt(g h) = {0.01 * np.sqrt(G * H):.4f})")
        blk = phi < 0.99
        ax[v].plot(pres[~blk], pos[~blk, 2], ".", ms=2, label="clear water")
        ax[v].plot(pres[blk], pos[blk, 2], ".", ms=2, label="inside the block (phi < 0.99)")
        zz = np.linspace(0, H, 50)
        ax[v].plot(RHO * G * (H - zz), zz, "k-", lw=1, label="rho g (h - z)")
        ax[v].errorbar([b["mean"] for b in bands], list(PROBES.values()), xerr=[b["sd"] for b in bands], fmt="ks",
                       mfc="none", capsize=3, label=f"probes, t >= {T_AVG:g} s: mean ± sd")
        ax[v].set_xlabel("p (Pa)")
        ax[v].set_ylabel("z (m)")
        ax[v].set_title(f"porous.field: {field}, probes max {100 * worst:.1f} %")
        ax[v].legend(fontsize=8)
        if field == "particles":
            sc = ax[2].scatter(pos[:, 0], pos[:, 2], c=phi, s=2, cmap="viridis")
            ax[2].add_patch(plt.Rectangle((BLOCK[0], BLOCK[2]), BLOCK[1] - BLOCK[0], BLOCK[3] - BLOCK[2], fill=False, ec="r"))
            fig.colorbar(sc, ax=ax[2], label="porosity")
            ax[2].set_aspect("equal")
            ax[2].set_title(f"particles at t = {m['end']} s (porous particles)")
    fig.tight_layout()
    save_figure(fig, HERE, NAME, a.mode, a.out)
    if rep.failed:
        print(f"\n{NAME} {a.mode}: FAILED: {', '.join(rep.failed)}")
        return 1
    print(f"\n{NAME} {a.mode}: all metrics pass")
    return 0


if __name__ == "__main__":
    sys.exit(main())
