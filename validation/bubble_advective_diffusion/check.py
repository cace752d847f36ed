#!/usr/bin/python3
"""Advective diffusion of a pollutant carried by a rising bubble (cases/bubble_advective_diffusion.yaml): issue 6
(transported scalars), validation 6; Federico §9.3.

Set-up: a tank 2.4 m x 2.4 m full of water; a circular bubble of a lighter pollutant phase, radius r = 0.2 m,
centred at (x0, z0) = (1.2, 1.2), density ratio rho2/rho1 = 0.5 (the case) and 0.3
(--set multiphase.phases.0.density=300); the bubble carries C(0) = exp(-r^2 / (4 D t0)) about its centre
(Federico 9.3), D = 1e-3 m2/s, t0 = 1 s. System 1 of the thesis (Tait gamma 7, equal B, c0 = 10 sqrt(g h),
alpha 0.01, XSPH 0.1). The scalar is carried as C = rho Y (Y the specific content): transport.advection =
conservative (default) is Federico's advective-diffusion model (4.12) with the sign of docs/numerics.md, Errata,
exactly conservative; transport.advection = none is his "pure diffusion" model (DC/Dt = diffusion only). Both run to
t = 0.5 s with the consistent diffusion operator.

Metrics (issue 6 validation 6), per density ratio, on the conservative run:
  (a) total pollutant mass sum m C / rho (gauge pollutant_mass, column mass, every output): max over the outputs of
      |mass / mass(0) - 1| <= 1e-10;
  (b) the concentration tracks the bubble: its mass centroid (pollutant_mass x, z) within 2 dx, at every output
      (0.05 s) up to 0.5 s, of the bubble material that carries it: the Lagrangian centroid of the initial
      pollutant, sum m_a Y_a(0) x_a(t) / sum m_a Y_a(0) (Y = C / rho at t = 0, particles tracked by id through the
      snapshots). The Gaussian sits in the bubble's core, which rises faster than the bubble's area centroid as
      the bubble rolls into an umbrella: the C centroid leads the area centroid by a physical distance that
      converges with resolution (0.5: 5.2 cm at dx 0.03, 4.3 cm at dx 0.015; 0.3: 10.3 and 7.0 cm), so against
      the area centroid 2 dx cannot hold at every resolution; that distance is printed as information;
  (b') the same bubble uniformly filled with C = 1 (--set transport.scalars.0.initial=[{type: region, ...}]):
      the pollutant then fills the bubble, and its C centroid must stay within 2 dx of the bubble's area centroid
      (gauge bubble x, z) at every output: the literal "concentration centroid tracks the bubble";
  (c) min C >= -1e-3 at every output (gauge min column and the snapshots).
Information (not gated; the thesis's own claim, Federico §9.3):
  - e_RMS (Federico 9.8) = sqrt(1/(N - 1) sum (C_a - C_n)^2) over the particles with C > 1e-3 at t = 0.2 and
    0.5 s against the heuristic (9.6)
        C = c0 / sqrt(t + t0) exp[-((x - x0)^2 + (z - z0 - V t)^2) / (4 D (t + t0))],
        V = 1/2 sqrt(g (rho1 - rho2) r / rho1) (9.7), c0 = 1, t0 = 1, D = 1e-3,
    for advection conservative and none. The thesis claims e_RMS(4.12) < e_RMS(pure diffusion) for
    rho2/rho1 <= 0.5 at t = 0.5 s (its Fig. 55). (9.6) is not an exact solution: a rigidly translating Gaussian
    with the 1D decay factor 1/sqrt(t + t0) (of (9.4), Federico §9.1.3; the exact 2D peak decays as t0/(t + t0))
    and Batchelor's speed for a bubble that deforms into an umbrella;
  - the distance between the concentration centroid and the Lagrangian centroid of the initial pollutant,
    sum m_a Y_a(0) x_a(t) / sum m_a Y_a(0) (Y = C / rho at t = 0, particles tracked by id through the snapshots):
    advection alone moves the C centroid with that point, so the distance isolates what diffusion moves;
  - mass drift of the advection = none runs (C does not follow the compression, so sum m C / rho drifts).
Figure: the particles' C at t = 0, 0.2, 0.5 s for both ratios with the bubble's outline (the phase indicator's
0.5 contour), the centroid tracks (bubble area, C, Lagrangian, (9.6)'s z0 + V t), and the C profile along x = 1.2
against (9.6).
Modes: coarse (CTest) dx = 0.03 (the thesis's, §9.1.3; 7,174 particles, ~45 s per run single-threaded):
per ratio the Gaussian and the uniform bubble, conservative advection (4 runs); fine dx = 0.015 (half; ~8x the
work) adds the advection = none runs for the e_RMS information (6 runs). Same thresholds.
Usage: /usr/bin/python3 validation/bubble_advective_diffusion/check.py [--mode coarse|fine] [--sphflume PATH]
       [--out DIR] [--threads N] [--reuse] [--set KEY=VALUE]
"""
import math
import os
import sys

