#!/usr/bin/python3
"""Open channels in 3D (issue 59, check 6): the inflow and outflow zones, the flux gauges over a section, the
unknown-discharge outlet, in 3D as in 2D.

1. Laminar channel (cases/channel_laminar_3d.yaml; Federico §7.1, Re = 10): the 2D case of
   validation/channel_laminar as a slab 0.08 m wide with periodic sides, the inflow and outflow zones across the
   width; run beside the 2D case at the same dx. Against the 2D run:
     - the velocity profile at x = 0.12 m (gauge u_mid: u Shepard-interpolated at 21 heights, the same points in 2D
       and 3D) averaged over t sqrt(g/h) in [40, 50]: max |u_3D - u_2D| <= 2 % of the surface velocity u_s (fine; the
       MSEP of the row means against the closed form, validation/channel_laminar's measure, is printed);
     - the mean depth (gauges at x = 0.06, 0.12, 0.18 m, from half the window's start) within 2 % of the 2D run's;
     - the time-mean outlet flux q_out (per metre of width at mid-width) within 2 % of the 2D run's;
     - the section discharge (flux gauge over the whole width, `span`) / width within 1 % of the per-metre flux at
       mid-width (a laterally uniform flow: the section integral is consistent);
     - the fluid mass balance to round-off (1e-12).
2. Pollutant release (cases/channel_release_3d.yaml; validation/channel_release; fine mode): the same, 0.06 m wide.
   Against the 2D run at the same dx:
     - the centreline concentration (z = 0.05 m, mid-width) at t = 2, 4, 6 s over x in [x0 + 2 dx, 0.9]:
       max |C_3D - C_2D| <= 0.02 C0;
     - the pollutant budget at t = 6 s between x = 0.05 and 0.9 (E_in, E_out from the section fluxes, S the
       content; 3D divided by the width): E_in and S within 2 % of the 2D run's, and (E_in - E_out - S) / E_in
       within 1 % as in 2D;
     - depth at x = 0.5 m and the water flux at x = 0.05 m (means over t >= 1 s) within 2 % of the 2D run's.
3. Channel with a bridge pier (cases/channel_pier_3d.yaml): no-slip side walls, an STL cylinder pier, an
   imposed inflow (U = 0.2 m/s, h = 0.1 m) and an outflow holding the tailwater level (extrapolated velocity, the
   hydrostatic pressure of a 0.094 m depth: the pier's backwater brings the upstream level to the inflow's 0.1 m).
   Over the balance window (fine: t = 12..22 s, 10 s; coarse: 1..3 s):
     - volume balance: the water in the channel (gauge `water`, sum m/rho of the fluid) against the volumes that
       crossed the zones (gauge `boundaries`, m/rho0): |dV - (V_in - V_out - V_back)| <= 0.5 % of V_in;
     - steady flow (fine; coarse: printed, 1..3 s is still the backwater's settling): the volume leaving over the
       window within 2 % of the volume entering, and the section discharges upstream (x = 0.15 m) and downstream
       (x = 0.6 m) of the pier within 2 % of each other;
     - information: the discharges against U h W, the levels in front of and behind the pier.
Modes: coarse (CTest): laminar at h/10 to t sqrt(g/h) = 10 in 2D and 3D (depth, fluxes, mass; the profile printed),
the pier at dx = 0.02 to 3 s; fine: laminar at h/20 to t sqrt(g/h) = 50, release at dx = 0.01, the pier to 22 s.
Usage: /usr/bin/python3 validation/channel_3d/check.py [--mode coarse|fine] [--sphflume PATH] [--out DIR]
       [--threads N] [--reuse] [--only laminar,release,pier]
"""
import importlib.util
import os
import sys

import numpy as np
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from common import Report, info, read_rows, run_case, save_figure, validation_args  # noqa: E402

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
CASES = os.path.normpath(os.path.join(HERE, "..", "..", "cases"))
NAME = "channel_3d"
SRC = "issue 59 check 6"


