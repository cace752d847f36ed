#!/usr/bin/python3
"""Flume A with a fine swash band against the uniform runs (issue 42, check 3; docs/numerics.md §14).

cases/runup_flume_a.yaml (the 1:2.08 beach, a solitary wave of H/h0 given by --ratio) run three ways, one after
the other, on the same threads, to the end validation/runup_flume_a/check.py uses:
  fine     uniform dx/2 (the thesis's d0 = 5 mm with the default dx = 0.01);
  band     dx with level 1 (dx/2) in a band along the beach (`shape: band`, slope geometry.2): 8 cm above its face,
           1 cm into it, from z = 0.15 m (6 cm below the still water) to 0.45 m (above every run-up);
  coarse   uniform dx.
For each: the run-up R/h0 against Li & Raichlen (2001) and against the fine run, wall time, steps, particle counts,
particle-steps per second; the band run's wall time as a ratio to the fine run's. Issue 42's gate for this pair
(5 mm in the band, 10 mm elsewhere): R within 2 % of the uniform 5 mm run's at <= 1/3 of its wall time.
Usage: /usr/bin/python3 bench/resolution_band.py [--sphflume build/sphflume] [--out DIR] [--threads 1]
       [--ratio 0.163] [--dx 0.01] [--reuse]
"""
import argparse
import math
import os
import sys
import tempfile

import numpy as np

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
sys.path.insert(0, os.path.join(ROOT, "validation"))
from common import run_case  # noqa: E402
CASE = os.path.join(ROOT, "cases", "runup_flume_a.yaml")
H0, G, COT = 0.21, 9.81, 2.08
BAND = "{regions: [{shape: band, slope: 2, above: 0.08, below: 0.01, z_min: 0.15, z_max: 0.45, level: 1}]}"


def li_raichlen(r):
    return 2.831 * math.sqrt(COT) * r ** 1.25 + 0.293 * COT ** 1.5 * r ** 2.25


def end_time(r):
    """validation/runup_flume_a/check.py's end: the crest at the toe plus 1.5 s."""
    H = r * H0
    c = math.sqrt(G * (H0 + H))
    beta = math.sqrt(3 * r / (1 + r)) / H0
    return round((7.6 / beta + 2 * r / beta) / c + 2.07 / c + 1.5, 1)


def run(a, tag, sets):
    out = os.path.join(a.out, tag)
    s, wall, rc = run_case(a.sphflume, CASE, out, sets, a.threads, a.reuse)
    if s is None:
        sys.exit(f"{tag} failed ({rc})")
    rows = np.genfromtxt(os.path.join(out, "gauges", "runup.csv"), delimiter=",", names=True)
    return {"R": float(np.nanmax(rows["runup"])) / H0, "wall": wall, "steps": s["steps"],
            "particles": s["particles"]["total"], "fluid": s["particles"]["fluid"],
            "rate": s["particle_steps_per_second"], "levels": s.get("resolution", {}).get("fluid_per_level")}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--sphflume", default=os.environ.get("SPHFLUME", os.path.join(ROOT, "build", "sphflume")))
    ap.add_argument("--out", default=os.path.join(tempfile.gettempdir(), "sphflume-bench", "resolution_band"))
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--ratio", type=float, default=0.163)
    ap.add_argument("--dx", type=float, default=0.01)
    ap.add_argument("--reuse", action="store_true", help="re-read finished runs in --out (validation/common.py run_case)")
    a = ap.parse_args()
    base = {"time.end": end_time(a.ratio), "motions.0.height": a.ratio * H0}
    res = {"fine": run(a, "fine", {**base, "particles.dx": a.dx / 2}),
           "band": run(a, "band", {**base, "particles.dx": a.dx, "resolution": BAND}),
           "coarse": run(a, "coarse", {**base, "particles.dx": a.dx})}
    ref = li_raichlen(a.ratio)
    print(f"Flume A, H/h0 = {a.ratio:g}, to t = {base['time.end']} s, {a.threads} thread(s); Li & Raichlen R/h0 = {ref:.4f}")
    print(f"{'run':8} {'R/h0':>7} {'vs L&R':>8} {'vs fine':>8} {'wall s':>8} {'steps':>7} {'particles':>9} {'M p-steps/s':>11}  fluid per level")
    for tag, v in res.items():
        print(f"{tag:8} {v['R']:7.4f} {100 * (v['R'] / ref - 1):+7.1f}% {100 * (v['R'] / res['fine']['R'] - 1):+7.1f}% "
              f"{v['wall']:8.1f} {v['steps']:7d} {v['particles']:9d} {v['rate'] / 1e6:11.2f}  {v['levels'] or '-'}")
    q = res["band"]["wall"] / res["fine"]["wall"]
    d = res["band"]["R"] / res["fine"]["R"] - 1
    print(f"band / fine: wall time {q:.3f} (gate <= 1/3), run-up {100 * d:+.2f} % (gate within 2 %)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
