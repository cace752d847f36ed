"""Helpers for the CLI-level robustness tests (run by CTest with Debian's python3 + h5py)."""
import filecmp
import glob
import os
import subprocess
import sys

import h5py
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", ".."))
FAILS = []


def check(cond, what):
    print(("[PASS] " if cond else "[FAIL] ") + what)
    if not cond:
        FAILS.append(what)


def finish(name):
    if FAILS:
        print(f"{name}: {len(FAILS)} check(s) failed")
        sys.exit(1)
    print(f"{name}: all checks passed")


def run(binary, args, **kw):
    """Run sphflume; returns (exit code, stdout + stderr)."""
    p = subprocess.run([binary] + args, capture_output=True, text=True, **kw)
    return p.returncode, p.stdout + p.stderr


def snapshots(out):
    return sorted(glob.glob(os.path.join(out, "snapshots", "snap_*.h5")))


FIELDS = ["position", "velocity", "density", "pressure", "mass", "kind", "id"]


def same_run(a, b):
    """Every snapshot field and every gauge file of two output folders bitwise equal: (ok, why)."""
    sa, sb = snapshots(a), snapshots(b)
    if [os.path.basename(s) for s in sa] != [os.path.basename(s) for s in sb]:
        return False, f"snapshot lists differ ({len(sa)} vs {len(sb)})"
    for fa, fb in zip(sa, sb):
        with h5py.File(fa, "r") as ha, h5py.File(fb, "r") as hb:
            if ha.attrs["step"] != hb.attrs["step"] or ha.attrs["time"] != hb.attrs["time"]:
                return False, f"{os.path.basename(fa)}: step/time differ"
            for k in FIELDS:
                x, y = ha[k][:], hb[k][:]
                if x.shape != y.shape or x.tobytes() != y.tobytes():
                    return False, f"{os.path.basename(fa)}: field {k} differs"
    for g in glob.glob(os.path.join(a, "gauges", "*.csv")):
        if not filecmp.cmp(g, os.path.join(b, "gauges", os.path.basename(g)), shallow=False):
            return False, f"gauge {os.path.basename(g)} differs"
    return True, f"{len(sa)} snapshots and the gauges bitwise equal"


def load_last(out):
    s = snapshots(out)[-1]
    with h5py.File(s, "r") as h:
        return s, {k: h[k][:] for k in FIELDS}, dict(h.attrs)
