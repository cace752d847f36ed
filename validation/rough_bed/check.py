#!/usr/bin/python3
"""Turbulent uniform flow over a rough bed (Kazemi ch. 3, Table 3-1; issue: open channels, validations 3 and 4).

Every flow: bed of spheres d_s = 24 mm as Kazemi's drag layer (thickness R_d from his fitted law, C_d = 1),
MSPH-ML mixing-length turbulence (Nezu-Rodi, kappa = 0.41, l_m from the numerical bed to the local surface),
fluid depth H + R_d above the numerical bed (H: Table 3-1's depth, read as above the crest; flows.py says why).
Two runs per flow: the in/out-flow channel of the thesis (Kazemi's unknown-discharge inflow: inflow particles take
the fluid's kernel-averaged velocity and density 0.5 dx inside; zero-gradient outlet), and the same channel
periodic along x (the developed flow, reference for validation 4). validation/rough_bed/flows.py writes the case
files and states the numerical settings; model_1d.py solves the same model as a 1D ODE (the uniform-flow answer of
the model itself, independent of SPH).
Metrics (time means over the window):
  1. [issue, validation 3] U = mean velocity over the depth H above the crest (mid-channel profile), in/out run,
     within 5 % of the measured U = Fr sqrt(g H) of Table 3-1;
  2. [issue, validation 3] depth uniform: (max - min) / mean of the depth at 9 stations (0.1-0.9 L) <= 2 %;
  3. [issue, validation 3] |V_out - V_in| / V_in < 0.5 % in every 1 s interval of the window (Kazemi's eq 3.19;
     V = mass / rho0 of the particles converted at the two lines);
  4. [issue, validation 4] in/out profile vs periodic profile at mid-channel: RMS difference over the depth
     / periodic depth-mean velocity <= 2 %;
  5. [verification, reported] periodic U vs the 1D ODE of the same model (discretisation error at H/dx = 20);
  6. steadiness: the flux averaged over the two halves of the window differs by < 2 % (Kazemi's criterion).
  --set sps=1 also runs S004H50 with SPS-Smagorinsky (C_s = 0.15), in/out, and reports its discharge against
  MSPH-ML's (the thesis: SPS overestimates it).
Draws rough_bed.png: simulated (in/out and periodic) and ODE U against measured U, and the S004H50 profiles.
Usage: /usr/bin/python3 validation/rough_bed/check.py [--mode coarse|fine] [--jobs 2] [--set flows=S004H50,...]
"""
import concurrent.futures as cf
import csv
import math
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, ".."))
sys.path.insert(0, HERE)
from common import Report, run_case, validation_args  # noqa: E402
import flows  # noqa: E402
import model_1d  # noqa: E402

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

NAME = "rough_bed"
MODES = {
    # coarse (CI): S004H50 at H/dx = 10 for 12 s, in/out, periodic and periodic SPS. Gated: the runs complete,
    # mass is conserved exactly, and SPS gives a discharge more than 10 % above MSPH-ML's (the thesis's finding,
    # robust: a factor ~2 at 30 s); the metrics, which the fine runs do not meet yet, are printed as (info)
    "coarse": {"flows": ["S004H50"], "dx_per_h": 10, "t_end": 12.0, "window": (6.0, 12.0), "coarse": True},
    "fine": {"flows": [r[1] for r in flows.TABLE], "dx_per_h": 20, "t_end": 30.0, "window": (20.0, 30.0),
             "coarse": False},
}


def read_csv(path):
    with open(path) as f:
        rows = list(csv.reader(f))
    return rows[0], np.array([[float(v) for v in r] for r in rows[1:]])


def window_mean(data, t0, t1):
    m = (data[:, 0] >= t0 - 1e-9) & (data[:, 0] <= t1 + 1e-9)
    return np.nanmean(data[m, 1:], axis=0)


def mean_profile(out, gauge, t0, t1):
    _, d = read_csv(os.path.join(out, "gauges", gauge + ".csv"))
    _, pts = read_csv(os.path.join(out, "gauges", gauge + ".points.csv"))
    return pts[:, 3], window_mean(d, t0, t1)[0::2]  # points: index, x, y, z


