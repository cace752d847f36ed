#!/usr/bin/python3
"""Turbulent uniform flow over a rough bed (Kazemi ch. 3, Table 3-1; issue: open channels, validation 3).

Every flow: bed of spheres d_s = 24 mm as Kazemi's drag layer (thickness R_d from his fitted law, C_d = 1),
MSPH-ML mixing-length turbulence (Nezu-Rodi, kappa = 0.41, l_m from the numerical bed to the local surface),
Kazemi's unknown-discharge inflow (inflow particles take the fluid's kernel-averaged velocity and density 0.5 dx
inside the fluid) and a frozen outflow, L = 4 H (validation/rough_bed/flows.py builds each case file and states
the numerical settings). The discharge is an output. Metrics over the averaging window:
  1. depth-averaged velocity U = q / H_mean (q: time-mean flux at mid-channel, H_mean: time-mean depth) within 5 %
     of the measured U = Fr sqrt(g H) of Table 3-1 (fine; coarse: 10 %, see MODES);
  2. depth uniform along the channel: (max - min) / mean of the time-mean depth at 9 stations from 0.1 L to 0.9 L
     within 2 %;
  3. volume balance: |V_out - V_in| / V_in < 0.5 % in every 1 s interval of the window (V: the volume of the
     particles converted at the inflow and outflow lines, mass / rho0; Kazemi's eq 3.19 criterion);
  4. steadiness (Kazemi's criterion): the mid-channel flux averaged over the two halves of the window differs by
     less than 2 %.
  --sps also runs each flow with SPS-Smagorinsky (C_s = 0.15) and reports its discharge against MSPH-ML's (the
  thesis: SPS overestimates it, being too weak a momentum transfer for a macroscopic rough bed).
Draws rough_bed.png: simulated against measured U for the flows run, and the S004H50 velocity profile against
the rough-bed log law u/u* = ln(z/k_s)/kappa + 8.5 with u* = sqrt(g H S0) and k_s = R_d fitted... no: k_s is not
given by the thesis, so the log law is drawn with the k_s that passes through the simulated profile at mid-depth
and only its slope (1/kappa) is compared.
Usage: /usr/bin/python3 validation/rough_bed/check.py [--mode coarse|fine] [--flows S004H50,...] [--sps]
"""
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

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

NAME = "rough_bed"
# coarse (CI): one flow, H/dx = 10, 12 s, averaged over [8, 12] s; the tolerance on U is wider (10 %: the bulk
# velocity at H/dx = 10 differs from the H/dx = 20 one by ~X %, measured, see validation/README.md)
MODES = {
    "coarse": {"flows": ["S004H50"], "dx_per_h": 10, "t_end": 12.0, "window": (8.0, 12.0), "u_tol": 0.10,
               "uniform_tol": 0.03, "balance_tol": 0.01},
    "fine": {"flows": [r[1] for r in flows.TABLE], "dx_per_h": 20, "t_end": 30.0, "window": (20.0, 30.0),
             "u_tol": 0.05, "uniform_tol": 0.02, "balance_tol": 0.005},
}


def read_csv(path):
    with open(path) as f:
        rows = list(csv.reader(f))
    head = rows[0]
    data = np.array([[float(v) for v in r] for r in rows[1:]])
    return head, data


def window_mean(data, t0, t1):
    m = (data[:, 0] >= t0 - 1e-9) & (data[:, 0] <= t1 + 1e-9)
    return np.nanmean(data[m, 1:], axis=0), m


