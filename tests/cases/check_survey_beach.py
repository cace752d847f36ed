#!/usr/bin/python3
"""cases/runup_flume_a_survey.yaml against cases/runup_flume_a.yaml (issue 43: a beach from a survey CSV).

The same solitary wave runs up Flume A's 1:2.08 beach typed as a slope (toe, gradient, top) and read from a survey
line (runup_flume_a_survey.csv: points every 0.05 m of chainage, elevations to 0.1 mm). The run-up R (the `runup`
gauge's maximum) of one run moves by more than 1 % under shifts far below dx: the typed slope's toe moved by the
survey's rounding, +-0.05 mm, moves R/h0 by +-2.1 % at dx = 0.01 and up to 5 % at dx = 0.02 (the swash tongue's
tip is one particle thick). So the survey is judged against that band: the typed slope is run with its toe at
x0 - 0.05 mm, x0 and x0 + 0.05 mm, and the survey's R must lie within their range widened by 1 % of their mean.
With --ensemble K, both beaches are also run shifted along x by -K..K x 0.05 mm (2K + 1 runs each: the survey's
points moved, the typed slope's toe moved) and the means of their R must agree within 1 %.
Usage: check_survey_beach.py SPHFLUME WORKDIR [DX] [--ensemble K]   (DX 0.02 in CTest; the cases' own is 0.01)
"""
import csv
import os
import shutil
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", ".."))
args = [a for a in sys.argv[1:]]
ensemble = 0
if "--ensemble" in args:
    k = args.index("--ensemble")
    ensemble = int(args[k + 1])
    del args[k:k + 2]
binary, work = args[0], args[1]
dx = args[2] if len(args) > 2 else "0.02"
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
sys.path.insert(0, os.path.join(HERE, "..", "robustness"))
from common import check, finish  # noqa: E402


def runup(name, extra=(), tag="", case=None):
    out = os.path.join(work, name + tag)
    p = subprocess.run([binary, "run", case or os.path.join(ROOT, "cases", name + ".yaml"), "-o", out, "-q", "--set", "time.snapshot_interval=100",
                        "--threads", "1", "--set", f"particles.dx={dx}"] + list(extra), capture_output=True, text=True)
    check(p.returncode == 0, f"{name} at dx = {dx} ends normally (exit {p.returncode}: {(p.stdout + p.stderr).strip()[-160:]})")
    if p.returncode != 0:
        return float("nan")
    with open(os.path.join(out, "gauges", "runup.csv")) as f:
        rows = [r for r in csv.reader(f) if r and not r[0].startswith("#")]
    col = rows[0].index("runup") if "runup" in rows[0] else 1
    vals = [float(r[col]) for r in rows[1:] if r[col] not in ("", "nan")]
    return max(vals) if vals else float("nan")


h0 = 0.21
# the four runs side by side, one thread each (a run's bits do not depend on its thread count), as many at once as
# this process may use cores
with ThreadPoolExecutor(max(1, len(os.sched_getaffinity(0)))) as ex:
    jobs = [ex.submit(runup, "runup_flume_a", ["--set", f"geometry.2.toe=[{x0:.5f}, 0.0]"], f"_{x0:.5f}")
            for x0 in (2.06995, 2.07, 2.07005)] + [ex.submit(runup, "runup_flume_a_survey")]
    *typed, survey = [j.result() for j in jobs]
lo, hi, mean = min(typed), max(typed), sum(typed) / len(typed)
print(f"run-up R/h0: typed slope {typed[1] / h0:.4f} (toe -0.05 mm {typed[0] / h0:.4f}, +0.05 mm {typed[2] / h0:.4f}), "
      f"survey line {survey / h0:.4f} ({100 * (survey - typed[1]) / typed[1]:+.2f} % of the typed slope's)")
check(lo - 0.01 * mean <= survey <= hi + 0.01 * mean,
      f"the survey beach's run-up lies within the typed slope's band under +-0.05 mm toe shifts, +-1 % "
      f"([{(lo - 0.01 * mean) / h0:.4f}, {(hi + 0.01 * mean) / h0:.4f}] R/h0)")
if ensemble > 0:  # both beaches shifted by the same sub-resolution steps: the means of R
    src = os.path.join(ROOT, "cases", "runup_flume_a_survey.csv")
    with open(src) as f:
        lines = f.read().splitlines()
    ts, ss = [], []
    for k in range(-ensemble, ensemble + 1):
        d = 5e-5 * k
        ts.append(runup("runup_flume_a", ["--set", f"geometry.2.toe=[{2.07 + d:.6f}, 0.0]"], f"_e{k}"))
        csv_k = os.path.join(work, f"survey_{k}.csv")
        with open(csv_k, "w") as f:
            for ln in lines:
                parts = ln.split(",")
                try:
                    f.write(f"{float(parts[0]) + d:.6f},{parts[1]}\n")
                except ValueError:
                    f.write(ln + "\n")
        case_k = os.path.join(work, f"survey_{k}.yaml")
        with open(os.path.join(ROOT, "cases", "runup_flume_a_survey.yaml")) as f:
            text = f.read().replace("runup_flume_a_survey.csv", csv_k)
        with open(case_k, "w") as f:
            f.write(text)
        ss.append(runup("runup_flume_a_survey", tag=f"_e{k}", case=case_k))
    mt, ms = sum(ts) / len(ts), sum(ss) / len(ss)
    sd = lambda v, m: (sum((x - m) ** 2 for x in v) / (len(v) - 1)) ** 0.5
    print("shift [mm] " + " ".join(f"{0.05 * k:+.2f}" for k in range(-ensemble, ensemble + 1)))
    print("typed R/h0 " + " ".join(f"{x / h0:.4f}" for x in ts))
    print("survey R/h0 " + " ".join(f"{x / h0:.4f}" for x in ss))
    print(f"means: typed {mt / h0:.4f} (sd {sd(ts, mt) / h0:.4f}), survey {ms / h0:.4f} (sd {sd(ss, ms) / h0:.4f})")
    check(abs(ms - mt) <= 0.01 * mt, f"the ensemble means of R agree within 1 % ({100 * (ms - mt) / mt:+.2f} %, "
          f"{len(ts)} runs each)")
finish("check_survey_beach")