def u_above(z, u, z0, z1):
    """Mean of u over [z0, z1] from profile points (trapezoids; NaN points, above the surface, dropped)."""
    m = np.isfinite(u) & (z >= z0 - 1e-12) & (z <= z1 + 1e-12)
    return float(np.trapz(u[m], z[m]) / (z[m][-1] - z[m][0]))


def ode(fid):
    _, _, s0, h, _, _ = flows.flow(fid)
    rd = flows.rd_over_h(h) * h
    zs, uu = model_1d.solve(h + rd, s0, rd)
    return model_1d.depth_mean(zs, uu, rd, h + rd), (zs, uu)


def gate(rep, coarse, name, value, ok, threshold, source):
    """A metric: gated in fine mode; in coarse mode printed as information (see MODES)."""
    if coarse:
        print(f"(info) [{'pass' if ok else 'fail'}] {name} = {value}   (fine threshold: {threshold}; source: {source})")
    else:
        rep.metric(name, value, ok, threshold, source)


def one_run(sphflume, out_root, fid, cfg, kind, threads, reuse):
    tag = f"{fid}_{kind}"
    out = os.path.join(out_root, tag)
    case = os.path.join(out_root, tag + ".yaml")
    with open(case, "w") as f:
        f.write(flows.case_yaml(fid, cfg["dx_per_h"], cfg["t_end"], periodic=kind in ("periodic", "sps"),
                                turbulence="smagorinsky" if kind == "sps" else "mixing_length"))
    h = flows.flow(fid)[3]
    s, wall, rc = run_case(sphflume, case, out, {"particles.dx": h / cfg["dx_per_h"], "time.end": cfg["t_end"]},
                           threads, reuse)
    return tag, out, s, rc


