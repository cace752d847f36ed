#!/usr/bin/python3
"""The 3D dam break against the STL obstacle, refined around the obstacle, against the uniform fine run (issue 58,
"3D regions"; docs/numerics.md §14).

cases/dambreak_3d_obstacle.yaml run two ways (--runs picks some), one after the other, on the same threads, to
--end (1.0 s: the surge reaches the obstacle at about 0.4 s, hits it and runs round and over it):
  fine     uniform --dx (default 0.02, the case's);
  refined  2 dx with level 1 (dx) inside the obstacle's STL surface and within --margin of it (`shape: mesh`), the
           fine level sub-cycled (`multirate: true`);
  coarse   uniform 2 dx.
For each: the pressure force on the obstacle's face towards the water (gauge F_obstacle) and the water level in front
of it (level_front, 0.125 m upstream of the face), sampled every 5 ms: the surge's arrival (the force first above
50 N), the means over t = 0.4 s to the end (the impact and after) and over 0.6 s to the end (after it), the force's
peak; wall and
CPU time (summary.json's cpu_seconds), steps, particle counts. Issue 58's gate: the force and the level within 5 % of
the uniform fine run's at <= 1/2 of its time.
Usage: /usr/bin/python3 bench/resolution_obstacle.py [--sphflume build/sphflume] [--out DIR] [--threads 2]
       [--dx 0.02] [--margin 0.1] [--end 1.0] [--runs fine,refined,coarse] [--reuse]
"""
import argparse
import os
import sys
import tempfile

import numpy as np

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
sys.path.insert(0, os.path.join(ROOT, "validation"))
from common import run_case  # noqa: E402

CASE = os.path.join(ROOT, "cases", "dambreak_3d_obstacle.yaml")
REGION = ("{{regions: [{{shape: mesh, file: kleefsman_obstacle.stl, units: mm, offset: [0.6635, 0.295, 0.0], "
          "margin: {margin}, level: 1}}], multirate: true}}")
T0 = 0.4  # the window's start: the surge's arrival at the obstacle
T1 = 0.6  # the second window's: after the impact (the flow round and over the obstacle)


def gauge(out, name):
    rows = np.genfromtxt(os.path.join(out, "gauges", f"{name}.csv"), delimiter=",", names=True)
    return rows[rows.dtype.names[0]], rows[rows.dtype.names[1]]


def run(a, tag, sets):
    out = os.path.join(a.out, tag)
    s, wall, rc = run_case(a.sphflume, CASE, out, sets, a.threads, a.reuse)
    if s is None:
        sys.exit(f"{tag} failed ({rc})")
    t, F = gauge(out, "F_obstacle")
    tl, lev = gauge(out, "level_front")
    w, wl = t >= T0 - 1e-9, tl >= T0 - 1e-9
    w2, wl2 = t >= T1 - 1e-9, tl >= T1 - 1e-9
    return {"F": float(np.mean(F[w])), "Fpeak": float(np.max(F[w])), "level": float(np.nanmean(lev[wl])),
            "F2": float(np.mean(F[w2])), "level2": float(np.nanmean(lev[wl2])), "arrival": float(t[np.argmax(F > 50.0)]),
            "wall": wall, "cpu": s.get("cpu_seconds", float("nan")), "steps": s["steps"],
            "particles": s["particles"]["total"], "fluid": s["particles"]["fluid"],
            "walls": s["particles"]["wall"], "mass": s["mass"]["relative_error"]}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--sphflume", default=os.environ.get("SPHFLUME", os.path.join(ROOT, "build", "sphflume")))
    ap.add_argument("--out", default=os.path.join(tempfile.gettempdir(), "sphflume-bench", "resolution_obstacle"))
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--dx", type=float, default=0.02, help="the fine spacing (the refined run's level 1)")
    ap.add_argument("--margin", type=float, default=0.1, help="the refined shell's width about the obstacle [m]")
    ap.add_argument("--end", type=float, default=1.0)
    ap.add_argument("--runs", default="fine,refined")
    ap.add_argument("--reuse", action="store_true", help="re-read finished runs in --out (validation/common.py run_case)")
    a = ap.parse_args()
    a.out = os.path.join(a.out, f"dx{a.dx:g}_m{a.margin:g}")
    base = {"time.end": a.end, "time.output_interval": 0.005, "time.snapshot_interval": 0.1}  # (the gauges every 5 ms)
    sets = {"fine": {**base, "particles.dx": a.dx},
            "refined": {**base, "particles.dx": 2 * a.dx, "resolution": REGION.format(margin=a.margin)},
            "coarse": {**base, "particles.dx": 2 * a.dx}}
    res = {tag: run(a, tag, sets[tag]) for tag in ("fine", "refined", "coarse") if tag in a.runs.split(",")}
    print(f"3D obstacle dam break, fine dx = {a.dx:g} m, shell margin {a.margin:g} m, to t = {a.end:g} s, "
          f"{a.threads} thread(s); means over t >= {T0} s")
    print(f"{'run':8} {'arrival':>7} {'F mean N':>9} {'F peak N':>9} {'level m':>8} {'F >=T1':>8} {'lvl >=T1':>8} "
          f"{'wall s':>8} {'cpu s':>8} {'steps':>6} {'fluid':>8} {'walls':>8} {'mass err':>9}")
    for tag, v in res.items():
        print(f"{tag:8} {v['arrival']:7.3f} {v['F']:9.2f} {v['Fpeak']:9.1f} {v['level']:8.4f} {v['F2']:8.2f} "
              f"{v['level2']:8.4f} {v['wall']:8.1f} {v['cpu']:8.1f} {v['steps']:6d} {v['fluid']:8d} {v['walls']:8d} "
              f"{v['mass']:9.1e}")
    for tag in ("refined", "coarse"):
        if "fine" in res and tag in res:
            f, r = res["fine"], res[tag]
            d = {k: 100 * (r[k] / f[k] - 1) for k in ("F", "Fpeak", "level", "F2", "level2")}
            print(f"{tag} / fine: from {T0} s force {d['F']:+.2f} %, peak {d['Fpeak']:+.1f} %, level {d['level']:+.2f} %; "
                  f"from {T1} s force {d['F2']:+.2f} %, level {d['level2']:+.2f} % (gate: within 5 %); arrival "
                  f"{r['arrival'] - f['arrival']:+.3f} s; wall time {r['wall'] / f['wall']:.3f}, CPU time "
                  f"{r['cpu'] / f['cpu']:.3f} (gate <= 1/2)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
