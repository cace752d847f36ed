#!/usr/bin/python3
"""The dual integrator's wall pressure against the Verlet scheme's, converged in dp (issue 40, decision 8).

cases/dambreak_sphinxsys.yaml (2D, H = 1, g = 1: times in sqrt(H/g), pressures in rho g H) run by both integrators
at dp = 0.025, 0.0125, 0.00625 to t = 7, gauges every 0.01. From the wall sensor (p_sensor: a 0.03 face at
(5.366, 0.2), its 0.02 window's mean):
  impact      the first time its mean exceeds 0.2 rho g H and stays above for 0.05;
  post-mean   its mean over t in [2.8, 7] (bench/vs_sphinxsys.py's window).
The decision's gate: the dual scheme's impact time and post-impact mean within 0.05 and 5 % of the converged Verlet
values (the finest dp), or the reason they differ. Verlet: scheme.integrator=verlet at cfl 0.2 (the case's other
settings: inviscid, dummy free-slip walls; the Verlet scheme's own defaults otherwise).
Usage: /usr/bin/python3 bench/dual_vs_verlet.py [--sphflume build/sphflume] [--out DIR] [--threads 2] [--reuse]
       [--dps 0.025,0.0125,0.00625]
"""
import argparse
import json
import os
import subprocess
import sys
import time

import numpy as np

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
CASE = os.path.join(ROOT, "cases", "dambreak_sphinxsys.yaml")
SCHEMES = {"dual": [], "verlet": ["--set", "scheme.integrator=verlet", "--set", "scheme.cfl=0.2"]}


def run(a, scheme, dp):
    out = os.path.join(a.out, f"{scheme}_dp{dp}")
    summ = os.path.join(out, "summary.json")
    if not (a.reuse and os.path.exists(summ)):
        cmd = [a.sphflume, "run", CASE, "-o", out, "-q", "--threads", str(a.threads), "--set", f"particles.dx={dp}",
               "--set", "time.end=7", "--set", "time.output_interval=0.01", "--set", "time.snapshot_interval=7"]
        t0 = time.time()
        r = subprocess.run(cmd + SCHEMES[scheme], capture_output=True, text=True)
        if r.returncode != 0:
            sys.exit(f"{scheme} at dp = {dp} failed ({r.returncode}): {(r.stdout + r.stderr)[-600:]}")
        print(f"  {scheme} dp = {dp}: {time.time() - t0:.0f} s", flush=True)
    s = json.load(open(summ))
    q = np.genfromtxt(os.path.join(out, "gauges", "p_sensor.csv"), delimiter=",", names=True)
    t, p = q["time"], np.nan_to_num(q["pressure"])
    above = p > 0.2
    impact = float("nan")
    for i in np.nonzero(above)[0]:
        hold = (t >= t[i]) & (t <= t[i] + 0.05)
        if above[hold].all():
            impact = float(t[i])
            break
    win = (t >= 2.8) & (t <= 7.0)
    return dict(impact=impact, post=float(p[win].mean()), sd=float(p[win].std()), steps=int(s["steps"]),
                wall=float(s["wall_seconds"]))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sphflume", default=os.environ.get("SPHFLUME", os.path.join(ROOT, "build", "sphflume")))
    ap.add_argument("--out", default=os.path.join(os.environ.get("TMPDIR", "/tmp"), "sphflume-dual-vs-verlet"))
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--reuse", action="store_true")
    ap.add_argument("--dps", default="0.025,0.0125,0.00625")
    a = ap.parse_args()
    dps = [float(x) for x in a.dps.split(",")]
    res = {(s, dp): run(a, s, dp) for dp in dps for s in SCHEMES}
    print("| dp | scheme | impact (sustained > 0.2) | post-impact mean ± sd, t = 2.8-7 | steps | wall s |")
    print("|---|---|---|---|---|---|")
    for dp in dps:
        for s in SCHEMES:
            r = res[(s, dp)]
            print(f"| {dp} | {s} | {r['impact']:.2f} | {r['post']:.3f} ± {r['sd']:.3f} | {r['steps']} | {r['wall']:.0f} |")
    ref = res[("verlet", dps[-1])]
    fails = 0
    for dp in dps:
        d = res[("dual", dp)]
        dt, dm = d["impact"] - ref["impact"], (d["post"] - ref["post"]) / ref["post"]
        ok = abs(dt) <= 0.05 and abs(dm) <= 0.05
        fails += 0 if ok or dp != dps[-1] else 1
        print(f"dual at dp = {dp} against Verlet at dp = {dps[-1]}: impact {dt:+.2f} (gate 0.05), post-impact mean "
              f"{100 * dm:+.1f} % (gate 5 %){'' if dp != dps[-1] else ('  PASS' if ok else '  FAIL')}")
    return 1 if fails else 0


if __name__ == "__main__":
    sys.exit(main())