import numpy as np
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from common import Report, fluid_snapshots, info, parse_sets, read_rows, run_case, save_figure, validation_args  # noqa: E402

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.tri as mtri  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
CASE = os.path.normpath(os.path.join(HERE, "..", "..", "cases", "bubble_advective_diffusion.yaml"))
NAME = "bubble_advective_diffusion"
G, RHO1, R_B = 9.81, 1000.0, 0.2
X0, Z0 = 1.2, 1.2
C0, T0, D = 1.0, 1.0, 1.0e-3
END = 0.5
RATIOS = (0.5, 0.3)
ADVECTION = ("conservative", "none")
UNIFORM = "[{type: region, shape: circle, center: [1.2, 1.2], radius: 0.2, value: 1.0}]"
ERMS_TIMES = (0.2, 0.5)
FIG_TIMES = (0.0, 0.2, 0.5)
MODES = {"coarse": {"dx": 0.03}, "fine": {"dx": 0.015}}
SRC = "issue 6 validation 6; Federico §9.3"


def rise_speed(ratio):
    return 0.5 * math.sqrt(G * (1.0 - ratio) * R_B)


def heuristic(x, z, t, V):
    """Federico (9.6)."""
    w = 4 * D * (t + T0)
    return C0 / math.sqrt(t + T0) * np.exp(-((x - X0) ** 2 + (z - Z0 - V * t) ** 2) / w)


def snapshots(out):
    """[(time, dict of the fluid particles' id, x, z, C, m, rho, phase)] in time order."""
    names = {"id": "id", "C": "concentration", "m": "mass", "rho": "density", "phase": "phase"}
    return [(t, {"x": d["x"], "z": d["z"], **{k: d[v] for k, v in names.items()}})
            for t, d in fluid_snapshots(out, list(names.values()))]


def at(snaps, t):
    for tt, s in snaps:
        if abs(tt - t) < 1e-6:
            return s
    raise SystemExit(f"no snapshot at t = {t}")


def lagrangian_track(snaps):
    """[(t, x, z)] of sum m Y(0) x(t) / sum m Y(0), particles tracked by id; and the C centroids [(t, x, z)]."""
    s0 = snaps[0][1]
    w0 = dict(zip(s0["id"].tolist(), (s0["m"] * s0["C"] / s0["rho"]).tolist()))
    lag, cen = [], []
    for t, s in snaps:
        w = np.array([w0.get(i, 0.0) for i in s["id"].tolist()])
        lag.append((t, np.sum(w * s["x"]) / np.sum(w), np.sum(w * s["z"]) / np.sum(w)))
        q = s["m"] * s["C"] / s["rho"]
        cen.append((t, np.sum(q * s["x"]) / np.sum(q), np.sum(q * s["z"]) / np.sum(q)))
    return np.array(lag), np.array(cen)


def e_rms(s, t, V):
    k = s["C"] > 1e-3
    ref = heuristic(s["x"][k], s["z"][k], t, V)
    return math.sqrt(np.sum((s["C"][k] - ref) ** 2) / (k.sum() - 1)), int(k.sum())


