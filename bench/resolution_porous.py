#!/usr/bin/python3
"""A permeable 1:2.08 beach with its surface layer refined, against the uniform d0 runs (issue 42, check 5).

cases/runup_permeable_a.yaml (Tsurudome's porous beach, H = 0.03423 m, porous-particle field, h = 2 dx) run two ways
per grain diameter Dc, one after the other, on the same threads, to validation/runup_permeable/check.py's end (4.5 s):
  fine   uniform dx/2 (the thesis's d0 = 5 mm with the default dx = 0.01);
  band   dx with level 1 (dx/2) in a band along the beach's face (`shape: band, porous: 0`): 8 cm above the face (the
         swash), 4 cm into the beach (the porous interface, two level-0 supports), from z = 0.15 m (6 cm below the
         still water) to 0.45 m (above every run-up). Each particle reads the porosity field of its own level's
         porous lattice (docs/numerics.md §14).
--multirate: the band runs sub-cycle the fine level (`multirate: true`, docs/numerics.md §14).
For each: the run-up R (the `runup` gauge's maximum, as the validation), wall and CPU time (summary.json's cpu_seconds), steps and particle counts. Issue 42's
gate: R's fall with Dc (from the first to the last Dc given) as in the uniform d0 runs, at <= 1/2 of their time.
CPU time is the gate's measure: it counts the work a one-thread run did, also where other runs share the cores.
Usage: /usr/bin/python3 bench/resolution_porous.py [--sphflume build/sphflume] [--out DIR] [--threads 1]
       [--dcs 0.25,100] [--dx 0.01] [--reuse]
"""
import argparse
import os
import sys
import tempfile

import numpy as np

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
sys.path.insert(0, os.path.join(ROOT, "validation"))
from common import run_case  # noqa: E402
CASE = os.path.join(ROOT, "cases", "runup_permeable_a.yaml")
END, H = 4.5, 0.03423
BAND = "{regions: [{shape: band, porous: 0, above: 0.08, below: 0.04, z_min: 0.15, z_max: 0.45, level: 1}]}"


def run(a, tag, sets):
    out = os.path.join(a.out, tag)
    s, wall, rc = run_case(a.sphflume, CASE, out, sets, a.threads, a.reuse)
    if s is None:
        sys.exit(f"{tag} failed ({rc})")
    cpu = s.get("cpu_seconds", float("nan"))  # (summary.json: the time loop's CPU seconds)
    rows = np.genfromtxt(os.path.join(out, "gauges", "runup.csv"), delimiter=",", names=True)
    return {"R": float(np.nanmax(rows["runup"])), "wall": wall, "cpu": cpu, "steps": s["steps"],
            "particles": s["particles"]["total"], "levels": s.get("resolution", {}).get("fluid_per_level")}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--sphflume", default=os.environ.get("SPHFLUME", os.path.join(ROOT, "build", "sphflume")))
    ap.add_argument("--out", default=os.path.join(tempfile.gettempdir(), "sphflume-bench", "resolution_porous"))
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--dcs", default="0.25,100", help="grain diameters in mm, comma-separated (the fall: first to last)")
    ap.add_argument("--dx", type=float, default=0.01)
    ap.add_argument("--multirate", action="store_true", help="the band runs with `multirate: true` (folder band_mr)")
    ap.add_argument("--reuse", action="store_true", help="re-read finished runs in --out (validation/common.py run_case)")
    a = ap.parse_args()
    dcs = [float(v) for v in a.dcs.split(",")]
    res = {}
    for dc in dcs:
        base = {"time.end": END, "motions.0.height": H, "porous.regions.0.diameter": dc / 1000}
        res[dc] = {"fine": run(a, f"dc{dc:g}/fine", {**base, "particles.dx": a.dx / 2}),
                   "band": run(a, f"dc{dc:g}/band_mr" if a.multirate else f"dc{dc:g}/band",
                               {**base, "particles.dx": a.dx, "resolution": BAND[:-1] + ", multirate: true}" if a.multirate else BAND})}
    print(f"permeable 1:2.08 beach, H = {H} m, to t = {END} s, {a.threads} thread(s); fine dx = {a.dx / 2:g}, band {a.dx:g} + {a.dx / 2:g}")
    print(f"{'Dc mm':>6} {'run':5} {'R mm':>6} {'vs fine':>8} {'wall s':>8} {'cpu s':>8} {'steps':>7} {'particles':>9}  fluid per level")
    for dc, r in res.items():
        for tag, v in r.items():
            print(f"{dc:6g} {tag:5} {1000 * v['R']:6.1f} {100 * (v['R'] / r['fine']['R'] - 1):+7.1f}% {v['wall']:8.1f} "
                  f"{v['cpu']:8.1f} {v['steps']:7d} {v['particles']:9d}  {v['levels'] or '-'}")
    cpu_f = sum(r["fine"]["cpu"] for r in res.values())
    cpu_b = sum(r["band"]["cpu"] for r in res.values())
    wall_f = sum(r["fine"]["wall"] for r in res.values())
    wall_b = sum(r["band"]["wall"] for r in res.values())
    print(f"band / fine: CPU time {cpu_b / cpu_f:.3f} (gate <= 1/2), wall time {wall_b / wall_f:.3f}")
    if len(dcs) > 1:
        lo, hi = dcs[0], dcs[-1]
        ff = res[lo]["fine"]["R"] - res[hi]["fine"]["R"]
        fb = res[lo]["band"]["R"] - res[hi]["band"]["R"]
        print(f"R's fall from Dc = {lo:g} to {hi:g} mm: fine {1000 * ff:.1f} mm ({100 * ff / res[lo]['fine']['R']:.1f} %), "
              f"band {1000 * fb:.1f} mm ({100 * fb / res[lo]['band']['R']:.1f} %); band's R falls at every step: "
              f"{all(res[dcs[i]]['band']['R'] > res[dcs[i + 1]]['band']['R'] for i in range(len(dcs) - 1))}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
