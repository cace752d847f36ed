#!/usr/bin/python3
"""Flume A or B with a fine swash band against the uniform runs (issue 42, checks 3 and 4; docs/numerics.md §14).

cases/runup_flume_a.yaml (the 1:2.08 beach; --flume a) or cases/runup_flume_b.yaml (the 1:20 beach, breaking;
--flume b), a solitary wave of H/h0 given by --ratio, run three ways (--runs picks some), one after the other, on
the same threads, to the end validation/runup_flume_a/check.py (or runup_flume_b/check.py) uses:
  fine     uniform dx/2 (the thesis's d0 = 5 mm with the default dx = 0.01);
  band     dx with level 1 (dx/2) in a band along the beach (`shape: band`, slope geometry.2): 8 cm above its face,
           1 cm into it, from z = 0.15 m (6 cm below the still water) to the slope's top (above every run-up);
  follow   the same band, its elevations following the waterline (`follow: waterline`: from 6 cm below the
           waterline to 5 cm above it);
  band_mr, follow_mr  the same with `multirate: true` (the fine level sub-cycled at half the coarse step);
  coarse   uniform dx.
For each: the run-up R/h0 against Li & Raichlen (2001; Flume A) or Synolakis (1986, breaking; Flume B) and against
the fine run, wall and CPU time (summary.json's cpu_seconds), steps, particle
counts, particle-steps per second; the band run's time as a ratio to the fine run's. Issue 42's gates: Flume A
(5 mm in the band, 10 mm elsewhere): R within 2 % of the uniform 5 mm run's at <= 1/3 of its wall time; Flume B at
H/h0 = 0.28: R within 10 % of Synolakis at <= 1/3 of the uniform 5 mm run's wall time.
--repeat N runs the chosen runs N times in turn (fine, band, fine, band, ...; the repeats into OUT/TAG_rK) and gives
each refined run's time ratio to the fine run of the same round, and their median: on a VM whose speed drifts by
±10 % between identical runs one pair measures the ratio to about ±15 % (bench/README.md, session 45); R is the
first round's (the runs are deterministic: every round gives the same gauges).
Usage: /usr/bin/python3 bench/resolution_band.py [--sphflume build/sphflume] [--out DIR] [--threads 1] [--flume a]
       [--ratio 0.163] [--dx 0.01] [--runs fine,band,coarse] [--end T] [--reuse] [--cells level0|finest] [--repeat N]
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
H0, G, COT = 0.21, 9.81, 2.08
BAND = "{{regions: [{{shape: band, slope: 2, above: 0.08, below: 0.01, z_min: 0.15, z_max: {top}, level: 1}}]}}"
# --follow: the band's elevations follow the waterline (6 cm below it to 5 cm above), within the fixed band's
FOLLOW = ("{{regions: [{{shape: band, slope: 2, above: 0.08, below: 0.01, z_min: 0.15, z_max: {top}, follow: waterline, "
          "waterline_below: 0.06, waterline_above: 0.05, level: 1}}]}}")


def li_raichlen(r):
    return 2.831 * math.sqrt(COT) * r ** 1.25 + 0.293 * COT ** 1.5 * r ** 2.25


def synolakis_breaking(r):
    """validation/runup_flume_b/check.py's reference."""
    return 1.109 * r ** 0.582


def end_time(r):
    """validation/runup_flume_a/check.py's end: the crest at the toe plus 1.5 s."""
    H = r * H0
    c = math.sqrt(G * (H0 + H))
    beta = math.sqrt(3 * r / (1 + r)) / H0
    return round((7.6 / beta + 2 * r / beta) / c + 2.07 / c + 1.5, 1)


# per flume: the case, the reference R/h0, the end time (each validation check's), the band's top
FLUMES = {"a": {"case": "runup_flume_a.yaml", "ref": li_raichlen, "ref_name": "Li & Raichlen", "end": end_time, "top": 0.45},
          "b": {"case": "runup_flume_b.yaml", "ref": synolakis_breaking, "ref_name": "Synolakis", "end": lambda r: 11.0,
                "top": 0.40}}


def multirate(res):
    """The same regions with `multirate: true` (the finest level sub-cycled, docs/numerics.md §14)."""
    return res[:-1] + ", multirate: true}"