def main():
    a = validation_args(NAME, __doc__, MODES)
    dx = MODES[a.mode]["dx"]
    os.makedirs(a.out, exist_ok=True)
    rep = Report()
    print(f"\n== {NAME} ({a.mode}: dx = {dx}, to t = {END} s, rho2/rho1 = {RATIOS}, advection {ADVECTION})")
    walls, failed, runs = {}, [], {}
    advections = ADVECTION if a.mode == "fine" else ("conservative",)
    for ratio in RATIOS:
        for adv in advections + ("uniform",):
            label = f"ratio{ratio:g}_{adv}_dx{dx:g}"
            out = os.path.join(a.out, label)
            sets = {"particles.dx": dx, "time.end": END}
            if ratio != 0.5:
                sets["multiphase.phases.0.density"] = f"{ratio * RHO1:g}"
            if adv == "uniform":
                sets["transport.scalars.0.initial"] = UNIFORM
            elif adv != "conservative":
                sets["transport.advection"] = adv
            sets.update(parse_sets(a.set))
            s, wall, rc = run_case(a.sphflume, CASE, out, sets, a.threads, a.reuse)
            walls[label] = wall
            if s is None:
                rep.metric(f"{label}: run", f"exit code {rc}", False, "0", "run")
                failed.append(label)
                continue
            runs[(ratio, adv)] = out

    data = {}
    for ratio in RATIOS:
        V = rise_speed(ratio)
        print(f"\n-- rho2/rho1 = {ratio}: (9.7) V = {V:.4f} m/s")
        out = runs.get((ratio, "uniform"))
        if out is not None:
            _, pm = read_rows(os.path.join(out, "gauges", "pollutant_mass.csv"))
            _, bu = read_rows(os.path.join(out, "gauges", "bubble.csv"))
            k = pm[:, 0] <= END + 1e-9
            dist = np.hypot(pm[k, 4] - bu[k, 3], pm[k, 5] - bu[k, 4])
            i = int(np.argmax(dist))
            rep.metric(f"rho2/rho1 = {ratio}: (b') bubble filled with C = 1: max |C centroid - bubble area centroid| "
                       f"over {k.sum()} outputs to {END} s", f"{dist[i]:.4f} m = {dist[i] / dx:.2f} dx (at t = "
                       f"{pm[i, 0]:g} s)", dist[i] <= 2 * dx, f"<= 2 dx = {2 * dx:g} m", SRC)
            drift = np.abs(pm[:, 1] / pm[0, 1] - 1)
            rep.metric(f"rho2/rho1 = {ratio}: (a') bubble filled with C = 1: max |mass / mass(0) - 1|",
                       f"{drift.max():.1e}", drift.max() <= 1e-10, "<= 1e-10", SRC)
        for adv in ADVECTION:
            out = runs.get((ratio, adv))
            if out is None:
                continue
            _, pm = read_rows(os.path.join(out, "gauges", "pollutant_mass.csv"))
            _, bu = read_rows(os.path.join(out, "gauges", "bubble.csv"))
            sn = snapshots(out)
            lag, cen = lagrangian_track(sn)
            data[(ratio, adv)] = (pm, bu, sn, lag, cen)
            drift = np.abs(pm[:, 1] / pm[0, 1] - 1)
            cmin = min(pm[:, 2].min(), min(s["C"].min() for _, s in sn))
            if adv == "conservative":
                rep.metric(f"rho2/rho1 = {ratio}: (a) total pollutant mass, max |mass / mass(0) - 1| over "
                           f"{len(pm)} outputs", f"{drift.max():.1e} (mass(0) = {pm[0, 1]:.6e} kg/m)",
                           drift.max() <= 1e-10, "<= 1e-10", SRC)
                if pm.shape[0] != bu.shape[0] or np.abs(pm[:, 0] - bu[:, 0]).max() > 1e-9:
                    raise SystemExit("pollutant_mass and bubble gauges have different output times")
                k = pm[:, 0] <= END + 1e-9
                dist = np.hypot(pm[k, 4] - bu[k, 3], pm[k, 5] - bu[k, 4])
                i = int(np.argmax(dist))
                dl = np.hypot(cen[:, 1] - lag[:, 1], cen[:, 2] - lag[:, 2])
                j = int(np.argmax(dl))
                rep.metric(f"rho2/rho1 = {ratio}: (b) max |C centroid - centroid of the bubble material carrying the "
                           f"initial pollutant| over {len(dl)} outputs to {END} s",
                           f"{dl[j]:.4f} m = {dl[j] / dx:.2f} dx (at t = {cen[j, 0]:g} s)", dl[j] <= 2 * dx,
                           f"<= 2 dx = {2 * dx:g} m", SRC)
                info(f"rho2/rho1 = {ratio}: max |C centroid - bubble area centroid| over {k.sum()} outputs to "
                     f"{END} s", f"{dist[i]:.4f} m = {dist[i] / dx:.2f} dx (at t = {pm[i, 0]:g} s; C centroid z "
                     f"{pm[i, 5]:.4f}, bubble {bu[i, 4]:.4f}): the core leads the umbrella", dist[i] <= 2 * dx,
                     f"<= 2 dx = {2 * dx:g} m", "information (see (b) in the docstring)")
                every = [j for j in range(len(dist)) if abs(pm[j, 0] / 0.1 - round(pm[j, 0] / 0.1)) < 1e-6]
                info(f"rho2/rho1 = {ratio}: |C centroid - bubble area centroid| / dx at t = "
                     + ", ".join(f"{pm[j, 0]:g}" for j in every) + " s",
                     ", ".join(f"{dist[j] / dx:.2f}" for j in every), True, "-", "information")
                rep.metric(f"rho2/rho1 = {ratio}: (c) min C over the outputs (gauge and snapshots)", f"{cmin:.2e}",
                           cmin >= -1e-3, ">= -1e-3", SRC)
                info(f"rho2/rho1 = {ratio}: |C centroid - Lagrangian centroid of C(0)| (diffusion's share)",
                     f"max {dl.max():.2e} m = {dl.max() / dx:.3f} dx; at 0.5 s {dl[-1]:.2e} m (dz = "
                     f"{cen[-1, 2] - lag[-1, 2]:+.2e} m); C centroid rose {cen[-1, 2] - cen[0, 2]:.4f} m, "
                     f"bubble centroid {bu[-1, 4] - bu[0, 4]:.4f} m, (9.7) V t = {V * END:.4f} m",
                     dl.max() <= dx, "<= dx", "information")
            else:
                info(f"rho2/rho1 = {ratio}, advection = {adv}: max |mass / mass(0) - 1|", f"{drift.max():.1e}",
                     drift.max() <= 1e-10, "<= 1e-10", "not conservative: C does not follow the compression")
                info(f"rho2/rho1 = {ratio}, advection = {adv}: min C", f"{cmin:.2e}", cmin >= -1e-3, ">= -1e-3",
                     "information")
        errs = {}
        for adv in ADVECTION:
            if (ratio, adv) not in data:
                continue
            sn = data[(ratio, adv)][2]
            cmax0 = sn[0][1]["C"].max()
            for t in ERMS_TIMES:
                e, n = e_rms(at(sn, t), t, V)
                errs[(adv, t)] = e
                s = at(sn, t)
                info(f"rho2/rho1 = {ratio}, advection = {adv}, t = {t:g} s: e_RMS (9.8) vs (9.6), {n} particles "
                     f"with C > 1e-3", f"{e:.4e} ({100 * e:.2f} % of c0); peak C {s['C'].max():.4f} vs (9.6) "
                     f"{C0 / math.sqrt(t + T0):.4f} (1D decay), 2D diffusion alone {cmax0 * T0 / (t + T0):.4f}",
                     True, "-",
                     "Federico (9.8), Fig. 55 (report)")
        for t in ERMS_TIMES:
            if ("conservative", t) in errs and ("none", t) in errs:
                ec, en = errs[("conservative", t)], errs[("none", t)]
                info(f"rho2/rho1 = {ratio}, t = {t:g} s: thesis's claim e_RMS(conservative, 4.12) < e_RMS(none)",
                     f"{ec:.4e} vs {en:.4e} (ratio {ec / en:.4f})", ec < en, "conservative < none",
                     "Federico §9.3, Fig. 55")

    draw(a, dx, data)
    print("\nrun wall times: " + ", ".join(f"{k} {v:.1f} s" for k, v in walls.items())
          + f"; total {sum(walls.values()):.1f} s")
    if failed:
        print(f"\n{NAME} {a.mode}: RUN FAILED: {', '.join(failed)}")
        raise SystemExit(2)
    rep.finish(NAME, a.mode)