def main():
    a = validation_args(NAME, __doc__, MODES)
    cfg = dict(MODES[a.mode])
    sets = dict(kv.split("=", 1) for kv in a.set)
    sel = sets["flows"].split(",") if "flows" in sets else cfg["flows"]
    jobs = int(sets.get("jobs", "2"))
    runs = [(fid, k) for fid in sel for k in ("inout", "periodic")]
    if sets.get("sps") or cfg["coarse"]:
        runs.append(("S004H50", "sps"))
    os.makedirs(a.out, exist_ok=True)
    threads = max(1, a.threads // jobs)
    with cf.ThreadPoolExecutor(max_workers=jobs) as ex:
        done = list(ex.map(lambda r: one_run(a.sphflume, a.out, r[0], cfg, r[1], threads, a.reuse), runs))
    res = {tag: (out, s, rc) for tag, out, s, rc in done}
    rep = Report()
    t0, t1 = cfg["window"]
    table = []
    for fid in sel:
        _, _, s0, h, fr, _ = flows.flow(fid)
        rd = flows.rd_over_h(h) * h
        um = flows.measured_u(fr, h)
        u_ode, _ = ode(fid)
        row = {"id": fid, "u_meas": um, "u_ode": u_ode}
        for kind in ("inout", "periodic"):
            out, s, rc = res[f"{fid}_{kind}"]
            rep.metric(f"{fid} {kind} run completes", f"exit {rc}", rc == 0, "exit 0", "robustness")
            if rc != 0:
                continue
            # round-off of the cumulative inflow/outflow sums: 1e-12 of the mass that went through the boundaries
            mb = s["mass"]
            tol = 1e-12 * max(1.0, (mb["inflow"] + mb["outflow"]) / mb["initial"])
            rep.metric(f"{fid} {kind} mass balance", f"{mb['relative_error']:.1e}", abs(mb["relative_error"]) < tol,
                       f"< {tol:.1e} (1e-12 x max(1, (inflow + outflow) / initial))", "conservation")
            z, u = mean_profile(out, "u_above", t0, t1)
            row[kind] = u_above(z, u, rd, h + rd)
            row[kind + "_profile"] = mean_profile(out, "u_50", t0, t1)
            row[kind + "_dir"] = out
            _, q = read_csv(os.path.join(out, "gauges", "q_mid.csv"))
            qa, qb = window_mean(q, t0, 0.5 * (t0 + t1))[0], window_mean(q, 0.5 * (t0 + t1), t1)[0]
            row[kind + "_q"] = 0.5 * (qa + qb)
            st = abs(qb - qa) / qa
            gate(rep, cfg["coarse"], f"{fid} {kind} steadiness (mid flux, two halves of the window)", f"{100 * st:.2f} %",
                 st < 0.02, "< 2 %", "Kazemi §3.2.2")
        if "inout" not in row or "periodic" not in row:
            continue
        err = row["inout"] / um - 1
        gate(rep, cfg["coarse"], f"{fid} U above the crest (in/out) vs measured {um:.3f} m/s", f"{row['inout']:.4f} ({100 * err:+.1f} %)",
             abs(err) <= 0.05, "|error| <= 5 %", "Kazemi Table 3-1; issue validation 3")
        out = res[f"{fid}_inout"][0]
        _, dep = read_csv(os.path.join(out, "gauges", "depth.csv"))
        dm = window_mean(dep, t0, t1)
        unif = (dm.max() - dm.min()) / dm.mean()
        gate(rep, cfg["coarse"], f"{fid} depth non-uniformity (in/out, 9 stations)", f"{100 * unif:.2f} % (mean {1000 * dm.mean():.1f} mm, "
             f"H + R_d = {1000 * (h + rd):.1f} mm)", unif <= 0.02, "<= 2 %", "issue validation 3")
        _, bv = read_csv(os.path.join(out, "gauges", "volumes.csv"))
        worst = 0.0
        for ta in np.arange(t0, t1 - 1.0 + 1e-9, 1.0):
            ia, ib = np.argmin(np.abs(bv[:, 0] - ta)), np.argmin(np.abs(bv[:, 0] - ta - 1.0))
            vin, vout = bv[ib, 1] - bv[ia, 1], bv[ib, 2] - bv[ia, 2]
            worst = max(worst, abs(vout - vin) / vin)
        gate(rep, cfg["coarse"], f"{fid} worst |V_out - V_in| / V_in per 1 s (in/out)", f"{100 * worst:.2f} %",
             worst < 0.005, "< 0.5 %", "Kazemi eq 3.19")
        (zi, ui), (zp, up) = row["inout_profile"], row["periodic_profile"]
        m = np.isfinite(ui) & np.isfinite(up)
        rms = float(np.sqrt(np.mean((ui[m] - up[m]) ** 2)) / np.mean(up[m]))
        gate(rep, cfg["coarse"], f"{fid} in/out vs periodic profile (RMS / periodic mean)", f"{100 * rms:.2f} %", rms <= 0.02,
             "<= 2 %", "issue validation 4")
        ev = row["periodic"] / u_ode - 1
        print(f"(info) {fid} periodic U vs the 1D model's {u_ode:.4f} = {row['periodic']:.4f} ({100 * ev:+.1f} %)   "
              "(verification of the SPH discretisation at this H/dx: model_1d.py)")
        print(f"(info) {fid} periodic U vs measured {um:.4f} = {100 * (row['periodic'] / um - 1):+.1f} %")
        row["meas_err_periodic"] = row["periodic"] / um - 1
        table.append(row)
    if "S004H50_sps" in res:
        out, s, rc = res["S004H50_sps"]
        rep.metric("S004H50 SPS (periodic) run completes", f"exit {rc}", rc == 0, "exit 0", "robustness")
        if rc == 0 and any(r["id"] == "S004H50" for r in table):
            _, q = read_csv(os.path.join(out, "gauges", "q_mid.csv"))
            qs = window_mean(q, t0, t1)[0]
            ml = next(r for r in table if r["id"] == "S004H50")["periodic_q"]
            rep.metric("S004H50 SPS-Smagorinsky (C_s 0.15) / MSPH-ML discharge (periodic)", f"{qs / ml:.3f} ({qs:.5f} vs {ml:.5f} m2/s)",
                       qs / ml > 1.10, "> 1.10 (digest B4)", "Kazemi §3.3: SPS overestimates the discharge")
    print("\n  flow       U meas   in/out   periodic  1D model   (m/s, above the crest)")
    for r in table:
        print(f"  {r['id']:9s} {r['u_meas']:.3f}   {r['inout']:.3f}    {r['periodic']:.3f}     {r['u_ode']:.3f}")
    if table:  # the fine figure goes next to this script, the coarse one into --out
        plot(table, cfg, a.out if cfg["coarse"] else HERE)
    rep.finish(NAME, a.mode)


def plot(table, cfg, folder):
    fig, ax = plt.subplots(1, 3, figsize=(15, 4.5))
    um = np.array([r["u_meas"] for r in table])
    ax[0].plot(um, [r["inout"] for r in table], "o", label="SPH, in/out (Kazemi inflow)")
    ax[0].plot(um, [r["periodic"] for r in table], "s", mfc="none", label="SPH, periodic")
    ax[0].plot(um, [r["u_ode"] for r in table], "x", label="1D ODE of the same model")
    for r in table:
        ax[0].annotate(r["id"], (r["u_meas"], r["inout"]), fontsize=6)
    xs = np.linspace(0.15, 0.65, 2)
    ax[0].plot(xs, xs, "k-", lw=0.8)
    ax[0].fill_between(xs, 0.95 * xs, 1.05 * xs, color="0.85", label="±5 %")
    ax[0].set_xlabel("measured U = Fr sqrt(gH) [m/s] (Kazemi Table 3-1)")
    ax[0].set_ylabel("simulated U above the crest [m/s]")
    ax[0].legend(fontsize=7)
    ref = next((r for r in table if r["id"] == "S004H50"), table[0])
    _, _, s0, h, _, _ = flows.flow(ref["id"])
    rd = flows.rd_over_h(h) * h
    for kind, st in (("inout", "o-"), ("periodic", "s-")):
        z, u = ref[kind + "_profile"]
        ax[1].plot(u, 1000 * z, st, ms=3, label=f"SPH {kind}")
    _, (zs, uu) = ode(ref["id"])
    ax[1].plot(uu, 1000 * np.array(zs), "k-", lw=1, label="1D ODE")
    us = math.sqrt(9.81 * h * s0)
    zp, upr = ref["periodic_profile"]
    i = np.argmin(np.abs(zp - (rd + 0.3 * h)))
    ks = (zp[i] - rd) * math.exp(-0.41 * (upr[i] / us - 8.5))  # log law from the crest through the 0.3 H point
    zz = np.linspace(rd + 0.05 * h, rd + h, 40)
    ax[1].plot(us * (np.log((zz - rd) / ks) / 0.41 + 8.5), 1000 * zz, "k--", lw=0.8,
               label=f"log law from the crest, u* = {us:.4f} m/s (k_s fitted at 0.3 H)")
    ax[1].axhline(1000 * rd, color="0.6", ls=":", lw=0.8)
    ax[1].set_xlabel("u [m/s]")
    ax[1].set_ylabel("z above the numerical bed [mm] (crest dotted)")
    ax[1].set_title(ref["id"], fontsize=9)
    ax[1].legend(fontsize=7)
    # shear stresses at mid-channel (periodic run): modelled tau_t, resolved tau_r (Kazemi eqs 3.22-3.23) and the
    # uniform-flow total g S0 (D - z) above the crest, where the drag layer no longer carries any of it
    out = ref.get("periodic_dir")
    if out:
        _, d = read_csv(os.path.join(out, "gauges", "stress_50.csv"))
        _, pts = read_csv(os.path.join(out, "gauges", "stress_50.points.csv"))
        t0, t1 = cfg["window"]
        m = window_mean(d, t0, t1)
        z = pts[:, 3]
        ax[2].plot(m[1::4], 1000 * z, "o-", ms=3, label="modelled τ_t/ρ (MSPH-ML)")
        ax[2].plot(m[2::4], 1000 * z, "s-", ms=3, label="resolved τ_r/ρ = −⟨u'w'⟩")
        D = h + rd
        zz = np.linspace(rd, D, 20)
        ax[2].plot(9.81 * s0 * (D - zz), 1000 * zz, "k--", lw=1, label="g S0 (D − z) (total, above the crest)")
        ax[2].axhline(1000 * rd, color="0.6", ls=":", lw=0.8)
        ax[2].set_xlabel("shear stress / ρ [m²/s²]")
        ax[2].set_ylabel("z above the numerical bed [mm]")
        ax[2].legend(fontsize=7)
    fig.tight_layout()
    path = os.path.join(folder, f"{NAME}.png")
    fig.savefig(path, dpi=120)
    print(f"plot: {path}")


if __name__ == "__main__":
    main()