def analyse(out, fid, cfg, rep, label=""):
    _, _, s0, h, fr, _ = flows.flow(fid)
    u_meas = flows.measured_u(fr, h)
    t0, t1 = cfg["window"]
    _, q = read_csv(os.path.join(out, "gauges", "q_mid.csv"))
    _, dep = read_csv(os.path.join(out, "gauges", "depth.csv"))
    qm, _ = window_mean(q, t0, t1)
    dm, _ = window_mean(dep, t0, t1)
    depth = float(np.mean(dm))
    u_sim = float(qm[0]) / depth
    err = (u_sim - u_meas) / u_meas
    rep.metric(f"{fid}{label} U (q/H = {qm[0]:.5f}/{depth:.4f}) vs measured {u_meas:.4f} m/s", f"{u_sim:.4f} m/s ({100 * err:+.1f} %)",
               abs(err) <= cfg["u_tol"], f"|error| <= {100 * cfg['u_tol']:.0f} %", "Kazemi Table 3-1 (U = Fr sqrt(gH))")
    unif = (float(np.max(dm)) - float(np.min(dm))) / depth
    rep.metric(f"{fid}{label} depth non-uniformity (9 stations, 0.1-0.9 L)", f"{100 * unif:.2f} % (mean depth {depth:.4f} m, H {h} m)",
               unif <= cfg["uniform_tol"], f"<= {100 * cfg['uniform_tol']:.0f} %", "issue (uniform flow)")
    _, bv = read_csv(os.path.join(out, "gauges", "volumes.csv"))
    worst = 0.0
    for a in np.arange(t0, t1 - 1.0 + 1e-9, 1.0):
        ia = np.argmin(np.abs(bv[:, 0] - a))
        ib = np.argmin(np.abs(bv[:, 0] - (a + 1.0)))
        vin = bv[ib, 1] - bv[ia, 1]
        vout = bv[ib, 2] - bv[ia, 2]
        worst = max(worst, abs(vout - vin) / vin)
    rep.metric(f"{fid}{label} worst |V_out - V_in| / V_in per 1 s", f"{100 * worst:.2f} %", worst < cfg["balance_tol"],
               f"< {100 * cfg['balance_tol']:.1f} %", "Kazemi eq 3.19")
    tm = 0.5 * (t0 + t1)
    qa, _ = window_mean(q, t0, tm)
    qb, _ = window_mean(q, tm, t1)
    st = abs(qb[0] - qa[0]) / qa[0]
    rep.metric(f"{fid}{label} steadiness (flux, two halves of the window)", f"{100 * st:.2f} %", st < 0.02, "< 2 %",
               "Kazemi §3 (steady criterion 2 %)")
    return {"id": fid, "u_meas": u_meas, "u_sim": u_sim, "depth": depth, "q": float(qm[0]), "s0": s0, "h": h}


def main():
    a = validation_args(NAME, __doc__, MODES)
    cfg = dict(MODES[a.mode])
    sel = cfg["flows"]
    extra = [s for s in a.set if s.startswith("flows=")]
    if extra:
        sel = extra[0].split("=", 1)[1].split(",")
    sets = [s for s in a.set if not s.startswith("flows=") and not s.startswith("sps")]
    run_sps = any(s.startswith("sps") for s in a.set)
    os.makedirs(a.out, exist_ok=True)
    rep = Report()
    results, sps = [], []
    for fid in sel:
        for turb in (["mixing_length", "smagorinsky"] if run_sps else ["mixing_length"]):
            tag = fid + ("" if turb == "mixing_length" else "_sps")
            out = os.path.join(a.out, tag)
            os.makedirs(a.out, exist_ok=True)
            case = os.path.join(a.out, tag + ".yaml")
            with open(case, "w") as f:
                f.write(flows.case_yaml(fid, cfg["dx_per_h"], cfg["t_end"], turbulence=turb)
                        + "  - {name: volumes, type: boundary_volume}\n")
            h = flows.flow(fid)[3]
            run_sets = {"particles.dx": h / cfg["dx_per_h"], "time.end": cfg["t_end"]}
            for kv in sets:
                k, v = kv.split("=", 1)
                run_sets[k] = v
            s, wall, rc = run_case(a.sphflume, case, out, run_sets, a.threads, a.reuse)
            rep.metric(f"{tag} run completes", f"exit {rc}", rc == 0, "exit 0", "robustness")
            if rc != 0:
                continue
            mb = s["mass"]
            rep.metric(f"{tag} mass balance", f"{mb['relative_error']:.2e}", abs(mb["relative_error"]) < 1e-12, "< 1e-12",
                       "initial + inflow - outflow - backflow - removed = final")
            r = analyse(out, fid, cfg, rep, "" if turb == "mixing_length" else " (SPS)")
            r["wall"] = wall
            (results if turb == "mixing_length" else sps).append(r)
    for r in sps:
        ml = next(x for x in results if x["id"] == r["id"])
        ratio = r["q"] / ml["q"]
        rep.metric(f"{r['id']} SPS-Smagorinsky (C_s 0.15) discharge / MSPH-ML discharge", f"{ratio:.3f}", ratio > 1.10,
                   "> 1.10 (SPS overestimates; digest B4: more than 10 % above)", "Kazemi §3.5, Fig. 3-19")
    if results:
        plot(a.out, results, sps, cfg)
    rep.finish(NAME, a.mode)