def load(name):
    """The 2D check's module (its readers and reference formulas)."""
    path = os.path.join(HERE, "..", name, "check.py")
    spec = importlib.util.spec_from_file_location(f"{name}_check", path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


LAM = load("channel_laminar")
REL = load("channel_release")
# (laminar dx, release dx, pier dx, pier end, pier window)
# laminar: dx, end (s), the window in t sqrt(g/h), the profile's tolerance (of u_s; None: information). Coarse: h/10 to
# t sqrt(g/h) = 10, still in the start-up transient, which h/10 resolves differently in 2D and 3D (13 % of u_s apart over [15, 20] at
# z = 0.07 m; the 2D run itself is 6 % off the closed form when steady, validation/channel_laminar): depth, fluxes and the
# mass balance are gated there, the profile in fine mode. rel: the release's dx (None: not run; its 3D run at dx = 0.01
# takes ~25 min on one core, the 2D check's coarse dx 0.005 some 4 h). pier: dx 0.02 (h/5; the pier, 0.08 m, 4 dx across),
# fine to 22 s with the balance over the last 10 s (the backwater takes ~12 s to settle), coarse to 3 s.
MODES = {"coarse": {"lam": 0.01, "lam_end": 1.01, "lam_window": (5.0, 10.0), "lam_tol": None,
                    "rel": None, "pier": 0.02, "pier_end": 3.0, "window": (1.0, 3.0)},
         "fine": {"lam": 0.005, "lam_end": 5.05, "lam_window": (40.0, 50.0), "lam_tol": 0.02,
                  "rel": 0.01, "pier": 0.02, "pier_end": 22.0, "window": (12.0, 22.0)}}
W_LAM, W_REL = 0.08, 0.06       # the slabs' widths (cases/channel_*_3d.yaml)
PIER_U, PIER_H, PIER_W = 0.2, 0.1, 0.2


def rows(out, name):
    hdr, r = read_rows(os.path.join(out, "gauges", f"{name}.csv"))
    return {k: r[:, i] for i, k in enumerate(hdr)}


def run_pair(a, rep, label, case2, case3, dx, end):
    """Runs the 2D and the 3D case at dx; returns their output folders (None where a run failed)."""
    outs = []
    for dim, case in (("2D", case2), ("3D", case3)):
        out = os.path.join(a.out, f"{label}_{dim}_dx{dx:g}")
        s, wall, rc = run_case(a.sphflume, case, out, {"particles.dx": dx, "time.end": end}, a.threads, a.reuse)
        rep.metric(f"{label} {dim} exit code", rc, rc == 0, "0", SRC)
        if s is not None:
            print(f"  ({dim}: {s['particles']['total']} particles, {s['steps']} steps, {wall:.0f} s wall)")
            if dim == "3D":
                m = s["mass"]
                bal = (m["initial"] + m["inflow"] - m["outflow"] - m["backflow"] - m["removed"] - m["final"]) / m["initial"]
                rep.metric(f"{label} 3D mass balance (initial + in - out - back - removed - final) / initial", f"{bal:.1e}",
                           abs(bal) <= 1e-12, "|.| <= 1e-12", SRC)
        outs.append(out if s is not None else None)
    return outs


def laminar(a, rep, m, figs):
    dx = m["lam"]
    print(f"\n== laminar channel, 2D and 3D at dx = {dx} (h/{LAM.H / dx:.0f})")
    o2, o3 = run_pair(a, rep, "laminar", LAM.CASE, os.path.join(CASES, "channel_laminar_3d.yaml"), dx, m["lam_end"])
    if not (o2 and o3):
        return
    nu, us = 5.718e-4, 0.08579
    t0, t1 = m["lam_window"]

    def gauge_profile(out):
        """The u_mid gauge (Shepard-interpolated u at 21 fixed heights, the same points in 2D and 3D), its
        time mean over the window."""
        hdr, r = read_rows(os.path.join(out, "gauges", "u_mid.csv"))
        cols = [i for i, k in enumerate(hdr) if k.startswith("ux_")]
        tt = r[:, 0] / LAM.T_STAR
        return r[(tt >= t0 - 1e-6) & (tt <= t1 + 1e-6)][:, cols].mean(axis=0)
    g2, g3 = gauge_profile(o2), gauge_profile(o3)
    zg = np.linspace(0.0, LAM.H, len(g2))
    d = np.abs(g3 - g2)
    i = int(np.argmax(d))
    name = f"laminar: max |u_3D - u_2D| on the profile gauge at x = 0.12 m, mean over t sqrt(g/h) in [{t0:g}, {t1:g}], / u_s"
    if m["lam_tol"] is None:  # coarse: the start-up transient at h/10 (information)
        info(name, f"{100 * d[i] / us:.2f} % (at z = {zg[i]:.3f} m)", True, "-", "information (h/10, transient)")
    else:
        rep.metric(name, f"{100 * d[i] / us:.2f} % (at z = {zg[i]:.3f} m)", d[i] <= m["lam_tol"] * us, f"<= {100 * m['lam_tol']:g} % of u_s", SRC)
    (z2, u2), (z3, u3) = LAM.profile(o2, dx, t0 * LAM.T_STAR), LAM.profile(o3, dx, t0 * LAM.T_STAR)
    info("laminar: MSEP of the row means against the closed form (validation/channel_laminar's measure)",
         f"2D {LAM.msep(z2, u2, nu, dx):.3f} %, 3D {LAM.msep(z3, u3, nu, dx):.3f} %", True, "-", "information")

    def depth(out):
        vals = []
        for g in ("depth_06", "depth_12", "depth_18"):
            r = rows(out, g)
            tt = r["time"] / LAM.T_STAR
            vals.append(r["level"][(tt >= t0 / 2) & (tt <= t1 + 0.5)].mean())
        return float(np.mean(vals))
    h2, h3 = depth(o2), depth(o3)
    rep.metric("laminar: mean depth 3D / 2D - 1", f"{100 * (h3 / h2 - 1):+.3f} % ({h3:.5f} vs {h2:.5f} m)",
               abs(h3 / h2 - 1) <= 0.02, "within 2 %", SRC)

    def mean_flux(out, g):
        r = rows(out, g)
        return r["flux"][r["time"] / LAM.T_STAR >= t0 / 2].mean()
    q2, q3 = mean_flux(o2, "q_out"), mean_flux(o3, "q_out")
    rep.metric("laminar: outlet flux (per metre, mid-width) 3D / 2D - 1", f"{100 * (q3 / q2 - 1):+.3f} % ({q3:.6f} vs {q2:.6f} m2/s)",
               abs(q3 / q2 - 1) <= 0.02, "within 2 %", SRC)
    qs, qm = mean_flux(o3, "q_in_section") / W_LAM, mean_flux(o3, "q_in")
    rep.metric("laminar: section discharge / width against the flux per metre at mid-width (x = 0.03 m)",
               f"{100 * (qs / qm - 1):+.3f} % ({qs:.6f} vs {qm:.6f} m2/s)", abs(qs / qm - 1) <= 0.01, "within 1 %", SRC)
    figs["laminar"] = (zg, g2, g3, dx, (t0, t1))


def release(a, rep, dx, figs):
    print(f"\n== pollutant release, 2D and 3D at dx = {dx}")
    o2, o3 = run_pair(a, rep, "release", REL.CASE, os.path.join(CASES, "channel_release_3d.yaml"), dx, REL.END)
    if not (o2 and o3):
        return
    g2, g3 = REL.read_gauges(o2), REL.read_gauges(o3)
    xg = g2[1][:, 1]
    if not np.allclose(xg, g3[1][:, 1]):
        raise SystemExit("c_centre: the 2D and 3D gauges' points differ")
    sel = (xg >= REL.X0 + 2 * dx - 1e-9) & (xg <= REL.X_OUT + 1e-9)
    prof = {}
    for tc in REL.CHECK_TIMES:
        c2 = g2[0][REL.row_at(g2[0], tc), 1:]
        c3 = g3[0][REL.row_at(g3[0], tc), 1:]
        e = np.abs(c3 - c2)[sel]
        i = int(np.argmax(e))
        rep.metric(f"release: t = {tc:g} s, max |C_3D - C_2D| on the centreline", f"{e[i]:.4f} C0 (at x = {xg[sel][i]:.3f} m)",
                   e[i] <= 0.02 * REL.C0, "<= 0.02 C0", SRC)
        prof[tc] = (c2, c3)

    def budget(g, width):
        fin, fout, box = g[2], g[3], g[4]
        t = fin[:, 0]
        e_in, e_out = REL.cumtrapz(t, fin[:, 1])[-1] / width, REL.cumtrapz(t, fout[:, 1])[-1] / width
        return e_in, e_out, box[-1, 1] / width
    (i2, x2, s2), (i3, x3, s3) = budget(g2, 1.0), budget(g3, W_REL)
    rep.metric(f"release: E_in (t = {REL.END:g} s) 3D / 2D - 1", f"{100 * (i3 / i2 - 1):+.3f} % ({i3:.6e} vs {i2:.6e} kg/m)",
               abs(i3 / i2 - 1) <= 0.02, "within 2 %", SRC)
    rep.metric("release: content S between the sections, 3D / 2D - 1", f"{100 * (s3 / s2 - 1):+.3f} % ({s3:.6e} vs {s2:.6e} kg/m)",
               abs(s3 / s2 - 1) <= 0.02, "within 2 %", SRC)
    rel = (i3 - x3 - s3) / i3
    rep.metric("release: 3D budget (E_in - E_out - S) / E_in", f"{100 * rel:+.3f} % (2D: {100 * (i2 - x2 - s2) / i2:+.3f} %)",
               abs(rel) <= 0.01, "|.| <= 1 % (as in 2D)", SRC)
    for k, lab, col in ((5, "water flux at x = 0.05 m", 1), (6, "depth at x = 0.5 m", 1)):
        v2 = g2[k][g2[k][:, 0] >= REL.MEAN_FROM, col].mean()
        v3 = g3[k][g3[k][:, 0] >= REL.MEAN_FROM, col].mean()
        rep.metric(f"release: {lab}, mean over t >= {REL.MEAN_FROM:g} s, 3D / 2D - 1", f"{100 * (v3 / v2 - 1):+.3f} % ({v3:.6f} vs {v2:.6f})",
                   abs(v3 / v2 - 1) <= 0.02, "within 2 %", SRC)
    figs["release"] = (xg, prof)


def pier(a, rep, m, figs):
    dx, end, (t0, t1) = m["pier"], m["pier_end"], m["window"]
    print(f"\n== channel with a bridge pier, 3D at dx = {dx} to t = {end:g} s (balance over t = {t0:g}..{t1:g} s)")
    out = os.path.join(a.out, f"pier_dx{dx:g}")
    s, wall, rc = run_case(a.sphflume, os.path.join(CASES, "channel_pier_3d.yaml"), out,
                           {"particles.dx": dx, "time.end": end}, a.threads, a.reuse)
    rep.metric("pier: exit code", rc, rc == 0, "0", SRC)
    if s is None:
        return
    print(f"  ({s['particles']['total']} particles, {s['steps']} steps, {wall:.0f} s wall)")
    w, b = rows(out, "water"), rows(out, "boundaries")
    t = w["time"]
    i0, i1 = int(np.argmin(np.abs(t - t0))), int(np.argmin(np.abs(t - t1)))
    dv = w["water"][i1] - w["water"][i0]
    vin = b["inflow"][i1] - b["inflow"][i0]
    vout = b["outflow"][i1] - b["outflow"][i0]
    vback = b["backflow"][i1] - b["backflow"][i0]
    err = (dv - (vin - vout - vback)) / vin
    rep.metric(f"pier: volume balance over t = {t[i0]:g}..{t[i1]:g} s, (dV - (V_in - V_out - V_back)) / V_in",
               f"{100 * err:+.3f} % (dV {dv:+.3e}, V_in {vin:.4e}, V_out {vout:.4e}, V_back {vback:.1e} m3)",
               abs(err) <= 0.005, "|.| <= 0.5 %", SRC)
    name = "pier: steady flow, V_out / V_in - 1 over the window"
    if a.mode == "fine":
        rep.metric(name, f"{100 * (vout / vin - 1):+.3f} %", abs(vout / vin - 1) <= 0.02, "within 2 %", SRC)
    else:  # coarse: 1..3 s is still the backwater's filling (dV / V_in printed above)
        info(name, f"{100 * (vout / vin - 1):+.3f} %", abs(vout / vin - 1) <= 0.02, "within 2 % (fine mode)", "information")
    qu, qd = rows(out, "q_up"), rows(out, "q_down")
    win = (qu["time"] >= t0 - 1e-9) & (qu["time"] <= t1 + 1e-9)
    mu, md = qu["flux"][win].mean(), qd["flux"][win].mean()
    q0 = PIER_U * PIER_H * PIER_W
    name = "pier: section discharge downstream / upstream of the pier - 1"
    value = f"{100 * (md / mu - 1):+.3f} % (up {mu:.5f}, down {md:.5f} m3/s; U h W = {q0:.5f}: {100 * (mu / q0 - 1):+.2f} %)"
    if a.mode == "fine":
        rep.metric(name, value, abs(md / mu - 1) <= 0.02, "within 2 %", SRC)
    else:  # coarse: the backwater still settling between the sections (+1.8 % over 1..3 s, +3.1 % over 1..2 s)
        info(name, value, abs(md / mu - 1) <= 0.02, "within 2 % (fine mode)", "information")
    levels = {g: rows(out, g) for g in ("level_up", "level_front", "level_wake", "level_down")}
    info("pier: mean levels over the window (m)", ", ".join(f"{g} {r['level'][win].mean():.4f}" for g, r in levels.items()),
         True, "-", "information")
    figs["pier"] = (t, w["water"], b, qu, qd, levels, (t0, t1))


def figure(figs, a):
    fig, ax = plt.subplots(1, 3, figsize=(15, 4.5))
    if "laminar" in figs:
        zg, g2, g3, dx, (t0, t1) = figs["laminar"]
        zz = np.linspace(0, LAM.H, 100)
        ax[0].plot(LAM.u_exact(zz, 5.718e-4), zz, "k-", lw=0.8, label="closed form (steady)")
        ax[0].plot(g2, zg, "o", ms=5, mfc="none", label=f"2D, dx = {dx:g}")
        ax[0].plot(g3, zg, "x", ms=5, label="3D slab, periodic sides")
        ax[0].set(xlabel="u (m/s)", ylabel="z (m)", title=f"laminar channel: x = 0.12 m, t sqrt(g/h) in [{t0:g}, {t1:g}]")
        ax[0].legend(fontsize=8)
    if "release" in figs:
        xg, prof = figs["release"]
        for tc, (c2, c3) in prof.items():
            ln, = ax[1].plot(xg, c2, "-", label=f"2D t = {tc:g} s")
            ax[1].plot(xg, c3, "--", color=ln.get_color(), label=f"3D t = {tc:g} s")
        ax[1].set(xlabel="x (m)", ylabel="C / C0", title="pollutant release: centreline")
        ax[1].legend(fontsize=7)
    if "pier" in figs:
        t, wv, b, qu, qd, levels, (t0, t1) = figs["pier"]
        ax[2].plot(qu["time"], qu["flux"], label="discharge x = 0.15 m (upstream)")
        ax[2].plot(qd["time"], qd["flux"], label="discharge x = 0.6 m (downstream)")
        ax[2].axhline(PIER_U * PIER_H * PIER_W, color="k", lw=0.8, label="U h W")
        ax[2].axvspan(t0, t1, color="0.9")
        ax[2].set(xlabel="t (s)", ylabel="Q (m3/s)", title="channel with a pier")
        ax[2].legend(fontsize=7)
    fig.tight_layout()
    save_figure(fig, HERE, NAME, a.mode, a.out)


def main():
    a = validation_args(NAME, __doc__, MODES, extra=lambda ap: ap.add_argument(
        "--only", default="laminar,release,pier", help="comma-separated parts to run"))
    m = MODES[a.mode]
    os.makedirs(a.out, exist_ok=True)
    rep, figs = Report(), {}
    parts = a.only.split(",")
    if "laminar" in parts:
        laminar(a, rep, m, figs)
    if "release" in parts and m["rel"]:
        release(a, rep, m["rel"], figs)
    if "pier" in parts:
        pier(a, rep, m, figs)
    figure(figs, a)
    rep.finish(NAME, a.mode)


if __name__ == "__main__":
    main()
