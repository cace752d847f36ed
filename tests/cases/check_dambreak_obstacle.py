#!/usr/bin/python3
"""cases/dambreak_3d_obstacle.yaml, coarse (issue 43: a 3D dam break against an STL obstacle).

The obstacle is read from cases/kleefsman_obstacle.stl (mm, offset into place). Checks, on a coarse run:
- the obstacle's wall particles are where the mesh is: all inside its box [0.6635, 0.8245] x [0.295, 0.698] x
  [0, 0.161], within the wall layers of its surface, and its surface covered (a face of 0.161 x 0.403 m holds
  about (0.161/dx)(0.403/dx) particles in each layer);
- no fluid particle ever enters the obstacle (deeper than dx/2 inside its box) in any snapshot;
- the water reaches it: the pressure on the face towards the water rises above 0.5 rho g H after the front
  arrives (the front leaves x = 2.0 m at t = 0 and runs at most 2 sqrt(g H): t > (2.0 - 0.8245) / 4.65 s);
- mass is exact (no particle lost).
Usage: check_dambreak_obstacle.py SPHFLUME WORKDIR
"""
import csv
import json
import os
import shutil
import subprocess
import sys

import h5py
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", ".."))
binary, work = sys.argv[1], sys.argv[2]
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
sys.path.insert(0, os.path.join(HERE, "..", "robustness"))
from common import check, finish  # noqa: E402


dx, H, rho, g = 0.05, 0.55, 1000.0, 9.81
case = os.path.join(ROOT, "cases", "dambreak_3d_obstacle.yaml")
p = subprocess.run([binary, "run", case, "-o", work, "-q", "--threads", "2", "--set", f"particles.dx={dx}",
                    "--set", "time.end=0.6", "--set", "time.output_interval=0.05"], capture_output=True, text=True)
check(p.returncode == 0, f"the coarse run ends normally (exit {p.returncode}: {(p.stdout + p.stderr).strip()[-200:]})")
if p.returncode != 0:
    sys.exit(1)
lo, hi = np.array([0.6635, 0.295, 0.0]), np.array([0.8245, 0.698, 0.161])
snaps = sorted(f for f in os.listdir(os.path.join(work, "snapshots")) if f.endswith(".h5"))
with h5py.File(os.path.join(work, "snapshots", snaps[0]), "r") as f:
    x, kind = f["position"][:], f["kind"][:]
walls = x[kind == 1]
obstacle = walls[np.all((walls > lo - 1e-9) & (walls < hi + 1e-9), axis=1) & (walls[:, 2] > 0.0)]
depth = np.min(np.concatenate([obstacle - lo, hi - obstacle], axis=1), axis=1)  # from the nearest face
face = (0.161 / dx) * (0.403 / dx)
check(len(obstacle) >= face, f"the obstacle's wall particles are there ({len(obstacle)}, one face holds ~{face:.0f} per layer)")
check(len(obstacle) > 0 and np.all(depth < 3 * dx), "they lie in the wall layers under its surface (< 3 dx deep)")
deepest = 0.0
for s in snaps:
    with h5py.File(os.path.join(work, "snapshots", s), "r") as f:
        xs, ks = f["position"][:], f["kind"][:]
    fl = xs[ks == 0]
    inside = np.all((fl > lo + 0.5 * dx) & (fl < hi - 0.5 * dx), axis=1)
    deepest = max(deepest, float(np.sum(inside)))
check(deepest == 0, f"no fluid particle inside the obstacle in any of {len(snaps)} snapshots")
with open(os.path.join(work, "gauges", "obstacle_face.csv")) as f:
    rows = [r for r in csv.reader(f) if r and not r[0].startswith("#")]
t = np.array([float(r[0]) for r in rows[1:]])
pf = np.array([float(r[1]) if r[1] not in ("", "nan") else np.nan for r in rows[1:]])
arrive = (2.0 - 0.8245) / (2.0 * np.sqrt(g * H))
hit = t[np.nan_to_num(pf) > 0.5 * rho * g * H]
check(len(hit) > 0 and hit[0] >= arrive,
      f"the water hits the obstacle's face (p > 0.5 rho g H first at t = {hit[0] if len(hit) else float('nan'):.2f} s; "
      f"the front cannot arrive before {arrive:.2f} s)")
summary = json.load(open(os.path.join(work, "summary.json")))
err = summary["mass"]["relative_error"]
check(summary["exit_status"] == "done" and abs(err) < 1e-12, f"done, mass exact (relative error {err})")
finish("check_dambreak_obstacle")
