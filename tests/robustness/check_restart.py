#!/usr/bin/python3
"""Checkpoint, restart and determinism, through the CLI (issue: SPHFlume keeps working and loses nothing).

- Two runs of the same case with the same thread count write bitwise identical snapshots and gauges.
- A run killed by SIGKILL at an arbitrary moment (a random number of snapshots in) and restarted from its last
  snapshot ends bitwise identical to the uninterrupted run: every snapshot, every gauge row. For each integrator.
- SIGTERM and SIGINT write OUTPUT/checkpoint.h5 and exit with 128 + the signal; a restart from it is bitwise equal.
- A restart with another case, from a truncated file, or past time.end is bad input: exit 2 and a clear message.
Usage: check_restart.py SPHFLUME [WORKDIR]
"""
import json
import os
import random
import shutil
import signal
import subprocess
import sys
import time

import h5py

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from common import ROOT, check, finish, run, same_run, snapshots  # noqa: E402

binary = sys.argv[1]
work = sys.argv[2] if len(sys.argv) > 2 else "/tmp/sphflume_restart_test"
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
case = os.path.join(ROOT, "cases", "dambreak_2d.yaml")
rng = random.Random(int(os.environ.get("SPHFLUME_TEST_SEED", time.time())))

N_SNAP = 25  # 0.5 s at 0.02 s intervals


