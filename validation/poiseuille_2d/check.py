#!/usr/bin/python3
"""Plane Poiseuille flow started from rest (Morris, Fox & Zhu 1997), cases/poiseuille_2d.yaml.

Channel of width H = 1e-3 m between no-slip walls at z = 0 and z = H, periodic in x, nu = 1e-6 m^2/s, driven by
a body force F = 2e-4 m/s^2. Closed form (series solution of the start-up flow):
  u(z, t) = F/(2 nu) z (H - z) - sum_{n odd} 4 F H^2 / (nu pi^3 n^3) sin(n pi z / H) exp(-n^2 pi^2 nu t / H^2),
  u_c = F H^2 / (8 nu) = 2.5e-5 m/s.
Metric: at every output time t > 0, the fluid particles' u_x averaged over each horizontal lattice row (rows are
kept in this laminar flow: row = round(z/dx - 0.5)) against the exact u at the row's mean z;
  e = max over rows and times |u_row - u_exact| / u_c.
Thresholds (issue, the same in both modes): e <= 2 % at H/dx = 40; observed order log2(e20/e40) >= 1 and
log2(e40/e80) >= 1. Both modes run H/dx = 20, 40, 80 (dx = 5e-5, 2.5e-5, 1.25e-5; about 30 s in all on 2 cores);
coarse runs to t = 0.5 s (5 viscous times H^2/(pi^2 nu)), fine to t = 1.0 s (10 viscous times: the steady state
is reached to 5e-5 u_c and any slow drift of the lattice has twice as long to show).
Cross-check (information, not gated): the kernel-interpolated gauge profile (21 points across the channel at
x = H/5) against the same closed form, interior points only (the two end points sit on the walls).
Usage: /usr/bin/python3 validation/poiseuille_2d/check.py [--mode coarse|fine] [--sphflume PATH] [--out DIR]
"""
import csv
import math
import os
import sys

import h5py
import numpy as np
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from common import parse_sets, run_case, save_figure, validation_args  # noqa: E402

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
CASE = os.path.normpath(os.path.join(HERE, "..", "..", "cases", "poiseuille_2d.yaml"))
NAME = "poiseuille_2d"

H, NU, F = 1.0e-3, 1.0e-6, 2.0e-4
U_C = F * H * H / (8 * NU)
RES = {20: 5.0e-5, 40: 2.5e-5, 80: 1.25e-5}  # H/dx -> dx
MODES = {"coarse": {"end": 0.5}, "fine": {"end": 1.0}}
E_TOL = 0.02  # at H/dx = 40
ORDER_MIN = 1.0


def read_csv(path):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    return {k: np.array([float(r[k]) for r in rows]) for k in rows[0]}


def u_exact(z, t, n_terms=2001):
    """Start-up Poiseuille flow; the series converges as 1/n^3 (and exponentially for t > 0)."""
    z = np.asarray(z, dtype=float)
    u = F / (2 * NU) * z * (H - z)
    for n in range(1, n_terms + 1, 2):
        decay = math.exp(-n * n * math.pi ** 2 * NU * t / H ** 2)
        if decay < 1e-300:
            break
        u = u - 4 * F * H * H / (NU * math.pi ** 3 * n ** 3) * np.sin(n * math.pi * z / H) * decay
    return u


def lattice_laplacian_moment(h_over_dx):
    """Morris viscous operator applied to u = z^2/2 on a full square lattice (Wendland C2, 2D): 1 when exact.
    At a fixed h/dx this factor does not change with dx, so a deficit becomes an error floor (the steady
    centreline velocity scales as 1/moment)."""
    n = int(math.ceil(2 * h_over_dx)) + 1
    i, j = np.meshgrid(np.arange(-n, n + 1), np.arange(-n, n + 1))
    r = np.hypot(i, j).astype(float)
    z = j.astype(float)
    q = r / h_over_dx
    dwdr = np.where(q < 2, 7 / (4 * math.pi * h_over_dx ** 2) * (-5 * q * (1 - q / 2) ** 3) / h_over_dx, 0.0)
    mask = r > 0
    return float(np.sum(-z[mask] ** 2 * dwdr[mask] / r[mask]))


