#!/usr/bin/python3
"""Still water meeting a 1:20 slope under ISPH `formulation: lind` (issue 57; cases/still_shore_isph.yaml).

0.04 m of water at rest in a 2 m tank meets a 1:20 slope (toe at x = 0.3 m, the still shoreline at x = 1.1 m) at
Flume B's d0 (dx = 5 mm, h = 2 dx): the shoreline of validation/runup_flume_b, where lind's first failure was
(session 26: the thin layer over the slope thrown up within 0.5 s). The fluid lattice is cut by the slope, so the
first row over it sits up to one dx above the slope's surface: the water falls into that gap at the start, which is
the only energy the initial state holds beyond rest.
Metrics (lind):
  1. the run reaches t_end (3 s) and conserves the fluid mass exactly;
  2. max |u| of the fluid over every snapshot <= sqrt(2 g dx) = 0.313 m/s: the speed of a free fall over the
     fill's largest gap; a faster particle took energy the initial state does not hold;
  3. nothing thrown: in every snapshot no fluid particle is more than 2 dx above both the still level and the
     slope's surface beneath it (a film creeping up the slope lies dx/2 above the slope and passes).
Information: the same case under WCSPH (the reference's behaviour at the same dx: its max |u|, its height above
level and slope), the shoreline's position over time, the 99th percentile of |u| at the end, and the number of
fluid pairs closer than 0.3 dx at the end (the surface rows' pairing, docs/numerics.md §13b).
Usage: /usr/bin/python3 validation/still_shore_isph/check.py [--mode coarse|fine] [--sphflume PATH] [--out DIR]
(both modes run the case at its dx: it is small; fine writes the figure next to this script)
"""
import glob
import math
import os
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from common import Report, parse_sets, run_case, run_metrics, save_figure, validation_args  # noqa: E402

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
CASE = os.path.normpath(os.path.join(HERE, "..", "..", "cases", "still_shore_isph.yaml"))
NAME = "still_shore_isph"
G, LEVEL, TOE, SLOPE, DX = 9.81, 0.04, 0.3, 1.0 / 20.0, 0.005
MODES = {"coarse": {"end": 3.0}, "fine": {"end": 3.0}}


def bed(x):
    return np.maximum(0.0, (x - TOE) * SLOPE)


def scan(out):
    """Per snapshot: time, max |u|, the largest height above max(level, slope surface), shoreline x, u99; and the
    last snapshot's fluid positions, speeds and close pairs."""
    rows = []
    for f in sorted(glob.glob(os.path.join(out, "snapshots", "*.h5"))):
        with h5py.File(f, "r") as h:
            fl = h["kind"][:] == 0
            p = h["position"][:][fl]
            v = h["velocity"][:][fl]
            t = float(h.attrs["time"])
        x, z = p[:, 0], p[:, 2]
        sp = np.hypot(v[:, 0], v[:, 2])
        above = z - np.maximum(LEVEL, bed(x))
        rows.append((t, sp.max(), above.max(), x.max(), np.percentile(sp, 99)))
    pts = np.column_stack([x, z])
    d2 = ((pts[:, None, :] - pts[None, :, :]) ** 2).sum(-1)
    np.fill_diagonal(d2, np.inf)
    pairs = int((d2 < (0.3 * DX) ** 2).sum() // 2)
    return np.array(rows), pts, sp, pairs


def main():
    a = validation_args(NAME, __doc__, MODES)
    m = MODES[a.mode]
    os.makedirs(a.out, exist_ok=True)
    sets = parse_sets(a.set)
    rep = Report()
    runs = {}
    for label, extra in (("lind", {}), ("wcsph", {"scheme": "{type: wcsph}"})):
        out = os.path.join(a.out, label)
        s, wall, rc = run_case(a.sphflume, CASE, out, {"particles.dx": DX, "time.end": m["end"], **extra, **sets},
                               a.threads, a.reuse)
        print(f"\n== {NAME} {label} ({a.mode}: dx = {DX} m, t_end = {m['end']} s; run wall time {wall:.1f} s)")
        if s is None:
            if label == "lind":
                rep.metric("lind: run exit code", rc, False, "0", "issue 57")
            else:
                print(f"  (info) the WCSPH reference run failed (exit code {rc})")
            continue
        runs[label] = scan(out)
        rows, _, sp, pairs = runs[label]
        umax, hmax = rows[:, 1].max(), rows[:, 2].max()
        u_lim = math.sqrt(2 * G * DX)
        shore = rows[:, 3]
        if label == "lind":
            run_metrics(rep, "lind: ", s, m["end"])
            rep.metric("lind: max |u| over the run (m/s)", f"{umax:.3f}", umax <= u_lim,
                       f"<= sqrt(2 g dx) = {u_lim:.3f}", "energy: a free fall over the fill's largest gap (dx)")
            rep.metric("lind: highest fluid particle above max(still level, slope surface)", f"{hmax / DX:.2f} dx",
                       hmax <= 2 * DX, "<= 2 dx (nothing thrown)", "issue 57 (session 26's failure)")
        print(f"  (info) {label}: max |u| {umax:.3f} m/s (at t = {rows[rows[:, 1].argmax(), 0]:.2f} s), "
              f"highest above level/slope {hmax / DX:.2f} dx, at the end u99 {rows[-1, 4]:.3f} m/s, max {sp.max():.3f} m/s; "
              f"shoreline x {shore[0]:.3f} -> {shore.min():.3f} ... {shore.max():.3f} -> {shore[-1]:.3f} m; "
              f"fluid pairs closer than 0.3 dx at the end: {pairs}")

    if runs:
        fig, ax = plt.subplots(1, 3, figsize=(16, 4.2))
        for label, (rows, pts, sp, _) in runs.items():
            ax[0].plot(rows[:, 0], rows[:, 1], label=f"{label}: max |u|")
            ax[0].plot(rows[:, 0], rows[:, 4], "--", label=f"{label}: 99th percentile")
            ax[1].plot(rows[:, 0], rows[:, 2] / DX, label=label)
        ax[0].axhline(math.sqrt(2 * G * DX), color="k", lw=0.8, label="sqrt(2 g dx)")
        ax[0].set_xlabel("t (s)")
        ax[0].set_ylabel("|u| (m/s)")
        ax[0].legend(fontsize=8)
        ax[1].axhline(2.0, color="k", lw=0.8, label="2 dx")
        ax[1].set_xlabel("t (s)")
        ax[1].set_ylabel("highest particle above max(level, slope) / dx")
        ax[1].legend(fontsize=8)
        if "lind" in runs:
            rows, pts, sp, _ = runs["lind"]
            sc = ax[2].scatter(pts[:, 0], pts[:, 1], c=sp, s=4, cmap="viridis")
            fig.colorbar(sc, ax=ax[2], label="|u| (m/s)")
            xx = np.linspace(0.3, 1.3, 50)
            ax[2].plot(xx, bed(xx), "k-", lw=0.8)
            ax[2].axhline(LEVEL, color="b", lw=0.5)
            ax[2].set_xlim(0.5, 1.3)
            ax[2].set_ylim(0.0, 0.06)
            ax[2].set_title(f"lind at t = {rows[-1, 0]:.2f} s (the thin part)")
        fig.tight_layout()
        save_figure(fig, HERE, NAME, a.mode, a.out)

    rep.finish(NAME, a.mode)
    return 0


if __name__ == "__main__":
    sys.exit(main())