def run(a, tag, sets, folder=None):
    out = os.path.join(a.out, folder or tag)
    s, wall, rc = run_case(a.sphflume, os.path.join(ROOT, "cases", FLUMES[a.flume]["case"]), out, sets, a.threads, a.reuse)
    if s is None:
        sys.exit(f"{tag} failed ({rc})")
    cpu = s.get("cpu_seconds", float("nan"))  # (summary.json: the time loop's CPU seconds)
    rows = np.genfromtxt(os.path.join(out, "gauges", "runup.csv"), delimiter=",", names=True)
    return {"R": float(np.nanmax(rows["runup"])) / H0, "wall": wall, "cpu": cpu, "steps": s["steps"],
            "particles": s["particles"]["total"], "fluid": s["particles"]["fluid"],
            "rate": s["particle_steps_per_second"], "levels": s.get("resolution", {}).get("fluid_per_level")}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--sphflume", default=os.environ.get("SPHFLUME", os.path.join(ROOT, "build", "sphflume")))
    ap.add_argument("--out", default=os.path.join(tempfile.gettempdir(), "sphflume-bench", "resolution_band"))
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--flume", choices=sorted(FLUMES), default="a")
    ap.add_argument("--ratio", type=float, default=None, help="H/h0 (default 0.163 on Flume A, 0.28 on Flume B)")
    ap.add_argument("--runs", default="fine,band,coarse",
                    help="which of fine, band, follow, band_mr, follow_mr, coarse to run (comma-separated)")
    ap.add_argument("--dx", type=float, default=0.01)
    ap.add_argument("--end", type=float, default=None,
                    help="end time in s (default: the validation check's); a shorter window times the runs' start "
                         "(sessions 30, 43: Flume B to 0.4 s) and writes to OUT/end_T")
    ap.add_argument("--reuse", action="store_true", help="re-read finished runs in --out (validation/common.py run_case)")
    ap.add_argument("--cells", choices=("levels", "level0", "finest"), default="levels",
                    help="the refined runs' cell list (`resolution.cells`, docs/numerics.md §14); level0 or finest: "
                         "runs go to OUT/cells_level0 or OUT/cells_finest")
    ap.add_argument("--repeat", type=int, default=1, help="rounds of the runs in turn; the median of the rounds' time ratios")
    a = ap.parse_args()
    F = FLUMES[a.flume]
    if a.ratio is None:
        a.ratio = 0.163 if a.flume == "a" else 0.28
    if a.flume == "b":  # (Flume A's runs keep their folder names of session 20)
        a.out = os.path.join(a.out, f"flume_b_{a.ratio:g}")
    if a.cells != "levels":
        a.out = os.path.join(a.out, f"cells_{a.cells}")
    if a.end is not None:
        a.out = os.path.join(a.out, f"end_{a.end:g}")
    base = {"time.end": F["end"](a.ratio) if a.end is None else a.end, "motions.0.height": a.ratio * H0}
    sets = {"fine": {**base, "particles.dx": a.dx / 2},
            "band": {**base, "particles.dx": a.dx, "resolution": BAND.format(top=F["top"])},
            "follow": {**base, "particles.dx": a.dx, "resolution": FOLLOW.format(top=F["top"])},
            "band_mr": {**base, "particles.dx": a.dx, "resolution": multirate(BAND.format(top=F["top"]))},
            "follow_mr": {**base, "particles.dx": a.dx, "resolution": multirate(FOLLOW.format(top=F["top"]))},
            "coarse": {**base, "particles.dx": a.dx}}
    if a.cells != "levels":  # (the refined runs only: the uniform ones have one level)
        for tag in ("band", "follow", "band_mr", "follow_mr"):
            sets[tag]["resolution"] = sets[tag]["resolution"][:-1] + f", cells: {a.cells}}}"
    tags = [tag for tag in ("fine", "band", "follow", "band_mr", "follow_mr", "coarse") if tag in a.runs.split(",")]
    rounds = [{tag: run(a, tag, sets[tag], tag if k == 0 else f"{tag}_r{k}") for tag in tags} for k in range(max(1, a.repeat))]
    res = rounds[0]
    ref = F["ref"](a.ratio)
    print(f"Flume {a.flume.upper()}, H/h0 = {a.ratio:g}, to t = {base['time.end']} s, {a.threads} thread(s); "
          f"{F['ref_name']} R/h0 = {ref:.4f}")
    print(f"{'run':8} {'R/h0':>7} {'vs ref':>8} {'vs fine':>8} {'wall s':>8} {'cpu s':>8} {'steps':>7} {'particles':>9} "
          f"{'M p-steps/s':>11}  fluid per level")
    for tag, v in res.items():
        vs = f"{100 * (v['R'] / res['fine']['R'] - 1):+7.1f}%" if "fine" in res else "       -"
        print(f"{tag:8} {v['R']:7.4f} {100 * (v['R'] / ref - 1):+7.1f}% {vs} "
              f"{v['wall']:8.1f} {v['cpu']:8.1f} {v['steps']:7d} {v['particles']:9d} {v['rate'] / 1e6:11.2f}  {v['levels'] or '-'}")
    for tag in ("band", "follow", "band_mr", "follow_mr"):
        if "fine" in res and tag in res:
            q = res[tag]["wall"] / res["fine"]["wall"]
            qc = res[tag]["cpu"] / res["fine"]["cpu"]
            d = res[tag]["R"] / res["fine"]["R"] - 1
            print(f"{tag} / fine: wall time {q:.3f}, CPU time {qc:.3f} (gate <= 1/3), run-up {100 * d:+.2f} % "
                  f"(Flume A's gate: within 2 %)")
            if len(rounds) > 1:
                qs = [r[tag]["wall"] / r["fine"]["wall"] for r in rounds]
                walls = ", ".join(f"{r['fine']['wall']:.1f}/{r[tag]['wall']:.1f}" for r in rounds)
                print(f"{tag} / fine over {len(rounds)} rounds (fine/{tag} wall s: {walls}): ratios "
                      f"{', '.join(f'{x:.3f}' for x in qs)}; median {float(np.median(qs)):.3f} (gate <= 1/3)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