def analyse_run(out, dx):
    """Row-averaged u_x against the closed form at every snapshot with t > 0."""
    snaps = sorted(os.listdir(os.path.join(out, "snapshots")))
    n_rows = int(round(H / dx))
    times, err_t, profiles, row_counts_bad, uz_max = [], [], {}, 0, 0.0
    worst = (0.0, None, None)
    for sn in snaps:
        with h5py.File(os.path.join(out, "snapshots", sn), "r") as f:
            t = float(f.attrs["time"])
            kind = f["kind"][:]
            pos, vel = f["position"][:], f["velocity"][:]
        if t <= 0:
            continue
        fl = kind == 0
        z, ux = pos[fl, 2], vel[fl, 0]
        uz_max = max(uz_max, float(np.max(np.abs(vel[fl, 2]))))
        row = np.round(z / dx - 0.5).astype(int)
        rows = np.unique(row)
        counts = np.array([np.sum(row == r) for r in rows])
        if len(rows) != n_rows or counts.min() != counts.max():
            row_counts_bad += 1
        zm = np.array([z[row == r].mean() for r in rows])
        um = np.array([ux[row == r].mean() for r in rows])
        e = np.abs(um - u_exact(zm, t)) / U_C
        i = int(np.argmax(e))
        if e[i] > worst[0]:
            worst = (float(e[i]), t, float(zm[i]))
        times.append(t)
        err_t.append(float(e.max()))
        profiles[t] = (zm, um)
    return {"times": np.array(times), "err_t": np.array(err_t), "err": worst[0], "worst_t": worst[1],
            "worst_z": worst[2], "profiles": profiles, "row_counts_bad": row_counts_bad, "uz_max": uz_max,
            "n_snap": len(times)}


def gauge_error(out):
    g = read_csv(os.path.join(out, "gauges", "profile.csv"))
    pts = read_csv(os.path.join(out, "gauges", "profile.points.csv"))
    z = pts["z"]
    interior = (z > 1e-12) & (z < H - 1e-12)
    n_nan, e_int, e_all = 0, 0.0, 0.0
    for k, t in enumerate(g["time"]):
        if t <= 0:
            continue
        u = np.array([g[f"ux_{i}"][k] for i in range(len(z))])
        n_nan += int(np.sum(~np.isfinite(u)))
        e = np.abs(u - u_exact(z, t)) / U_C
        e_int = max(e_int, float(np.nanmax(e[interior])))
        e_all = max(e_all, float(np.nanmax(e)))
    return e_int, e_all, n_nan, g, z


