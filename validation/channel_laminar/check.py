#!/usr/bin/python3
"""Laminar free-surface channel flow with in/out-flow (cases/channel_laminar.yaml; Federico 2010 §7.1).

Depth h = 0.1 m, slope s0 = 0.001, Re = 10; the analytic profile u(z) = (g s0 / (2 nu)) (2 h z - z^2) is imposed
on the inflow and outflow particles (Federico's algorithm) and given to the fluid at t = 0; run to
t sqrt(g/h) = 50. Metrics (issue: open channels, validation 1):
  1. MSEP = (100/N) sum ((u_a - u_n)/u_a)^2 at x = h downstream of the inlet zone (x = 0.12 m) (Federico's eq. 7.3),
     u_n = the mean velocity of the fluid particles of each particle row within 2 dx of x = 0.12 m, averaged over
     the snapshots at t sqrt(g/h) in [40, 50] (the flow is steady; one snapshot alone carries the particle noise,
     whose relative size is largest in the slow rows near the bed), u_a the closed form at the row's mean height;
     rows below z = dx excluded (u_a -> 0 there, and eq. 7.3 divides by it). The instantaneous MSEP at
     t sqrt(g/h) = 50 is printed beside it.
     Fine: <= 2 % at h/dx = 40 (the thesis reports < 3.5 %); coarse (CI, h/dx = 20): <= 4 % (first order: 2x).
  2. fine: observed order of MSEP between h/20 and h/40, log2(MSEP_20 / MSEP_40) >= 1.
  3. mean depth (water-level gauges at x = 0.06, 0.12, 0.18 m, t sqrt(g/h) in [25, 50]) within 1 % of h.
  4. time-averaged volume flux at the outlet (gauge q_out, x = 0.21 m) within 2 % of the inlet's (q_in, x = 0.03 m),
     t sqrt(g/h) in [25, 50]; the flux against the closed form U h is reported.
  5. mass balance initial + inflow - outflow - backflow - removed = final to round-off (1e-12 of the initial mass).
  6. fine: Re = 100 (nu = 1.808e-4, u_s = 0.2713 m/s) runs stably to t sqrt(g/h) = 50 at h/dx = 20 (exit 0).
Usage: /usr/bin/python3 validation/channel_laminar/check.py [--mode coarse|fine] [--sphflume PATH] [--out DIR]
"""
import glob
import math
import os
import sys

import h5py
import numpy as np
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from common import Report, parse_sets, run_case, save_figure, validation_args  # noqa: E402

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
CASE = os.path.normpath(os.path.join(HERE, "..", "..", "cases", "channel_laminar.yaml"))
NAME = "channel_laminar"
G, S0, H = 9.81, 0.001, 0.1
T_STAR = math.sqrt(H / G)  # t sqrt(g/h) = 1
END = 5.05
X_MID = 0.12
MODES = {"coarse": {"res": {"h/20": 0.005}, "tol": {"h/20": 4.0}},
         "fine": {"res": {"h/20": 0.005, "h/40": 0.0025}, "tol": {"h/40": 2.0}}}



def u_exact(z, nu):
    return G * S0 / (2 * nu) * (2 * H * z - z * z)


def profile(out, dx, t_from):
    """Row means of the fluid particles within 2 dx of X_MID, averaged over the snapshots at t >= t_from:
    (z, u). t_from = the last snapshot's time gives the instantaneous profile."""
    acc = {}
    for snap in sorted(glob.glob(os.path.join(out, "snapshots", "snap_*.h5"))):
        with h5py.File(snap, "r") as f:
            if float(f.attrs["time"]) < t_from * (1 - 1e-9):
                continue
            x, u, k = f["position"][:], f["velocity"][:], f["kind"][:]
        sel = (k == 0) & (np.abs(x[:, 0] - X_MID) < 2 * dx)
        z, ux = x[sel, 2], u[sel, 0]
        rows = np.round(z / dx - 0.5).astype(int)
        for r in set(rows.tolist()):
            m = rows == r
            acc.setdefault(r, []).append((z[m].mean(), ux[m].mean()))
    rows = sorted(acc)
    return (np.array([np.mean([a[0] for a in acc[r]]) for r in rows]),
            np.array([np.mean([a[1] for a in acc[r]]) for r in rows]))


def msep(z, u, nu, dx):
    keep = z >= dx
    ua = u_exact(z[keep], nu)
    return 100.0 * np.mean(((ua - u[keep]) / ua) ** 2)


def gauge(out, name):
    return np.genfromtxt(os.path.join(out, "gauges", f"{name}.csv"), delimiter=",", names=True)


