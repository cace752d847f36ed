#!/usr/bin/env python3
"""Every case of cases/ run by two sphflume binaries: gauges and snapshots must be bitwise equal.

Issue 41 (structure work) changes no result: run this before each commit of such work, with the binary of the
commit before the work as --base and the new build as --new (default build/sphflume).

    /usr/bin/python3 tests/compare_gauges.py --base /path/to/old/sphflume [--new build/sphflume] [--steps 120]
        [--cases dambreak_2d,piston_bore] [--mpi] [--work DIR]

Each case runs --steps steps first (base binary, no output) to find the time it reaches; then both binaries run to
that time with six gauge outputs and two snapshots, one thread, and tests/robustness/common.py's same_run compares
every snapshot field and gauge file byte for byte. Variants beside the cases: the dam break under ISPH (hybrid and
split sources) and with the dual integrator, and (with --mpi) the dam break, the Liu porous dam break and the
3D dam break on 2 MPI ranks. Exit 1 when any run differs, 2 when a run fails.
"""
import argparse
import glob
import json
import os
import shutil
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, ".."))
sys.path.insert(0, os.path.join(HERE, "robustness"))
from common import same_run  # noqa: E402

VARIANTS = [
    ("dambreak_2d", "isph_hybrid", ["scheme.type=isph", "scheme.formulation=tsurudome"]),
    ("dambreak_2d", "isph_split", ["scheme.type=isph", "scheme.formulation=tsurudome", "scheme.source.type=split"]),
    ("dambreak_2d", "dual", ["scheme.integrator=dual", "fluid.viscosity=0"]),
    ("dambreak_3d", "dual", ["scheme.integrator=dual", "fluid.viscosity=0"]),
]
MPI_CASES = ["dambreak_2d", "porous_dambreak_liu", "dambreak_3d"]


def sets_args(sets):
    out = []
    for s in sets:
        out += ["--set", s]
    return out


def launch(binary, case, out, sets, extra, ranks):
    cmd = [binary, "run", case, "-o", out, "-q", "--threads", "1"] + sets_args(sets) + extra
    if ranks > 1:
        cmd = ["mpirun", "--oversubscribe", "-np", str(ranks)] + \
            (["--allow-run-as-root"] if os.geteuid() == 0 else []) + cmd
    p = subprocess.run(cmd, capture_output=True, text=True)
    return p.returncode, (p.stdout + p.stderr).strip().splitlines()[-3:]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--base", required=True, help="the binary of the commit before the change")
    ap.add_argument("--new", default=os.environ.get("SPHFLUME", os.path.join(ROOT, "build", "sphflume")))
    ap.add_argument("--steps", type=int, default=120)
    ap.add_argument("--cases", default="", help="comma-separated case names (default: every cases/*.yaml)")
    ap.add_argument("--mpi", action="store_true", help="also the MPI_CASES on 2 ranks")
    ap.add_argument("--work", default=os.path.join(tempfile.gettempdir(), "sphflume-compare-gauges"))
    a = ap.parse_args()
    names = a.cases.split(",") if a.cases else \
        sorted(os.path.splitext(os.path.basename(p))[0] for p in glob.glob(os.path.join(ROOT, "cases", "*.yaml")))
    runs = [(n, n, [], 1) for n in names]
    runs += [(c, tag, s, 1) for c, tag, s in VARIANTS if not a.cases or c in names]
    if a.mpi:
        runs += [(c, "ranks2", [], 2) for c in MPI_CASES if not a.cases or c in names]
    shutil.rmtree(a.work, ignore_errors=True)
    os.makedirs(a.work)
    bad, failed = [], []
    for case, tag, sets, ranks in runs:
        label = case if tag == case else f"{case} [{tag}]"
        path = os.path.join(ROOT, "cases", case + ".yaml")
        probe = os.path.join(a.work, f"{case}_{tag}_probe")
        rc, tail = launch(a.base, path, probe, sets, ["--max-steps", str(a.steps), "--no-output"], 1)
        if rc != 0:
            print(f"[FAIL] {label}: the base binary's probe run exited {rc}: {' | '.join(tail)}")
            failed.append(label)
            continue
        with open(os.path.join(probe, "summary.json")) as f:
            t = json.load(f)["simulated_time"]
        timing = [f"time.end={t!r}", f"time.output_interval={t / 6!r}", f"time.snapshot_interval={t / 2!r}"]
        outs = []
        for which, binary in (("base", a.base), ("new", a.new)):
            out = os.path.join(a.work, f"{case}_{tag}_{which}")
            rc, tail = launch(binary, path, out, sets + timing, [], ranks)
            if rc != 0:
                print(f"[FAIL] {label}: the {which} binary exited {rc}: {' | '.join(tail)}")
                failed.append(label)
                break
            outs.append(out)
        if len(outs) < 2:
            continue
        ok, why = same_run(*outs)
        print(f"[{'PASS' if ok else 'FAIL'}] {label}: to t = {t:.4g} s: {why}", flush=True)
        if not ok:
            bad.append(label)
    print(f"compare_gauges: {len(runs) - len(bad) - len(failed)} of {len(runs)} runs bitwise equal"
          + (f"; differ: {', '.join(bad)}" if bad else "") + (f"; failed: {', '.join(failed)}" if failed else ""))
    sys.exit(2 if failed else 1 if bad else 0)


if __name__ == "__main__":
    main()
