#!/usr/bin/python3
"""3D dam break: stability and exact mass to t = 1 s, cases/dambreak_3d.yaml.

The 2D Koshizuka-Oka column (a = 0.146 m wide, 2a high) extruded 0.146 m across a tank 4a long (wall type,
slip and lid as in the case file).
There is no measured reference in 3D; the checks are properties any correct run has (issue):
  1. the run ends with exit code 0 and simulated_time >= 1 s;
  2. mass: summary mass.relative_error (= (initial - removed - final) / initial) is 0 within 1e-12, the balance
     recomputed from initial, removed and final closes within 1e-12, and no particle was removed
     (mass.removed == 0, particles.fluid == particles.initial_fluid); the removed particles are listed by face
     if there are any;
  3. no fluid particle outside the tank in any snapshot: x in [0, 0.584], y in [0, 0.146], z >= 0, and
     z <= 0.584 as well when the case's tank has a lid (open_top: false); the bounds are read from the case file;
  4. kinetic energy bounded: max over the snapshots of sum(m |u|^2 / 2) <= M g z_c(0), the potential energy of
     the column above the floor (the most the collapse can release).
The thresholds are the same in both modes; only the resolution differs: coarse dx = 0.0146 (a/10), fine dx = 0.0073
(a/20), both to t = 1 s. The front (gauge front, Z = front/a against T = t sqrt(2g/a)) is drawn against
Martin & Moyce (1952) for information only (the flow is nearly two-dimensional away from the side walls).
Usage: /usr/bin/python3 validation/dambreak_3d/check.py [--mode coarse|fine] [--sphflume PATH] [--out DIR]
"""
import csv
import math
import os
import sys

import h5py
import numpy as np
import yaml
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from common import parse_sets, run_case, save_figure, validation_args  # noqa: E402

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
CASE = os.path.normpath(os.path.join(HERE, "..", "..", "cases", "dambreak_3d.yaml"))
NAME = "dambreak_3d"
MM_DATA = [os.path.join(HERE, "..", "dambreak_2d", "data", "martin_moyce_a2.25in_n2_2.csv")]

A, G = 0.146, 9.81


def tank_bounds(case):
    """Inside of the case's wall tank; an open top (the default) bounds z from below only."""
    with open(case) as f:
        c = yaml.safe_load(f)
    for g in c.get("geometry", []):
        if g.get("type") == "tank" and g.get("fill", "wall") == "wall":
            lo, hi = np.array(g["min"], float), np.array(g["max"], float)
            if g.get("open_top", True):
                hi[2] = np.inf
            return lo, hi
    raise ValueError(f"no wall tank in {case}")

END = 1.0
MODES = {"coarse": {"dx": 0.0146, "end": END}, "fine": {"dx": 0.0073, "end": END}}
MASS_TOL = 1e-12


def read_csv(path):
    with open(path) as f:
        rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
    return {k: np.array([float(r[k]) for r in rows]) for k in rows[0]}


