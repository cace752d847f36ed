#!/usr/bin/python3
"""Soak run: the sloshing tank (cases/sloshing_soak.yaml) for about 10^6 steps.

Water 0.25 m deep on average in a closed 0.5 m x 0.5 m tank, surface released from a tilt of A = 0.05 m at the
walls; it sloshes and decays. Nothing enters or leaves, so over any number of steps:
  1. the run ends normally (exit 0) after the expected number of steps (fine: >= 10^6);
  2. mass: no particle removed, fluid count constant, the fluid mass of every snapshot equal to the initial one
     (|drift| <= 1e-12 relative: particle masses are constant, so only summation order could change it);
  3. no particle crosses a wall: the worst excursion of a fluid particle centre past the tank's inner boundary,
     over all snapshots, stays below dx/2 (the first wall-particle layer);
  4. energy is bounded: the kinetic energy never exceeds the energy released by the tilted surface,
     E_avail = rho g A^2 L / 6 (linear tilt eta = A (1 - 2x/L), E = rho g/2 int eta^2 dx), and the total
     mechanical energy never rises above its initial value by more than 5 % of E_avail (the scheme dissipates);
     the kinetic energy of the last tenth of the run is below its maximum over the first second.
Modes: coarse (CI) t_end = 3 s (about 2 x 10^4 steps); fine t_end = 170 s (about 1.1 x 10^6 steps).
Usage: /usr/bin/python3 validation/soak/check.py [--mode coarse|fine] [--sphflume PATH] [--out DIR]
"""
import glob
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
CASE = os.path.normpath(os.path.join(HERE, "..", "..", "cases", "sloshing_soak.yaml"))
NAME = "soak"
RHO, G, A, L = 1000.0, 9.81, 0.05, 0.5
TANK = ((0.0, 0.5), (0.0, 0.5))  # inner boundary, x and z
E_AVAIL = RHO * G * A * A * L / 6.0
MODES = {"coarse": {"dx": 0.0125, "end": 3.0, "min_steps": 15000},
         "fine": {"dx": 0.0125, "end": 170.0, "min_steps": 1000000}}



def main():
    a = validation_args(NAME, __doc__, MODES)
    rep = Report()
    m = MODES[a.mode]
    out = os.path.join(a.out, f"dx{m['dx']}_t{m['end']:g}")
    s, wall, rc = run_case(a.sphflume, CASE, out, {"particles.dx": m["dx"], "time.end": m["end"], **parse_sets(a.set)},
                           a.threads, a.reuse)
    print(f"\n== {NAME} ({a.mode}: dx = {m['dx']} m, t_end = {m['end']} s)")
    rep.metric("exit code", rc, rc == 0, "0", "issue")
    if s is None:
        sys.exit(2)
    steps = s.get("total_steps", s["steps"])
    rep.metric("steps", steps, steps >= m["min_steps"], f">= {m['min_steps']}", "issue (about 10^6 steps; CI: a short version)")
    print(f"  {s['particles']['fluid']} fluid + {s['particles']['wall']} wall particles, {wall:.0f} s wall, "
          f"{s['particle_steps_per_second'] / 1e6:.2f} M particle-steps/s")

    # mass
    rep.metric("fluid particles at the end / at the start; removed", f"{s['particles']['fluid']} / {s['particles']['initial_fluid']}; "
           f"{s.get('removed_particles_total', 0)}", s["particles"]["fluid"] == s["particles"]["initial_fluid"] and s.get("removed_particles_total", 0) == 0, "equal; 0", "issue (closed tank)")
    snaps = sorted(glob.glob(os.path.join(out, "snapshots", "snap_*.h5")))
    m0 = s["mass"]["initial"]
    drift, worst, worst_t = 0.0, -1e9, 0.0
    t_s = []
    for f in snaps:
        with h5py.File(f, "r") as h:
            k = h["kind"][:] == 0
            x = h["position"][:][k]
            t = float(h.attrs["time"])
            drift = max(drift, abs(h["mass"][:][k].sum() - m0) / m0)
            exc = max(TANK[0][0] - x[:, 0].min(), x[:, 0].max() - TANK[0][1],
                      TANK[1][0] - x[:, 2].min(), x[:, 2].max() - TANK[1][1])
            if exc > worst:
                worst, worst_t = exc, t
            t_s.append(t)
    rep.metric("fluid mass drift over the snapshots (max |m - m0| / m0)", f"{drift:.1e} (summary: {s['mass']['relative_error']:.1e})", drift <= 1e-12 and abs(s["mass"]["relative_error"]) <= 1e-12, "<= 1e-12", "issue (no drift of the total mass)")
    rep.metric("worst excursion past the tank's inner boundary (m)", f"{worst:.5f} at t = {worst_t:g} s", worst < m["dx"] / 2, f"< dx/2 = {m['dx'] / 2}", "issue (no particle crosses a wall)")

    # energy
    e = np.genfromtxt(os.path.join(out, "gauges", "energy.csv"), delimiter=",", names=True)
    t, ke, tot = e["time"], e["kinetic"], e["total"]
    rise = float(np.max(tot - tot[0]))
    rep.metric("max kinetic energy (J/m)", f"{ke.max():.4f} at t = {t[np.argmax(ke)]:g} s", ke.max() <= E_AVAIL, f"<= E_avail = rho g A^2 L / 6 = {E_AVAIL:.4f}", "energy bound (linear tilt)")
    rep.metric("max rise of the total mechanical energy above its initial value (J/m)", f"{rise:.2e}", rise <= 0.05 * E_AVAIL, f"<= 0.05 E_avail = {0.05 * E_AVAIL:.4f}", "energy bound (dissipative scheme)")
    late = ke[t >= 0.9 * t[-1]].max()
    early = ke[t <= 1.0].max()
    rep.metric("max kinetic energy over the last tenth of the run (J/m)", f"{late:.2e}", late <= early, f"<= max over the first second = {early:.4f}", "bounded kinetic energy")
    print(f"  (info) energy dissipated by the end: {tot[0] - tot[-1]:.4f} J/m = {(tot[0] - tot[-1]) / E_AVAIL:.2f} E_avail")

    fig, ax = plt.subplots(2, 1, figsize=(8, 6), sharex=True)
    ax[0].semilogy(t, np.maximum(ke, 1e-12), label="kinetic energy")
    ax[0].axhline(E_AVAIL, color="k", ls="--", label="E_avail (bound)")
    ax[0].set_ylabel("J/m")
    ax[0].legend()
    ax[0].set_title(f"Sloshing soak, dx = {m['dx']} m, {steps} steps, {s['particles']['fluid']} fluid particles")
    ax[1].plot(t, tot - tot[0], label="total mechanical energy - initial")
    ax[1].axhline(0.05 * E_AVAIL, color="r", ls=":", label="threshold of rise")
    ax[1].set_xlabel("t (s)")
    ax[1].set_ylabel("J/m")
    ax[1].legend()
    fig.tight_layout()
    save_figure(fig, HERE, NAME, a.mode, a.out)
    rep.finish(NAME, a.mode)


if __name__ == "__main__":
    main()