def main():
    a = validation_args(NAME, __doc__, MODES)
    rep = Report()
    mode = MODES[a.mode]
    nu = 5.718e-4
    results = {}
    for res, dx in mode["res"].items():
        out = os.path.join(a.out, f"dx{dx}")
        s, wall, rc = run_case(a.sphflume, CASE, out, {"particles.dx": dx, "time.end": END, **parse_sets(a.set)},
                               a.threads, a.reuse)
        print(f"\n== {NAME} {res} (dx = {dx} m)")
        rep.metric(f"{res} exit code", rc, rc == 0, "0", "issue")
        if s is None:
            continue
        z, u = profile(out, dx, END - 10 * T_STAR)
        e = msep(z, u, nu, dx)
        zi, ui = profile(out, dx, s["simulated_time"])
        results[res] = (dx, z, u, e, out)
        if res in mode["tol"]:
            rep.metric(f"{res} MSEP at x = {X_MID} m, profile averaged over t sqrt(g/h) in [40, 50] (%)", f"{e:.3f}", e <= mode["tol"][res], f"<= {mode['tol'][res]}", "issue (thesis: < 3.5 %)" if a.mode == "fine" else "issue, first order 2x")
        else:
            print(f"  (info) {res} MSEP, profile averaged over t sqrt(g/h) in [40, 50] = {e:.3f} %")
        print(f"  (info) {res} MSEP of the instantaneous profile at t sqrt(g/h) = {s['simulated_time'] / T_STAR:.1f}: "
              f"{msep(zi, ui, nu, dx):.3f} %")
        tt = None
        depths = []
        for gname in ["depth_06", "depth_12", "depth_18"]:
            d = gauge(out, gname)
            tt = d["time"] / T_STAR
            depths.append(d["level"][(tt >= 25) & (tt <= 50.5)].mean())
        dmean = float(np.mean(depths))
        rep.metric(f"{res} mean depth (m), x = 0.06/0.12/0.18, t* in [25, 50]", f"{dmean:.5f} ({100 * (dmean - H) / H:+.2f} %; {', '.join(f'{v:.5f}' for v in depths)})", abs(dmean - H) / H <= 0.01, "within 1 % of h = 0.1", "issue")
        qi, qo = gauge(out, "q_in"), gauge(out, "q_out")
        w = (qi["time"] / T_STAR >= 25)
        qin, qout = qi["flux"][w].mean(), qo["flux"][w].mean()
        U = G * S0 * H * H / (3 * nu)
        rep.metric(f"{res} time-averaged outlet flux / inlet flux - 1", f"{100 * (qout / qin - 1):+.3f} % (q_in {qin:.6f}, q_out {qout:.6f} m2/s; closed form U h = {U * H:.6f}: "
               f"{100 * (qin / (U * H) - 1):+.2f} %)", abs(qout - qin) / qin <= 0.02, "within 2 %", "issue")
        m = s["mass"]
        bal = (m["initial"] + m["inflow"] - m["outflow"] - m["backflow"] - m["removed"] - m["final"]) / m["initial"]
        rep.metric(f"{res} mass balance (initial + inflow - outflow - backflow - removed - final) / initial", f"{bal:.1e}", abs(bal) <= 1e-12, "|.| <= 1e-12", "issue (none lost without being counted)")
        print(f"  (info) inflow {m['inflow']:.4f} kg/m, outflow {m['outflow']:.4f} kg/m (ratio {m['outflow'] / m['inflow']:.4f}); "
              f"fluid particles back into the inflow zone (removed): {s['backflow']['particles']}; "
              f"{s['particles']['fluid']} fluid, {s['steps']} steps, {wall:.0f} s wall")
    if "h/20" in results and "h/40" in results:
        order = math.log2(results["h/20"][3] / results["h/40"][3])
        rep.metric("observed order of MSEP, h/20 -> h/40", f"{order:.2f}", order >= 1.0, ">= 1", "issue (thesis: 1.52)")
    if a.mode == "fine":  # Re = 100 at h/20: stability
        out = os.path.join(a.out, "re100")
        s, wall, rc = run_case(a.sphflume, CASE, out, {"particles.dx": 0.005, "time.end": END, "fluid.viscosity": 1.808e-4,
                                                       "open_boundaries.0.profile.u_surface": 0.2713,
                                                       "open_boundaries.1.profile.u_surface": 0.2713}, a.threads, a.reuse)
        rep.metric("Re = 100, h/20: runs to t sqrt(g/h) = 50", f"exit {rc}", rc == 0, "0", "issue")
        if s is not None:
            z, u = profile(out, 0.005, END - 10 * T_STAR)
            print(f"  (info) Re = 100 MSEP = {msep(z, u, 1.808e-4, 0.005):.3f} %")
            results["Re=100 h/20"] = (0.005, z, u, msep(z, u, 1.808e-4, 0.005), out)

    fig, ax = plt.subplots(1, 2, figsize=(11, 4.5))
    zz = np.linspace(0, H, 200)
    ax[0].plot(u_exact(zz, nu), zz, "k-", label="closed form, Re = 10")
    for res, (dx, z, u, e, out) in results.items():
        if res.startswith("Re"):
            continue
        ax[0].plot(u, z, "o", ms=4, label=f"{res}: MSEP {e:.2f} %")
        q = gauge(out, "q_out")
        ax[1].plot(q["time"] / T_STAR, q["flux"], label=f"{res} outlet")
        q = gauge(out, "q_in")
        ax[1].plot(q["time"] / T_STAR, q["flux"], "--", label=f"{res} inlet")
    ax[1].axhline(G * S0 * H ** 3 / (3 * nu), color="k", lw=0.8, label="closed form U h")
    ax[0].set_xlabel("u (m/s)")
    ax[0].set_ylabel("z (m)")
    ax[0].set_title(f"profile at x = {X_MID} m, mean over t sqrt(g/h) in [40, 50]")
    ax[0].legend(fontsize=8)
    ax[1].set_xlabel("t sqrt(g/h)")
    ax[1].set_ylabel("volume flux (m2/s)")
    ax[1].legend(fontsize=8)
    fig.tight_layout()
    save_figure(fig, HERE, NAME, a.mode, a.out)
    rep.finish(NAME, a.mode)


if __name__ == "__main__":
    main()