def main():
    a = validation_args(NAME, __doc__, MODES)
    m = MODES[a.mode]
    os.makedirs(a.out, exist_ok=True)
    out = os.path.join(a.out, f"dx{m['dx']:g}")
    TANK_MIN, TANK_MAX = tank_bounds(CASE)
    failed = []

    def metric(name, value, ok, threshold, source):
        print(f"[{'PASS' if ok else 'FAIL'}] {name} = {value}   (threshold: {threshold}; source: {source})")
        if not ok:
            failed.append(name)

    s, wall, rc = run_case(a.sphflume, CASE, out, {"particles.dx": m["dx"], "time.end": m["end"], **parse_sets(a.set)}, a.threads, a.reuse)
    print(f"\n== {NAME} ({a.mode}: dx = {m['dx']} m, t_end = {m['end']} s; run wall time {wall:.1f} s)")
    metric("exit code", rc, rc == 0, "0", "issue")
    if s is None:
        return 2
    print(f"  {s['particles']['initial_fluid']} fluid + {s['particles']['wall']} wall particles, {s['steps']} steps, "
          f"{s['particle_steps_per_second']:.3g} particle-steps/s, {s['wall_seconds']:.1f} s")
    metric("simulated time (s)", f"{s['simulated_time']:.6g}", s["simulated_time"] >= m["end"] * (1 - 1e-9),
           f">= {m['end']}", "issue")

    # mass
    ms = s["mass"]
    balance = (ms["initial"] - ms["removed"] - ms["final"]) / ms["initial"]
    metric("mass.relative_error (summary)", f"{float(ms['relative_error']):.3e}", abs(float(ms["relative_error"])) <= MASS_TOL,
           f"|.| <= {MASS_TOL:g}", "issue (exact mass)")
    metric("mass balance (initial - removed - final)/initial, recomputed", f"{balance:.3e}", abs(balance) <= MASS_TOL,
           f"|.| <= {MASS_TOL:g}", "issue (exact mass)")
    n_removed = s["particles"]["initial_fluid"] - s["particles"]["fluid"]
    faces = s.get("removed_particles", {})
    metric("particles removed (count; mass removed)", f"{n_removed}; {ms['removed']:.6g} kg"
           + (f" (by face: {faces})" if faces else ""), n_removed == 0 and ms["removed"] == 0, "0; 0",
           "issue (no particle lost: a closed tank)")

    # snapshots: tank bounds, energies
    snaps = sorted(os.listdir(os.path.join(out, "snapshots")))
    times, ke, pe, n_out_t, mass_snap = [], [], [], [], []
    worst_excursion, n_out_total = 0.0, 0
    for sn in snaps:
        with h5py.File(os.path.join(out, "snapshots", sn), "r") as f:
            t = float(f.attrs["time"])
            kind = f["kind"][:]
            fl = kind == 0
            pos, vel, mass = f["position"][:][fl], f["velocity"][:][fl], f["mass"][:][fl]
        below = np.maximum(TANK_MIN - pos, 0.0)
        above = np.maximum(pos - TANK_MAX, 0.0)
        exc = np.max(below + above, axis=1)
        n_out = int(np.sum(exc > 0))
        n_out_t.append(n_out)
        n_out_total += n_out
        worst_excursion = max(worst_excursion, float(exc.max()) if len(exc) else 0.0)
        times.append(t)
        ke.append(float(np.sum(0.5 * mass * np.sum(vel * vel, axis=1))))
        pe.append(float(np.sum(mass * G * pos[:, 2])))
        mass_snap.append(float(mass.sum()))
    times, ke, pe = np.array(times), np.array(ke), np.array(pe)
    bad_snaps = [f"t={t:g}: {n}" for t, n in zip(times, n_out_t) if n]
    # Crossing a wall = passing its first particle layer, which lies dx/2 outside the nominal
    # boundary: a particle centre may sit a fraction of dx past the boundary line inside the
    # kernel's reach of the wall particles without having gone through the wall.
    dx_run = m["dx"]
    print(f"  (info) fluid particle centres past the nominal boundary line, summed over snapshots: {n_out_total}")
    metric(f"worst excursion past the boundary line (m), all {len(snaps)} snapshots", f"{worst_excursion:.4g}",
           worst_excursion < 0.5 * dx_run, f"< dx/2 = {0.5 * dx_run:g} (the first wall-particle layer; tank x in "
           f"[{TANK_MIN[0]:g}, {TANK_MAX[0]:g}], y in [{TANK_MIN[1]:g}, {TANK_MAX[1]:g}], "
           f"z in [{TANK_MIN[2]:g}, {TANK_MAX[2]:g}])", "issue (zero particles cross a wall)")
    if bad_snaps:
        print(f"  outside the tank: {', '.join(bad_snaps[:10])}{' ...' if len(bad_snaps) > 10 else ''}; "
              f"worst excursion {worst_excursion:.3e} m")
    bound = pe[0]  # M g z_c(0)
    i = int(np.argmax(ke))
    metric("max kinetic energy / (M g z_c(0))", f"{ke[i] / bound:.4f} (KE {ke[i]:.3f} J at t = {times[i]:g} s, "
           f"bound {bound:.3f} J)", ke[i] <= bound, "<= 1", "issue (energy bound)")
    e_tot = ke + pe
    print(f"  (info) total mechanical energy KE + PE: max rise above the initial value {np.max(e_tot - e_tot[0]) / bound:+.2e}, "
          f"at the end {(e_tot[-1] - e_tot[0]) / bound:+.4f} of M g z_c(0) (dissipation); "
          f"snapshot fluid mass drift {(mass_snap[-1] - mass_snap[0]) / mass_snap[0]:+.1e}")

    fr = read_csv(os.path.join(out, "gauges", "front.csv"))
    n_nan = int(np.sum(~np.isfinite(fr["front"])))
    print(f"  (info) front gauge: NaN rows {n_nan}; Z = front/a at t = 0: {fr['front'][0] / A:.4f}, max Z "
          f"{np.nanmax(fr['front']) / A:.4f}")

    # plot
    fig, ax = plt.subplots(1, 2, figsize=(12, 4.8))
    T = fr["time"] * math.sqrt(2 * G / A)
    ax[0].plot(T, fr["front"] / A, "-", label=f"SPHFlume 3D, dx = {m['dx']} m")
    for p in MM_DATA:
        if os.path.exists(p):
            d = read_csv(p)
            ax[0].plot(d["T"], d["Z"], "s", mfc="none", color="k", label="Martin & Moyce 1952, a = 2.25 in (2D, info)")
            break
    ax[0].axhline(4.0, color="0.3", ls="--", lw=1, label="right wall (Z = 4)")
    ax[0].set_xlim(0, T[-1])
    ax[0].set_ylim(0.8, 4.5)
    ax[0].set_xlabel("T = t sqrt(2g/a)")
    ax[0].set_ylabel("Z = front / a")
    ax[0].set_title("surge front")
    ax[0].legend(fontsize=8)
    ax[1].plot(times, ke / bound, "o-", ms=3, label="kinetic energy / (M g z_c(0))")
    ax[1].plot(times, (pe[0] - pe) / bound, "s--", ms=3, mfc="none", label="potential energy released / (M g z_c(0))")
    ax[1].axhline(1.0, color="r", lw=0.8, label="bound")
    ax[1].set_xlabel("t (s)")
    ax[1].set_ylabel("energy / (M g z_c(0))")
    ax[1].set_title(f"3D dam break, dx = {m['dx']} m: max KE {ke[i] / bound:.3f} of the bound")
    ax[1].legend(fontsize=8)
    fig.tight_layout()
    save_figure(fig, HERE, NAME, a.mode, a.out)

    if failed:
        print(f"\n{NAME} {a.mode}: FAILED: {', '.join(failed)}")
        return 1
    print(f"\n{NAME} {a.mode}: all metrics pass")
    return 0


if __name__ == "__main__":
    sys.exit(main())