def kill_after(args, out, k):
    """Start a run into out; SIGKILL it once k snapshots exist, at a random moment within that output
    interval. Returns (the snapshots left, the run's return code)."""
    p = subprocess.Popen([binary] + args + ["-o", out], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    while len(snapshots(out)) < k and p.poll() is None:
        time.sleep(0.002)
    time.sleep(rng.uniform(0.0, 0.05))
    p.send_signal(signal.SIGKILL)
    p.wait()
    return snapshots(out), p.returncode
# each WCSPH integrator, and the projection scheme (its pressures are the next solve's warm start)
# (isph: Tsurudome's formulation; isph_lind: the projection of Lind, Skillen and Chow, issue 57, the default)
for integ in ["verlet", "symplectic", "isph", "isph_lind"]:
    scheme = ["--set", "scheme.type=isph", "--set", "scheme.formulation=tsurudome",
              "--set", "scheme.shifting.coefficient=2"] if integ == "isph" else \
        ["--set", "scheme.type=isph", "--set", "scheme.formulation=lind"] if integ == "isph_lind" else \
        ["--set", f"scheme.integrator={integ}"]
    sets = ["--set", "particles.dx=0.0073", "--set", "time.end=0.5", "--set", "time.output_interval=0.02"] + scheme
    args = ["run", case, "-q", "--threads", "2"] + sets
    ref, ref2, killed = (os.path.join(work, f"{integ}_{n}") for n in ("ref", "ref2", "killed"))
    rc, log = run(binary, args + ["-o", ref])
    check(rc == 0, f"{integ}: uninterrupted run exits 0 (got {rc})")
    rc, _ = run(binary, args + ["-o", ref2])
    ok, why = same_run(ref, ref2)
    check(rc == 0 and ok, f"{integ}: two runs with the same thread count are bitwise identical: {why}")

    left, code = kill_after(args, killed, rng.randint(2, N_SNAP - 3))
    p_rc = code
    check(p_rc == -signal.SIGKILL and len(left) < N_SNAP + 1,
          f"{integ}: run killed (SIGKILL) after {len(left)} of {N_SNAP + 1} snapshots")
    rc, log = run(binary, args + ["--restart", left[-1]])  # output folder: the restart file's run folder
    check(rc == 0, f"{integ}: restart from {os.path.basename(left[-1])} exits 0 (got {rc}) {log[-300:] if rc else ''}")
    ok, why = same_run(ref, killed)
    check(ok, f"{integ}: killed + restarted run bitwise equal to the uninterrupted run: {why}")

def killed_and_restarted(tag, args, k):
    """An uninterrupted run of args into WORK/TAG_ref, and one SIGKILLed after k snapshots into WORK/TAG_killed and
    restarted from its last snapshot: (both exit 0 and every snapshot and gauge bitwise equal, why, the two folders,
    the snapshots the killed run left)."""
    ref, kill = os.path.join(work, f"{tag}_ref"), os.path.join(work, f"{tag}_killed")
    rc, _ = run(binary, args + ["-o", ref])
    check(rc == 0, f"{tag}: uninterrupted run exits 0 (got {rc})")
    left, _ = kill_after(args, kill, k)
    rc, _ = run(binary, args + ["--restart", left[-1]])
    ok, why = same_run(ref, kill)
    return rc == 0 and ok, why, ref, kill, left


def sets_of(*kv):
    return [x for e in kv for x in ("--set", e)]


# open boundaries: particles created and deleted every few steps, counters in the restart data
chan = os.path.join(ROOT, "cases", "channel_laminar.yaml")
ok, why, _, _, left = killed_and_restarted(
    "channel", ["run", chan, "-q", "--threads", "2"] + sets_of("particles.dx=0.005", "time.end=1.0", "time.output_interval=0.05"),
    rng.randint(3, 15))
check(ok, f"channel (open boundaries): killed after {len(left)} snapshots, restarted: bitwise equal: {why}")

# transported scalars (inflow values, the Y = C/rho start-of-step fields) and two phases
for tname, tsets in [("channel_release", ["particles.dx=0.01", "time.end=0.6", "time.output_interval=0.05"]),
                     ("bubble_advective_diffusion", ["particles.dx=0.06", "time.end=0.2", "time.output_interval=0.02"])]:
    tcase = os.path.join(ROOT, "cases", f"{tname}.yaml")
    ok, why, tref, tkill, left = killed_and_restarted(tname, ["run", tcase, "-q", "--threads", "2"] + sets_of(*tsets),
                                                      rng.randint(3, 8))
    with h5py.File(snapshots(tref)[-1], "r") as ha, h5py.File(snapshots(tkill)[-1], "r") as hb:
        same_c = ha["concentration"][:].tobytes() == hb["concentration"][:].tobytes()
    check(ok and same_c, f"{tname} (transport): killed after {len(left)} snapshots, restarted: bitwise "
                         f"equal, concentration too: {why}, concentration {'equal' if same_c else 'DIFFERS'}")

# moving walls (a piston paddle; gauges at every output, snapshots at every other one): the paddle's place
# comes from its law and the stored origins, under both schemes
pcase = os.path.join(ROOT, "cases", "piston_bore.yaml")
for pscheme in ["wcsph", "isph", "isph_lind"]:
    ok, why, _, _, left = killed_and_restarted(
        f"piston_{pscheme}", ["run", pcase, "-q", "--threads", "2"] + sets_of(
            "particles.dx=0.01", "time.end=0.4", "time.output_interval=0.01", "time.snapshot_interval=0.02",
            *(["scheme.type=isph", "scheme.formulation=lind"] if pscheme == "isph_lind" else
              ["scheme.type=isph", "scheme.formulation=tsurudome"] if pscheme == "isph" else [f"scheme.type={pscheme}"])),
        rng.randint(3, 15))
    check(ok, f"piston ({pscheme}, moving walls): killed after {len(left)} snapshots, restarted: bitwise equal: {why}")

# active absorption (issue 59): the paddles' corrections (displacement, velocity, mean, the delayed readings) travel
# in the restart data; both the generating paddle and the absorber at the far end correct from t = 0
acase = os.path.join(ROOT, "cases", "absorber_end.yaml")
ok, why, _, _, left = killed_and_restarted(
    "absorbing", ["run", acase, "-q", "--threads", "2"] + sets_of(
        "particles.dx=0.03", "time.end=1.0", "time.output_interval=0.02", "time.snapshot_interval=0.04"),
    rng.randint(3, 20))
check(ok, f"absorber_end (active absorption): killed after {len(left)} snapshots, restarted: bitwise equal: {why}")

# resolution levels (issue 42): the particles' h and level travel in the restart data
rcase = os.path.join(ROOT, "cases", "still_tank_refined.yaml")
ok, why, rref, rkill, left = killed_and_restarted(
    "levels", ["run", rcase, "-q", "--threads", "2"] + sets_of(
        "particles.dx=0.03", "time.end=0.3", "time.output_interval=0.02", "resolution.regions.0.min=[0.3, 0.2]"),
    rng.randint(3, 10))
with h5py.File(snapshots(rref)[-1], "r") as ha, h5py.File(snapshots(rkill)[-1], "r") as hb:
    same_h = all(ha[k][:].tobytes() == hb[k][:].tobytes() for k in ("h", "level"))
check(ok and same_h, f"still_tank_refined (resolution levels): killed after {len(left)} snapshots, restarted: bitwise "
                     f"equal, h and level too: {why}, h and level {'equal' if same_h else 'DIFFER'}")

# resolution levels with splits and merges during the run: the dam break's surge crosses a refined box
ok, why, rref, rkill, left = killed_and_restarted(
    "levels_adapt", ["run", case, "-q", "--threads", "2"] + sets_of(
        "particles.dx=0.0146", "time.end=0.3", "time.output_interval=0.01", "scheme.integrator=verlet",
        "resolution={regions: [{shape: box, min: [0.2, 0.04], max: [0.35, 0.2], level: 1}]}"),
    rng.randint(8, 22))
with open(os.path.join(rref, "summary.json")) as f:
    adapt = json.load(f).get("resolution", {})
check(ok and adapt.get("splits", 0) > 0 and adapt.get("merges", 0) > 0,
      f"dam break through a refined box (splits {adapt.get('splits')}, merges {adapt.get('merges')}): killed after "
      f"{len(left)} snapshots, restarted: bitwise equal: {why}")

# multirate time stepping (issue 42): the same dam break, the fine level sub-cycled; the step keeps no state between steps
ok, why, rref, rkill, left = killed_and_restarted(
    "levels_multirate", ["run", case, "-q", "--threads", "2"] + sets_of(
        "particles.dx=0.0146", "time.end=0.3", "time.output_interval=0.01", "scheme.integrator=symplectic",
        "resolution={regions: [{shape: box, min: [0.2, 0.04], max: [0.35, 0.2], level: 1}], multirate: true}"),
    rng.randint(8, 22))
check(ok, f"dam break through a refined box, multirate: killed after {len(left)} snapshots, restarted: bitwise equal: {why}")

# SIGTERM / SIGINT: checkpoint, exit 128 + signal, restart bitwise
args = ["run", case, "-q", "--threads", "2", "--set", "particles.dx=0.0073", "--set", "time.end=0.5",
        "--set", "time.output_interval=0.02", "--set", "scheme.integrator=verlet"]
ref = os.path.join(work, "verlet_ref")
for sig in [signal.SIGTERM, signal.SIGINT]:
    out = os.path.join(work, f"sig{int(sig)}")
    p = subprocess.Popen([binary] + args + ["-o", out], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    while len(snapshots(out)) < rng.randint(3, 15) and p.poll() is None:
        time.sleep(0.002)
    p.send_signal(sig)
    _, err = p.communicate()
    ck = os.path.join(out, "checkpoint.h5")
    check(p.returncode == 128 + int(sig) and os.path.exists(ck) and "--restart" in err,
          f"{sig.name}: exit {128 + int(sig)} (got {p.returncode}), checkpoint.h5 written, message says how to resume")
    rc, log = run(binary, args + ["--restart", ck])
    ok, why = same_run(ref, out)
    check(rc == 0 and ok, f"{sig.name}: restart from checkpoint.h5 bitwise equal to the uninterrupted run: {why}")

# bad restarts: exit 2, clear message, nothing computed
last = snapshots(ref)[-1]
mid = snapshots(ref)[5]
rc, log = run(binary, args + ["--set", "scheme.alpha=0.05", "--restart", mid, "-o", os.path.join(work, "x1")])
check(rc == 2 and "differs from the one that wrote" in log, f"restart with another case: exit 2 and says so (got {rc}: {log.strip()[-160:]})")
rc, log = run(binary, args + ["--restart", last, "-o", os.path.join(work, "x2")])
check(rc == 2 and "raise the end time" in log, f"restart at time.end: exit 2, suggests raising time.end (got {rc})")
trunc = os.path.join(work, "truncated.h5")
with open(mid, "rb") as f:
    data = f.read()
with open(trunc, "wb") as f:
    f.write(data[: len(data) // 2])
rc, log = run(binary, args + ["--restart", trunc, "-o", os.path.join(work, "x3")])
check(rc == 2 and "truncated.h5" in log, f"restart from a truncated file: exit 2 naming the file (got {rc}: {log.strip()[-160:]})")
branch = os.path.join(work, "x4")
rc, log = run(binary, args + ["--set", "time.end=0.6", "--restart", mid, "-o", branch])
with h5py.File(mid, "r") as h:
    t_mid = float(h.attrs["time"])
first = snapshots(branch)[0] if snapshots(branch) else None
t_first = float(h5py.File(first, "r").attrs["time"]) if first else None
check(rc == 0 and t_first == t_mid,
      f"restart with a later time.end into another folder runs on there, its series starting at the restart time "
      f"(got {rc}, first snapshot at t = {t_first}, restart at {t_mid})")

finish("check_restart")