def draw(a, dx, data):
    fig, axs = plt.subplots(len(RATIOS), len(FIG_TIMES) + 2, figsize=(19, 7.8), layout="constrained",
                            gridspec_kw={"width_ratios": [1] * len(FIG_TIMES) + [1.1, 1.1]})
    sc = None
    for r, ratio in enumerate(RATIOS):
        V = rise_speed(ratio)
        d = data.get((ratio, "conservative"))
        if d is None:
            continue
        pm, bu, sn, lag, cen = d
        for c, t in enumerate(FIG_TIMES):
            ax = axs[r, c]
            s = at(sn, t)
            win = (np.abs(s["x"] - X0) < 0.55) & (s["z"] > 0.8) & (s["z"] < 2.05)
            ms = 10 if dx > 0.02 else 3
            hot = win & (s["C"] > 1e-3)
            ax.scatter(s["x"][win & ~hot], s["z"][win & ~hot], s=ms / 3, c="0.75", lw=0)
            sc = ax.scatter(s["x"][hot], s["z"][hot], c=s["C"][hot], s=ms, lw=0, cmap="viridis", vmin=0, vmax=0.9)
            tri = mtri.Triangulation(s["x"][win], s["z"][win])
            ax.tricontour(tri, (s["phase"][win] != 0).astype(float), levels=[0.5], colors="k", linewidths=1.0)
            ax.plot(*cen[np.argmin(np.abs(cen[:, 0] - t)), 1:], "r+", ms=9, mew=1.5)
            ax.plot(X0, Z0 + V * t, "kx", ms=6)
            ax.set_xlim(X0 - 0.45, X0 + 0.45)
            ax.set_ylim(0.9, 1.95)
            ax.set_aspect("equal")
            ax.set_title(f"rho2/rho1 = {ratio}, t = {t:g} s", fontsize=9)
            ax.tick_params(labelsize=7)
        ax = axs[r, len(FIG_TIMES)]
        ax.plot(bu[:, 0], bu[:, 4], "C0o-", ms=3, lw=1, label="bubble area centroid")
        ax.plot(pm[:, 0], pm[:, 5], "C3s-", ms=3, lw=1, label="C centroid (gauge)")
        ax.plot(lag[:, 0], lag[:, 2], "k+", ms=7, label="Lagrangian centroid of C(0)")
        tt = np.linspace(0, END, 50)
        ax.plot(tt, Z0 + V * tt, "k--", lw=1, label=f"(9.6): z0 + V t, V = {V:.3f} m/s")
        ax.fill_between(bu[:, 0], bu[:, 4] - 2 * dx, bu[:, 4] + 2 * dx, color="C0", alpha=0.15,
                        label="bubble centroid +- 2 dx")
        dn = data.get((ratio, "none"))
        if dn is not None:
            ax.plot(dn[0][:, 0], dn[0][:, 5], "C2:", lw=1.2, label="C centroid, advection none")
        ax.set_xlabel("t (s)")
        ax.set_ylabel("z (m)")
        ax.set_title(f"rho2/rho1 = {ratio}: centroid tracks, dx = {dx}", fontsize=9)
        ax.legend(fontsize=6)
        ax = axs[r, len(FIG_TIMES) + 1]
        zz = np.linspace(0.9, 1.9, 400)
        for t, col in zip(FIG_TIMES, ("k", "C0", "C3")):
            ax.plot(zz, heuristic(X0, zz, t, V), "-", color=col, lw=1, label=f"(9.6), t = {t:g} s")
            for adv, mk in (("conservative", "o"), ("none", "x")):
                dd = data.get((ratio, adv))
                if dd is None:
                    continue
                s = at(dd[2], t)
                k = (np.abs(s["x"] - X0) < dx) & (s["z"] > 0.9) & (s["z"] < 1.9)
                ax.plot(s["z"][k], s["C"][k], mk, ms=3, mfc="none", color=col,
                        label=f"SPH {adv}" if t == FIG_TIMES[-1] else None)
        ax.set_xlabel(f"z (m), particles with |x - {X0}| < dx")
        ax.set_ylabel("C")
        ax.set_title(f"rho2/rho1 = {ratio}: C along x = {X0}", fontsize=9)
        ax.legend(fontsize=6)
    if sc is not None:
        fig.colorbar(sc, ax=axs[:, :len(FIG_TIMES)].ravel().tolist(), shrink=0.6, label="C (kg/m3)")
    fig.suptitle(f"{NAME}: C of the particles (C > 1e-3 coloured; black line: bubble outline; red +: C centroid; "
                 "black x: (9.6)'s centre)",
                 fontsize=10)
    save_figure(fig, HERE, NAME, a.mode, a.out)


if __name__ == "__main__":
    main()