def plot(out, results, sps, cfg):
    fig, ax = plt.subplots(1, 2, figsize=(11, 4.5))
    um = [r["u_meas"] for r in results]
    us = [r["u_sim"] for r in results]
    ax[0].plot(um, us, "o", label="MSPH-ML (this code)")
    for r in results:
        ax[0].annotate(r["id"], (r["u_meas"], r["u_sim"]), fontsize=6)
    if sps:
        ax[0].plot([r["u_meas"] for r in sps], [r["u_sim"] for r in sps], "s", mfc="none", label="SPS-Smagorinsky")
    lo, hi = 0.15, 0.7
    xs = np.linspace(lo, hi, 2)
    ax[0].plot(xs, xs, "k-", lw=0.8)
    ax[0].fill_between(xs, xs * (1 - cfg["u_tol"]), xs * (1 + cfg["u_tol"]), color="0.85", label=f"±{100 * cfg['u_tol']:.0f} %")
    ax[0].set_xlabel("measured U [m/s] (Table 3-1)")
    ax[0].set_ylabel("simulated U = q / H [m/s]")
    ax[0].legend(fontsize=8)
    ref = next((r for r in results if r["id"] == "S004H50"), results[0])
    fid = ref["id"]
    head, prof = read_csv(os.path.join(out, fid, "gauges", "u_50.csv"))
    _, pts = read_csv(os.path.join(out, fid, "gauges", "u_50.points.csv"))
    t0, t1 = cfg["window"]
    pm, _ = window_mean(prof, t0, t1)
    ux = pm[0::2]
    z = pts[:, 2]
    ax[1].plot(ux, z * 1000, "o-", ms=3, label=f"{fid} simulated (t in [{t0:g}, {t1:g}] s)")
    us_ = math.sqrt(9.81 * ref["h"] * ref["s0"])
    rd = flows.rd_over_h(ref["h"]) * ref["h"]
    zw = z  # from the numerical bed
    mid = len(z) // 2
    ks = zw[mid] * math.exp(-0.41 * (ux[mid] / us_ - 8.5))
    zz = np.linspace(max(rd, z[0]), ref["h"], 50)
    ax[1].plot(us_ * (np.log(zz / ks) / 0.41 + 8.5), zz * 1000, "k--", label=f"log law, u* = {us_:.4f}, k_s = {1000 * ks:.1f} mm")
    ax[1].axhline(rd * 1000, color="0.6", lw=0.8, ls=":")
    ax[1].text(ux.min(), rd * 1000, " roughness crest (R_d)", fontsize=7, va="bottom")
    ax[1].set_xlabel("u [m/s]")
    ax[1].set_ylabel("z above the numerical bed [mm]")
    ax[1].legend(fontsize=7)
    fig.tight_layout()
    path = os.path.join(HERE, f"{NAME}.png")
    fig.savefig(path, dpi=120)
    print(f"plot: {path}")


if __name__ == "__main__":
    main()