def main():
    a = validation_args(NAME, __doc__, MODES)
    m = MODES[a.mode]
    os.makedirs(a.out, exist_ok=True)
    failed, run_failed = [], False

    def metric(name, value, ok, threshold, source):
        print(f"[{'PASS' if ok else 'FAIL'}] {name} = {value}   (threshold: {threshold}; source: {source})")
        if not ok:
            failed.append(name)

    res, walls = {}, {}
    for n, dx in RES.items():
        out = os.path.join(a.out, f"dx{dx:g}")
        s, wall, rc = run_case(a.sphflume, CASE, out, {"particles.dx": dx, "time.end": m["end"], **parse_sets(a.set)}, a.threads, a.reuse)
        walls[n] = wall
        if s is None:
            print(f"[FAIL] run H/dx = {n} exit code = {rc}   (threshold: 0)")
            run_failed = True
            continue
        r = analyse_run(out, dx)
        r["gauge_int"], r["gauge_all"], r["gauge_nan"], r["gauge"], r["gauge_z"] = gauge_error(out)
        r["summary"] = s
        res[n] = r
        print(f"\n== {NAME} H/dx = {n} (dx = {dx:g} m, {s['particles']['fluid']} fluid particles, {s['steps']} steps; "
              f"run wall time {wall:.1f} s)")
        print(f"  row-averaged error max over {r['n_snap']} times: {100 * r['err']:.3f} % of u_c "
              f"(worst at t = {r['worst_t']:.3f} s, z/H = {r['worst_z'] / H:.3f}); at the end: {100 * r['err_t'][-1]:.3f} %")
        print(f"  lattice rows intact: {'yes' if r['row_counts_bad'] == 0 else 'NO in %d snapshots' % r['row_counts_bad']}; "
              f"max |u_z| = {r['uz_max']:.2e} m/s ({100 * r['uz_max'] / U_C:.3f} % of u_c)")
        zm, um = r["profiles"][r["times"][-1]]
        ue = u_exact(zm, r["times"][-1])
        ic, iw = int(np.argmax(ue)), 0
        print(f"  (info) signed error at t = {r['times'][-1]:.3g} s: centre row {100 * (um[ic] - ue[ic]) / U_C:+.3f} %, "
              f"row next to the wall {100 * (um[iw] - ue[iw]) / U_C:+.3f} % of u_c")
        print(f"  (info) gauge profile cross-check: max error interior points {100 * r['gauge_int']:.3f} %, "
              f"with the wall points {100 * r['gauge_all']:.3f} % of u_c; NaN values: {r['gauge_nan']}")
        if r["row_counts_bad"]:
            metric(f"H/dx = {n}: rows keep their particles", r["row_counts_bad"], False, "0 snapshots with mixed rows",
                   "metric definition (row binning)")

    print(f"\n== {NAME} {a.mode} (t_end = {m['end']} s): metrics")
    src = "Morris, Fox & Zhu (1997) series solution; issue thresholds"
    if 40 in res:
        metric("error at H/dx = 40 (max over rows and times, / u_c)", f"{100 * res[40]['err']:.3f} %",
               res[40]["err"] <= E_TOL, f"<= {100 * E_TOL:g} %", src)
    for n0, n1 in ((20, 40), (40, 80)):
        if n0 in res and n1 in res:
            p = math.log2(res[n0]["err"] / res[n1]["err"]) if res[n1]["err"] > 0 else float("inf")
            metric(f"observed order log2(e{n0}/e{n1})", f"{p:.3f}", p >= ORDER_MIN, f">= {ORDER_MIN:g}", src)
    if res:
        hdx = next(iter(res.values()))["summary"]["h"] / next(iter(res.values()))["summary"]["dx"]
        mom = lattice_laplacian_moment(hdx)
        print(f"  (info) lattice moment of the viscous operator at h/dx = {hdx:.3g} (Wendland C2, eta2 -> 0): {mom:.5f}; "
              f"at a fixed h/dx this is an error floor of about {100 * (1 / mom - 1):.2f} % of u_c at steady state")
    print("  errors: " + ", ".join(f"H/dx = {n}: {100 * r['err']:.3f} %" for n, r in res.items()))
    print("run wall times: " + ", ".join(f"H/dx = {n}: {w:.1f} s" for n, w in walls.items()))

    # plot
    fig, ax = plt.subplots(1, 2, figsize=(12, 5))
    zz = np.linspace(0, H, 201)
    if res:
        ref = 40 if 40 in res else max(res)
        all_t = sorted(res[ref]["profiles"])
        show = [t for t in all_t if any(abs(t - w) < 1e-9 for w in (0.025, 0.05, 0.1, 0.2))] + [all_t[-1]]
        mks = {20: "s", 40: "o", 80: "."}
        for j, t in enumerate(show):
            c = f"C{j}"
            ax[0].plot(u_exact(zz, t) / U_C, zz / H, "-", color=c, lw=1, label=f"exact, t = {t:g} s")
            for n, r in res.items():
                tk = min(r["profiles"], key=lambda x: abs(x - t))
                zm, um = r["profiles"][tk]
                ax[0].plot(um / U_C, zm / H, mks[n], color=c, ms=4 if n != 80 else 3, mfc="none" if n != 80 else c,
                           label=f"SPH H/dx = {n}" if j == 0 else None)
        ax[0].set_xlabel("u_x / u_c (row averages)")
        ax[0].set_ylabel("z / H")
        ax[0].set_title("start-up Poiseuille flow: profiles")
        ax[0].legend(fontsize=7)
        ns = np.array(sorted(res))
        dxs = np.array([RES[n] for n in ns])
        es = np.array([res[n]["err"] for n in ns])
        ax[1].loglog(dxs, 100 * es, "o-", label="max row error (particles)")
        ax[1].loglog(dxs, [100 * res[n]["gauge_int"] for n in ns], "s--", mfc="none", label="gauge profile (interior)")
        ax[1].loglog(dxs, 100 * es[0] * (dxs / dxs[0]), "k:", label="first order")
        ax[1].loglog(dxs, 100 * es[0] * (dxs / dxs[0]) ** 2, "k-.", lw=0.8, label="second order")
        ax[1].axhline(100 * E_TOL, color="r", lw=0.8, label="2 % (threshold at H/dx = 40)")
        ax[1].set_xlabel("dx (m)")
        ax[1].set_ylabel("max |u - u_exact| / u_c (%)")
        ax[1].set_title(f"error vs resolution (t <= {m['end']} s)")
        ax[1].legend(fontsize=8)
    fig.tight_layout()
    save_figure(fig, HERE, NAME, a.mode, a.out)

    if run_failed or failed:
        print(f"\n{NAME} {a.mode}: FAILED: {', '.join(failed + (['a run failed'] if run_failed else []))}")
        return 2 if run_failed else 1
    print(f"\n{NAME} {a.mode}: all metrics pass")
    return 0


if __name__ == "__main__":
    sys.exit(main())
