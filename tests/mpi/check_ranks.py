#!/usr/bin/python3
"""The same case on 1, 2 (and 4) MPI ranks (issue 24): `mpirun -np N sphflume run CASE`.

For each case below (2D and 3D dam breaks, an ISPH dam break under each formulation, a dam break with the
mixing-length model, a porous dam break (under ISPH too, lind's with its lifted gate), two periodic channels: one cut
across its periodic axis, one along it), one process and N ranks (1 thread each; oversubscribed on a 2-core machine, which is fine for
correctness) must give:
- the same particle counts (fluid, wall, total) and the same mass: initial and final mass equal to 1e-12 relative
  (the sums over ranks add the same terms in another order: round-off, ~1e-16 per term);
- the same flow within round-off-driven differences. The ranks' pair sums add the same terms as one process's, but
  a particle's neighbours come in another order (owned, then halo copies), so the states differ at float round-off
  (the pair loops sum in float) from the first step, and the differences grow with the flow's sensitivity: in the 2D
  dam break the release's acoustic ringing at the reservoir wall (+-0.6 rho g H) amplifies them to 0.03 rho g H by
  t = 2. For scale, one process with gravity changed by one float ulp (2^-23 relative, nothing else changed)
  differs from the unchanged run by 0.009 rho g H, 2.6e-5 relative energy and 2.3e-4 dx front there
  (tests/mpi/README.md); the same ranks differ there by 0.03-0.06 from one run of the code to the next as the
  summation order changes (energy 2e-5 to 5e-5, front up to 5e-3 dx on 4 ranks). The gates are fixed, about 5
  times the largest of those and far below any physical change (dx +-2 % moves the energy by 1e-2): energy
  within 3e-4 relative, front within 0.02 dx, wall pressure within 0.1 rho g H at every sample and within
  0.01 rho g H in its mean over the run's second half (the ringing averages out);
- a run restarted on 2 ranks from a snapshot of a one-process run continues it: its end state matches the
  uninterrupted one-process run within the same gates;
- a distributed run writes the same snapshot files as one process (every particle once, by id); a snapshot of a
  2-rank run continues in one process; a rank killed mid-run leaves whole snapshots, and the last one restarts on 2
  ranks and ends where the uninterrupted run does;
- a moving paddle and a run-up gauge across ranks stay within 5 times the differences a one-ulp change of gravity makes;
- open channels (particles created and deleted, inflow states averaged at nodes on other ranks, a transported
  pollutant with a bed source across the cut) and an air bubble in water (two phases) keep their counts,
  masses and the masses through their boundaries, and their profile and flux gauges agree within 1e-4;
- resolution levels (a dam break through a refined box; again with `multirate: true, cells: finest`): mass conserved
  and equal to one process's, unique ids, the front within 5 times what one ulp of gravity or another order of the
  pair sums moves it, the wall sensor within the dam breaks' gates above (or 5 times that, if larger);
- what distributed runs do not support (ISPH with Eigen's solver, which holds the whole system in one process; the
  dual integrator's `pairs: advection`, whose kept rows hold one store's indices) is refused with exit 2 and a
  message that names it.
Usage: check_ranks.py SPHFLUME WORKDIR [--ranks 2,4] [--snapshot-writes collective|gathered]
"""
import argparse
import csv
import json
import math
import os
import shutil
import signal
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor

import h5py
import yaml

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "robustness"))
from common import ROOT, check, finish  # noqa: E402  (the robustness tests' helpers)
ap = argparse.ArgumentParser()
ap.add_argument("binary")
ap.add_argument("work")
ap.add_argument("--ranks", default="2")
ap.add_argument("--snapshot-writes", default="", help="how a distributed run must write its snapshots: collective "
                "(the build's HDF5 is parallel) or gathered (on rank 0); empty: either")
args = ap.parse_args()
RANKS = sorted({2} | {int(r) for r in args.ranks.split(",")})  # (2 always: the restart, snapshot and fault checks use it)
shutil.rmtree(args.work, ignore_errors=True)
os.makedirs(args.work)


def mpirun_works():
    """Whether this machine can start 2 MPI processes at all (a container without shared memory or
    process slots cannot); the test is then skipped (77), not failed, and says why."""
    cmd = ["mpirun", "--oversubscribe", "-np", "2"] + (["--allow-run-as-root"] if os.geteuid() == 0 else []) + ["true"]
    try:
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
    except (OSError, subprocess.TimeoutExpired) as e:
        return str(e)
    return "" if p.returncode == 0 else (p.stdout + p.stderr).strip()[-500:]


why = mpirun_works()
if why:
    print(f"skipped: mpirun cannot start 2 processes here: {why}")
    sys.exit(77)


def mpirun(n):
    if n == 1:
        return []
    cmd = ["mpirun", "--oversubscribe", "-np", str(n)]
    if os.geteuid() == 0:
        cmd.insert(1, "--allow-run-as-root")
    return cmd


def run(n, case, out, extra=()):
    cmd = mpirun(n) + [args.binary, "run", case, "-o", out, "-q", "--threads", "1"] + list(extra)
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=1200)
    return p


def run_ones(jobs):
    """Run one-process jobs [(case, out)] side by side, as many at once as this process may use cores (each on one
    thread, so each gives what it gives alone; CI's 2 cores run the references in pairs). Returns their results in
    order."""
    with ThreadPoolExecutor(max(1, len(os.sched_getaffinity(0)))) as ex:
        return list(ex.map(lambda j: run(1, *j), jobs))


def gauge(out, name):
    with open(os.path.join(out, "gauges", name + ".csv")) as f:
        rows = list(csv.reader(f))
    head = rows[0]
    return {h: [float(r[i]) for r in rows[1:]] for i, h in enumerate(head)}


def variant(src, name, sets, gauges, ulp=False):
    """A copy of case src with its gauges replaced (the MPI-ready ones) and keys set; ulp: gravity's last
    component larger by one float ulp, 2^-23 relative (a round-off-sized perturbation, for the README's scale);
    ulp = -1: smaller by one."""
    with open(os.path.join(ROOT, "cases", src)) as f:
        c = yaml.safe_load(f)
    c["gauges"] = gauges
    if name.startswith("isph_porous_dambreak"):
        # without the gate: ISPH compresses the water under the rising gate at the dam face (1.31 rho0 at
        # t = 0.054 s at dx = 0.01, validation/porous_dambreak_liu/README.md); this check is about the ranks
        c["geometry"] = [g for g in c["geometry"] if g.get("motion") != "gate"]
        c["motions"] = [m for m in c.get("motions", []) if m.get("name") != "gate"]
        if not c["motions"]:
            del c["motions"]
    # the copy lives elsewhere: files the case names (a motion's table) keep pointing at the case's folder
    for m in c.get("motions", []):
        if "file" in m and not os.path.isabs(m["file"]):
            m["file"] = os.path.join(ROOT, "cases", m["file"])
    if ulp:
        c["gravity"][-1] = float(c["gravity"][-1]) * (1.0 + (-1.0 if ulp == -1 else 1.0) * 2.0**-23)
    for k, v in sets.items():
        node = c
        *path, last = k.split(".")
        for p in path:
            node = node[int(p)] if isinstance(node, list) else node.setdefault(p, {})
        node[int(last) if isinstance(node, list) else last] = v
    path = os.path.join(args.work, name + ".yaml")
    with open(path, "w") as f:
        yaml.safe_dump(c, f)
    return path


def ulp_gate(label, one, out, ulps, gname, col, exact=False, floor=0.0, mean_floor=None):
    """Gauge `gname`.`col` of the ranks' run `out` against the one-process run `one`: within 5 times the larger of
    what the reference runs `ulps` differ from `one` by, and at least `floor` (exact: equal); the same number of
    rows. mean_floor: the time means over the run's second half (both wet) also within 5 times the references'
    and at least mean_floor."""
    a, b = gauge(one, gname), gauge(out, gname)
    scale = max(abs(x) for x in a[col] if x == x) or 1.0

    def dmax(x, y):
        return max((abs(p - q) if p == p and q == q else (0.0 if p != p and q != q else math.inf)) for p, q in zip(x, y))

    def dmean(x, y):
        half = [(p, q) for t, p, q in zip(a["time"], x, y) if t >= 0.5 * a["time"][-1] and p == p and q == q]
        return abs(sum(p for p, _ in half) - sum(q for _, q in half)) / max(1, len(half))
    d_ranks = dmax(a[col], b[col])
    d_ulp = max(dmax(a[col], gauge(u, gname)[col]) for u in ulps)
    gate = 0.0 if exact else max(5.0 * max(d_ulp, 1e-6 * scale), floor)
    check(len(a["time"]) == len(b["time"]) and d_ranks <= gate,
          f"{label}: {gname}.{col} differs by {d_ranks:.3g} (references: {d_ulp:.3g}; gate {gate:.3g}; "
          f"largest value {scale:.3g})")
    if mean_floor is not None:
        m_ranks = dmean(a[col], b[col])
        m_ulp = max(dmean(a[col], gauge(u, gname)[col]) for u in ulps)
        mgate = max(5.0 * m_ulp, mean_floor)
        check(m_ranks <= mgate, f"{label}: {gname}.{col}'s mean over the second half differs by {m_ranks:.3g} "
              f"(references: {m_ulp:.3g}; gate {mgate:.3g})")


def one_and_ulps(tag, src, sets, gauges, reorder=None):
    """The one-process run of a variant of case src and its reference runs: gravity one float ulp larger and smaller
    ("ulp", "ulpm") and, with `reorder` (keys that change only the order of the pair sums), "order".
    Returns ({"one", "ulp", "ulpm"[, "order"]: output folder}, the variant's case file, whether all ran)."""
    cases = {"one": variant(src, tag, sets, gauges), "ulp": variant(src, tag + "_ulp", sets, gauges, ulp=True),
             "ulpm": variant(src, tag + "_ulpm", sets, gauges, ulp=-1)}
    if reorder:
        cases["order"] = variant(src, tag + "_order", {**sets, **reorder}, gauges)
    outs = {k: os.path.join(args.work, f"{tag}_{k}") for k in cases}
    ok = True
    for k, p in zip(cases, run_ones([(c, outs[k]) for k, c in cases.items()])):
        ok &= p.returncode == 0
        check(p.returncode == 0, f"{tag} ({k}): one process ran ({p.returncode}) {p.stderr.strip()[-300:]}")
    return outs, cases["one"], ok


def diffs(a, b):
    """The largest differences between two runs' gauges: energy (relative to its largest value), front, wall pressure
    (NaN where both are NaN; inf where only one is)."""
    ea, eb = gauge(a, "energy"), gauge(b, "energy")
    n = min(len(ea["time"]), len(eb["time"]))
    escale = max(abs(x) for x in ea["total"][:n]) or 1.0  # (a channel starting at rest has no energy at t = 0)
    de = max(abs(ea["total"][i] - eb["total"][i]) for i in range(n)) / escale
    df = 0.0
    if os.path.exists(os.path.join(a, "gauges", "front.csv")):
        fa, fb = gauge(a, "front"), gauge(b, "front")
        df = max(abs(fa["front"][i] - fb["front"][i]) for i in range(n))
    du = 0.0
    if os.path.exists(os.path.join(a, "gauges", "u_mid.csv")):
        ua, ub = gauge(a, "u_mid"), gauge(b, "u_mid")
        du = max(abs(ua["ux"][i] - ub["ux"][i]) for i in range(n)) / max(abs(x) for x in ua["ux"][:n])
    dp = dm = 0.0
    if os.path.exists(os.path.join(a, "gauges", "p_wall.csv")):
        ga, gb = gauge(a, "p_wall"), gauge(b, "p_wall")
        pa, pb = ga["pressure"][:n], gb["pressure"][:n]
        for x, y in zip(pa, pb):
            dp = max(dp, math.inf if (x != x) != (y != y) else (abs(x - y) if x == x else 0.0))
        # the time mean over the second half of the run (both wet): what a ringing signal can be compared by
        half = [(x, y) for t, x, y in zip(ga["time"][:n], pa, pb) if t >= 0.5 * ga["time"][n - 1] and x == x and y == y]
        dm = abs(sum(x for x, _ in half) - sum(y for _, y in half)) / max(1, len(half))
    return de, df, dp, du, dm


def compare(name, a, b, dx, scale_p, label, ulp=None):
    """ulp: a one-process run of the same case with gravity one float ulp larger; where given, each gate is at least
    5 times what that round-off-sized perturbation changes (the projection scheme's impact pressure is chaotic)."""
    sa, sb = (json.load(open(os.path.join(d, "summary.json"))) for d in (a, b))
    for k in ("fluid", "wall", "total"):
        check(sa["particles"][k] == sb["particles"][k], f"{name} {label}: {k} particles {sa['particles'][k]} / {sb['particles'][k]}")
    for k in ("initial", "final"):
        ma, mb = sa["mass"][k], sb["mass"][k]
        check(abs(ma - mb) <= 1e-12 * abs(ma), f"{name} {label}: {k} mass {ma:.15g} / {mb:.15g}")
    ea, eb = gauge(a, "energy"), gauge(b, "energy")
    n = min(len(ea["time"]), len(eb["time"]))
    check(n >= 3 and len(ea["time"]) == len(eb["time"]), f"{name} {label}: {n} gauge rows in both")
    de, df, dp, du, dm = diffs(a, b)
    ge, gf, gp, gm = 3e-4, 0.02 * dx, 0.1 * scale_p, 0.01 * scale_p
    if ulp:
        ue, uf, up, _, um = diffs(a, ulp)
        ge, gf, gp, gm = max(ge, 5 * ue), max(gf, 5 * uf), max(gp, 5 * up), max(gm, 5 * um)
        print(f"  ({name}: one ulp of gravity changes the energy by {ue:.2e}, the front by {uf / dx:.2e} dx, the wall "
              f"pressure by {up / scale_p:.2e} rho g H, its mean by {um / scale_p:.2e})")
    check(de <= ge, f"{name} {label}: energy differs by {de:.2e} relative (gate {ge:.2e})")
    if os.path.exists(os.path.join(a, "gauges", "u_mid.csv")):
        check(du <= 1e-4, f"{name} {label}: mid-channel velocity differs by {du:.2e} of its largest value (gate 1e-4)")
    if os.path.exists(os.path.join(a, "gauges", "front.csv")):
        check(df <= gf, f"{name} {label}: front differs by {df / dx:.2e} dx (gate {gf / dx:.2e} dx)")
    if os.path.exists(os.path.join(a, "gauges", "p_wall.csv")):
        check(dp <= gp and dm <= gm,
              f"{name} {label}: wall pressure differs by {dp / scale_p:.2e} rho g H at most (gate {gp / scale_p:.2e}), its "
              f"mean over the second half by {dm / scale_p:.2e} (gate {gm / scale_p:.2e})")
    return sb


GAUGES_DB = [{"name": "energy", "type": "energy"}, {"name": "front", "type": "front", "axis": "x"}]
cases = [
    # name, case file, keys, gauges, dx, rho g H (pressure scale)
    # (the SPHinXsys cases keep each advection step's pairs, which one process only can: pairs: acoustic here)
    ("dambreak_2d", "dambreak_sphinxsys.yaml", {"time.end": 2.0, "time.output_interval": 0.1, "scheme.pairs": "acoustic"},
     # the reservoir's wall (wet all along): a sensor face and window, as the bench's (a point probe here reads
     # the acoustic ringing of the release, +-0.6 rho g H, where round-off differences grow to 0.04 by t = 2)
     GAUGES_DB + [{"name": "p_wall", "type": "pressure", "point": [0.0, 0.2], "diameter": 0.03, "normal": [1.0, 0.0],
                   "window": 0.02}], 0.0125, 1.0),
    ("dambreak_3d", "dambreak_sphinxsys_3d.yaml", {"time.end": 1.0, "time.output_interval": 0.1, "scheme.pairs": "acoustic"},
     GAUGES_DB, 0.05, 1.0),
    # periodic channels: the slabs across the periodic axis (Darcy-Forchheimer, porous, long in x), and the
    # periodic images of other ranks' copies (Poiseuille, slabs across the depth)
    ("darcy_forchheimer", "darcy_forchheimer.yaml", {"time.end": 0.3, "time.output_interval": 0.02},
     [{"name": "energy", "type": "energy"}, {"name": "u_mid", "type": "velocity", "point": [0.1, 0.05]}], 0.005, 1.0),
    ("poiseuille", "poiseuille_2d.yaml", {"time.end": 0.1, "time.output_interval": 0.01},
     [{"name": "energy", "type": "energy"}, {"name": "u_mid", "type": "velocity", "point": [0.0002, 0.0005]}], 2.5e-5, 1.0),
    # ISPH under Tsurudome's formulation (its pressure equation solved by hypre over every rank's rows) with a tight
    # solver tolerance: at the default 1e-6 the partitions' different iterates dominate (energy 8e-5, wall pressure
    # up to 0.8 of its peak in the impact; docs/parallel.md); at 1e-11 what is left is round-off, which the split
    # source amplifies (gated against a one-ulp run, below)
    ("isph_dambreak", "dambreak_2d.yaml",
     {"particles.dx": 0.0073, "time.end": 0.3, "time.output_interval": 0.02, "scheme.type": "isph",
      "scheme.formulation": "tsurudome", "scheme.shifting": {"coefficient": 2.0}, "scheme.solver.type": "boomeramg",
      "scheme.solver.tolerance": 1e-11},
     GAUGES_DB + [{"name": "p_wall", "type": "pressure", "point": [0.584, 0.0146]}], 0.0073, 1000 * 9.81 * 0.292),
    # the mixing-length model on a sloped free surface: a column's top (for the mixing length) may be another rank's
    # particle; without the columns' reduction over the ranks the energy differs by 1.5e-2 at t = 0.2 (checked)
    ("mixing_length_dambreak", "dambreak_2d.yaml",
     {"particles.dx": 0.0073, "time.end": 0.2, "time.output_interval": 0.02,
      "turbulence": {"model": "mixing_length", "profile": "nezu_rodi", "bed": 0.0, "kappa": 0.41}},
     GAUGES_DB, 0.0073, 1.0),
    ("porous_dambreak", "porous_dambreak_liu.yaml", {"particles.dx": 0.01, "time.end": 0.3, "time.output_interval": 0.02},
     GAUGES_DB + [{"name": "volume", "type": "water_volume"},
                  {"name": "p_wall", "type": "pressure", "point": [0.0, 0.05], "diameter": 0.02, "normal": [1.0, 0.0]}],
     0.01, 1000 * 9.81 * 0.3534),
    # the same porous dam break under ISPH with the split source, which runs it (issue 39, point 6): the porosity
    # field, the split source's second solve and the dummies' feet across the cut, hypre over both ranks' rows
    ("isph_porous_dambreak", "porous_dambreak_liu.yaml",
     {"particles.dx": 0.01, "time.end": 0.3, "time.output_interval": 0.02, "scheme.type": "isph",
      "scheme.formulation": "tsurudome", "scheme.shifting": {"coefficient": 2.0},
      "scheme.solver": {"type": "boomeramg", "tolerance": 1e-11}, "scheme.source": {"type": "split"}},
     GAUGES_DB + [{"name": "volume", "type": "water_volume"},
                  {"name": "p_wall", "type": "pressure", "point": [0.0, 0.05], "diameter": 0.02, "normal": [1.0, 0.0]}],
     0.01, 1000 * 9.81 * 0.3534),
    # the projection of Lind, Skillen and Chow (issue 57, check 6): the walls' mirror-point rows, the moments and the
    # surface's Robin rows across the cut; the Liu case with its lifted gate (a moving wall over the ranks) and the
    # porosity field
    ("isph_lind_dambreak", "dambreak_2d.yaml",
     {"particles.dx": 0.0073, "time.end": 0.3, "time.output_interval": 0.02, "scheme.type": "isph",
      "scheme.formulation": "lind", "scheme.solver": {"type": "boomeramg", "tolerance": 1e-11}},
     GAUGES_DB + [{"name": "p_wall", "type": "pressure", "point": [0.584, 0.0146]}], 0.0073, 1000 * 9.81 * 0.292),
    ("isph_lind_porous_gate", "porous_dambreak_liu.yaml",
     {"particles.dx": 0.01, "time.end": 0.3, "time.output_interval": 0.02, "scheme.type": "isph",
      "scheme.formulation": "lind", "scheme.solver": {"type": "boomeramg", "tolerance": 1e-11}},
     GAUGES_DB + [{"name": "volume", "type": "water_volume"},
                  {"name": "p_wall", "type": "pressure", "point": [0.0, 0.05], "diameter": 0.02, "normal": [1.0, 0.0]}],
     0.01, 1000 * 9.81 * 0.3534),
]
def one_and_ranks(name, case, p):
    """Check that `case`'s one-process run (its result p, run into name_1) ran and run it on each rank count
    (checking that each ran). Returns the one-process output folder (None if it failed) and the (ranks, folder) of
    the distributed runs that ran."""
    one = os.path.join(args.work, name + "_1")
    check(p.returncode == 0, f"{name}: one process ran ({p.returncode}) {p.stderr.strip()[-300:]}")
    if p.returncode != 0:
        return None, []
    ran = []
    for n in RANKS:
        out = os.path.join(args.work, f"{name}_{n}")
        p = run(n, case, out)
        check(p.returncode == 0, f"{name}: {n} ranks ran ({p.returncode}) {p.stderr.strip()[-300:]}")
        if p.returncode == 0:
            ran.append((n, out))
    return one, ran


# the one-process runs first, side by side (run_ones); then the distributed runs, one at a time
# (the projection scheme amplifies round-off to the impact pressure's own scale by t = 0.3 (the split source: one ulp
# of gravity moves the wall point by 2.0 rho g H, 1e-3 of the energy; 2026-11-26): its gates are calibrated in the
# same run against a one-ulp run, as the paddle's below)
ones = run_ones([(variant(src, name, sets, gauges), os.path.join(args.work, name + "_1")) for name, src, sets, gauges, _, _
                 in cases] + [(variant(src, name + "_ulp", sets, gauges, ulp=True), os.path.join(args.work, name + "_ulp"))
                              for name, src, sets, gauges, _, _ in cases if name.startswith("isph")])
ulps = iter(ones[len(cases):])
for (name, src, sets, gauges, dx, scale_p), p1 in zip(cases, ones):
    one, ran = one_and_ranks(name, os.path.join(args.work, name + ".yaml"), p1)
    ulp = None
    if name.startswith("isph"):
        p = next(ulps)
        check(p.returncode == 0, f"{name}: the one-ulp run ran ({p.returncode}) {p.stderr.strip()[-300:]}")
        ulp = os.path.join(args.work, name + "_ulp") if p.returncode == 0 else None
    for n, out in ran:
        s = compare(name, one, out, dx, scale_p, f"{n} ranks", ulp)
        check(s["ranks"]["count"] == n and s["ranks"]["halo_bytes_per_step"] > 0 and s["ranks"]["fluid_imbalance"] < 1.2,
              f"{name}: summary.json reports {s['ranks']} (fluid imbalance gate 1.2: rebalanced above 1.1)")

# open channels: particles created at the inlet (new ids numbered in rank order after every id given so far) and
# deleted past the outlet on other ranks than the first. Federico's imposed parabolic inflow (laminar channel, coarse),
# and Kazemi's averaged inflow (rough-bed channel without its mixing-length model) with nodes on another rank than the
# particles that ask: the inflow's velocity from 0.15 m downstream (recycling), the outflow's pressure from the inlet
# and its velocity extrapolated. Gauges read where their points are (profiles, fluxes, depths) and the cumulative
# boundary volumes. Counts, masses and the masses through the boundaries must agree as above (the same particles
# cross the zones' lines on the same steps); profiles and fluxes within 1e-4 of their largest value (the periodic
# channels' gate). Round-off-driven differences are ~5e-7 in the viscous laminar channel after 1 s; the rough-bed
# channel without its turbulence model is nearly inviscid over a no-slip bed and amplifies them: 5e-5 to 8e-4 after
# 0.3 s, whether the inflow is averaged or imposed and whether its nodes lie on the asking rank or not (so the
# averaging across ranks adds nothing to them), ~1e-6 over the 0.06 s compared here (5 new inflow particles per
# column, outflow particles deleted from the start). A node averaged on the wrong rank or read for the wrong
# particle moves the inflow state by percents at the first step.
GAUGES_CH = [{"name": "energy", "type": "energy"}, {"name": "volumes", "type": "boundary_volume"}]
channels = [
    ("channel_laminar", "channel_laminar.yaml", {"particles.dx": 0.005, "time.end": 1.0, "time.output_interval": 0.1},
     GAUGES_CH + [{"name": "u_prof", "type": "velocity_profile", "start": [0.12, 0.0], "end": [0.12, 0.1], "points": 11},
                  {"name": "q_in", "type": "flux", "start": [0.03, 0.0], "end": [0.03, 0.15], "points": 31},
                  {"name": "q_out", "type": "flux", "start": [0.21, 0.0], "end": [0.21, 0.15], "points": 31}]),
    ("channel_averaged", "rough_bed_S004H50.yaml",
     {"turbulence.model": "none", "open_boundaries.0.average_at": 0.15, "open_boundaries.1.velocity": "extrapolated",
      "open_boundaries.1.pressure": "inlet", "time.end": 0.06, "time.output_interval": 0.006},
     GAUGES_CH + [{"name": "u_prof", "type": "velocity_profile", "start": [0.1, 0.00125], "end": [0.1, 0.0593], "points": 11},
                  {"name": "stress", "type": "stress_profile", "start": [0.1, 0.00125], "end": [0.1, 0.0593], "points": 11},
                  {"name": "q_mid", "type": "flux", "start": [0.1, 0.0], "end": [0.1, 0.1], "points": 41},
                  {"name": "depth", "type": "depth_profile", "start": [0.02, 0.0], "end": [0.18, 0.0], "points": 5}]),
]
# Federico's pollutant release into an open channel (coarse), with a flux source on the bed that straddles the cut
# (its release shared among the fluid near it on both ranks): the scalar's mass, profile and fluxes as above
with open(os.path.join(ROOT, "cases", "channel_release.yaml")) as f:
    CR_GAUGES = yaml.safe_load(f)["gauges"]
channels.append(("channel_scalar", "channel_release.yaml",
                 {"particles.dx": 0.01, "time.end": 1.0, "time.output_interval": 0.1,
                  "transport.scalars.0.sources": [{"shape": "box", "min": [0.4, -0.05], "max": [0.6, 0.0], "flux": 0.01}]},
                 CR_GAUGES))
# two phases (Federico's air bubble in water, coarse, its first 0.01 s: the case's small air time step makes it
# slow): the phase field travels with the particles and the bubble's gauge (area, top, centroid) is reduced
with open(os.path.join(ROOT, "cases", "bubble_air.yaml")) as f:
    BUB_GAUGES = yaml.safe_load(f)["gauges"]
channels.append(("bubble_air", "bubble_air.yaml",
                 {"particles.dx": 0.02, "time.end": 0.01, "time.output_interval": 0.002}, BUB_GAUGES))
ones = run_ones([(variant(src, name, sets, gauges), os.path.join(args.work, name + "_1"))
                 for name, src, sets, gauges in channels])
for (name, src, sets, gauges), p1 in zip(channels, ones):
    one, ran = one_and_ranks(name, os.path.join(args.work, name + ".yaml"), p1)
    if one is None:
        continue
    sa = json.load(open(os.path.join(one, "summary.json")))
    if name.startswith("channel"):
        check(sa["mass"]["inflow"] > 0 and sa["mass"]["outflow"] > 0, f"{name}: water enters and leaves ({sa['mass']})")
    for n, out in ran:
        sb = json.load(open(os.path.join(out, "summary.json")))
        for k in ("fluid", "inflow", "outflow", "wall", "total"):
            check(sa["particles"].get(k) == sb["particles"].get(k),
                  f"{name} {n} ranks: {k} particles {sa['particles'].get(k)} / {sb['particles'].get(k)}")
        for k in ("initial", "final", "inflow", "outflow"):
            ma, mb = sa["mass"][k], sb["mass"][k]
            check(abs(ma - mb) <= 1e-12 * abs(ma), f"{name} {n} ranks: {k} mass {ma:.15g} / {mb:.15g}")
        for g in gauges:
            ga, gb = gauge(one, g["name"]), gauge(out, g["name"])
            cols = [c for c in ga if c != "time"]
            rows = len(ga["time"])
            check(rows >= 3 and len(gb["time"]) == rows, f"{name} {n} ranks: gauge {g['name']} has {rows} rows in both")
            big = max((abs(x) for c in cols for x in ga[c] if x == x), default=0.0) or 1.0
            worst = 0.0
            for c in cols:
                for x, y in zip(ga[c], gb[c]):
                    worst = max(worst, math.inf if (x != x) != (y != y) else (abs(x - y) if x == x else 0.0))
            check(worst <= 1e-4 * big, f"{name} {n} ranks: gauge {g['name']} differs by {worst / big:.2e} of its largest "
                  f"value (gate 1e-4)")
        snap = sorted(x for x in os.listdir(os.path.join(out, "snapshots")) if x.endswith(".h5"))[-1]
        with h5py.File(os.path.join(out, "snapshots", snap)) as f:
            ids = list(f["id"][:])
        with h5py.File(os.path.join(one, "snapshots", snap)) as f:
            ids1 = list(f["id"][:])
        check(len(set(ids)) == len(ids) and sorted(ids) == sorted(ids1),
              f"{name} {n} ranks: the last snapshot's {len(ids)} ids are unique and those of one process")

# a moving wall: Tsurudome's solitary-wave flume (a piston paddle, a 1:2.08 slope), coarse, to t = 2.5 (the wave
# runs up the slope from t ~ 2). The paddle moves on the first rank, the slope is on the last; the paddle's force
# is a sum over the ranks' wall particles and the run-up gauge's stretches are reduced over the ranks. This acoustic
# WCSPH flow amplifies round-off (the force on the paddle is a pressure integral), so the gate is calibrated in the
# same run: the ranks must stay within 5 times what one process differs by with gravity one float ulp larger or
# smaller, the larger of the two (measured: force 1.2 N against 2.2 N by t = 3, run-up 6e-4 m against 6e-4 m, levels
# 1.4e-4 against 6.5e-4). One perturbed run is one sample of a chaotic divergence: after the wall slopes' rows
# changed at the toe (2026-11-27), +1 ulp moved the paddle's force by 0.033 N where the ranks moved it by 0.21 N
# (before: 2.4 N against 0.69 N), so the gate takes two.
with open(os.path.join(ROOT, "cases", "runup_flume_a.yaml")) as f:
    RU_GAUGES = yaml.safe_load(f)["gauges"]
ru_sets = {"particles.dx": 0.02, "time.end": 2.5, "time.output_interval": 0.05, "time.snapshot_interval": 0.5}
ru_out, ru_case, ok = one_and_ulps("runup", "runup_flume_a.yaml", ru_sets, RU_GAUGES)
for n in RANKS if ok else []:
    out = os.path.join(args.work, f"runup_{n}")
    p = run(n, ru_case, out)
    check(p.returncode == 0, f"runup flume: {n} ranks ran ({p.returncode}) {p.stderr.strip()[-300:]}")
    if p.returncode != 0:
        continue
    sa, sb = (json.load(open(os.path.join(d, "summary.json"))) for d in (ru_out["one"], out))
    check(sa["particles"] == sb["particles"], f"runup flume {n} ranks: particle counts {sb['particles']}")
    for gname, col in (("paddle", "displacement"), ("paddle", "force_x"), ("eta_1", "level"), ("eta_toe", "level"),
                       ("runup", "runup")):
        ulp_gate(f"runup flume {n} ranks", ru_out["one"], out, (ru_out["ulp"], ru_out["ulpm"]), gname, col,
                 exact=col == "displacement")

# resolution levels (issue 42): the 2D dam break at a/10 with a level-1 box over the downstream wall, symplectic, to
# t = 0.6 s (the surge is split as it enters the box, about 120 splits). The ranks balance work (a level-1 particle
# weighs 4) and give new particles ids in rank order; merges take partners of one rank only. Gates: the mass
# conserved (1e-12) and the same as one process's; every id once; the front within 5 times what one process differs
# by with gravity one float ulp larger or smaller or with its pair sums in another order (the other cell list, which
# finds the same pairs: the kind of difference the ranks make); the wall sensor (the point probe at (0.584, 0.0146),
# the ISPH dam breaks' above) as the dam breaks above: within 0.1 rho g H at every sample and 0.01 rho g H in its
# mean over the second half, or 5 times the references' if larger. After the impact this probe reads the surge's
# acoustic ringing, and a gate of 5 times the references alone failed on a sample (2026-11-30: 191 Pa on 2 ranks
# against references 11-31 Pa, while a run with snapshots every 0.02 s showed the ranks' and the reordered run's
# fields apart by the same amounts, tests/mpi/README.md).
with open(os.path.join(ROOT, "cases", "dambreak_2d.yaml")) as f:
    DB_GAUGES = yaml.safe_load(f)["gauges"]
lv_sets = {"particles.dx": 0.0146, "scheme.integrator": "symplectic", "time.end": 0.6, "time.output_interval": 0.01,
           "time.snapshot_interval": 0.1,
           "resolution": {"regions": [{"shape": "box", "min": [0.38, 0.0], "max": [0.6, 0.8], "level": 1}]}}
LV_RHO_G_H = 1000 * 9.81 * 0.292  # the column's height 2a (the ISPH dam breaks' scale above)


def levels_block(tag, sets, cells_order):
    """The levels gates above for the variant `tag` of the refined dam break (sets); cells_order: the other cell
    list for the reordered reference."""
    reorder = {"resolution": {**sets["resolution"], "cells": cells_order}}
    lv_out, lv_case, ok = one_and_ulps(tag, "dambreak_2d.yaml", sets, DB_GAUGES, reorder=reorder)
    refs = (lv_out["ulp"], lv_out["ulpm"], lv_out["order"])
    for n in RANKS if ok else []:
        out = os.path.join(args.work, f"{tag}_{n}")
        p = run(n, lv_case, out)
        check(p.returncode == 0, f"{tag}: {n} ranks ran ({p.returncode}) {p.stderr.strip()[-300:]}")
        if p.returncode != 0:
            continue
        sa, sb = (json.load(open(os.path.join(d, "summary.json"))) for d in (lv_out["one"], out))
        ra, rb = sa["resolution"], sb["resolution"]
        check(rb["splits"] > 50 and abs(sb["mass"]["relative_error"]) <= 1e-12
              and abs(sb["mass"]["final"] - sa["mass"]["final"]) <= 1e-12 * sa["mass"]["final"],
              f"{tag} {n} ranks: {rb['splits']} splits, {rb['merges']} merges, fluid per level {rb['fluid_per_level']} "
              f"(one process: {ra['splits']}, {ra['merges']}, {ra['fluid_per_level']}); mass error "
              f"{sb['mass']['relative_error']:.1e}, final mass {sb['mass']['final']:.15g} / {sa['mass']['final']:.15g}")
        last = sorted(x for x in os.listdir(os.path.join(out, "snapshots")) if x.endswith(".h5"))[-1]
        with h5py.File(os.path.join(out, "snapshots", last)) as f:
            ids = list(f["id"][:])
        check(len(set(ids)) == len(ids), f"{tag} {n} ranks: the last snapshot's {len(ids)} ids are unique")
        ulp_gate(f"{tag} {n} ranks", lv_out["one"], out, refs, "front", "front")
        ulp_gate(f"{tag} {n} ranks", lv_out["one"], out, refs, "p_wall_right", "pressure", floor=0.1 * LV_RHO_G_H,
                 mean_floor=0.01 * LV_RHO_G_H)


levels_block("levels", lv_sets, "level0")
# the same with the multirate step (the box's particles sub-cycled, docs/numerics.md §14) and the finest cells
# (each cell's stencil narrowed to its pairs, with the halo's images among them): the same gates
levels_block("levels_mr", {**lv_sets, "resolution": {**lv_sets["resolution"], "multirate": True, "cells": "finest"}},
             "levels")

# restart on another rank count: the one-process 2D run's snapshot at t = 1 continued on 2 ranks to t = 2
snaps = sorted(os.listdir(os.path.join(args.work, "dambreak_2d_1", "snapshots")))
mid = [s for s in snaps if s.endswith(".h5")][10]  # t = 1.0 (every 0.1)
cont = os.path.join(args.work, "dambreak_2d_restart2")
p = run(2, os.path.join(args.work, "dambreak_2d.yaml"), cont,
        ["--restart", os.path.join(args.work, "dambreak_2d_1", "snapshots", mid)])
check(p.returncode == 0, f"restart on 2 ranks from {mid} ran ({p.returncode}) {p.stderr.strip()[-300:]}")
if p.returncode == 0:
    ea, eb = gauge(os.path.join(args.work, "dambreak_2d_1"), "energy"), gauge(cont, "energy")
    fa, fb = gauge(os.path.join(args.work, "dambreak_2d_1"), "front"), gauge(cont, "front")
    check(abs(eb["time"][-1] - 2.0) < 1e-9, f"restart on 2 ranks reached t = {eb['time'][-1]}")
    check(abs(ea["total"][-1] - eb["total"][-1]) <= 1e-4 * abs(ea["total"][0]) and abs(fa["front"][-1] - fb["front"][-1]) <= 0.01 * 0.0125,
          f"restart on 2 ranks ends where one process does: energy {eb['total'][-1]:.6g} / {ea['total'][-1]:.6g}, "
          f"front {fb['front'][-1]:.6g} / {fa['front'][-1]:.6g}")

def end_diff(a, b):
    """Energy (relative) and front differences of two runs' last gauge rows (a restarted run's gauges start at the
    restart time), with both last rows' times."""
    ea, eb = gauge(a, "energy"), gauge(b, "energy")
    fa, fb = gauge(a, "front"), gauge(b, "front")
    return (abs(ea["total"][-1] - eb["total"][-1]) / abs(ea["total"][0]), abs(fa["front"][-1] - fb["front"][-1]),
            ea["time"][-1], eb["time"][-1])


# snapshots of a distributed run: gathered on the first rank, one file per output time as one process writes
d1, d2 = os.path.join(args.work, "dambreak_2d_1"), os.path.join(args.work, "dambreak_2d_2")
s1 = sorted(x for x in os.listdir(os.path.join(d1, "snapshots")) if x.endswith(".h5"))
s2 = sorted(x for x in os.listdir(os.path.join(d2, "snapshots")) if x.endswith(".h5"))
check(s1 == s2 and len(s2) == 21, f"2 ranks write the same {len(s1)} snapshot files as one process ({len(s2)})")
with h5py.File(os.path.join(d2, "snapshots", s2[-1])) as f:
    ids = list(f["id"][:])
    conn = list(f["connectivity"][:])
    n_xyz = f["position"].shape
check(sorted(ids) == list(range(len(ids))) and conn == list(range(len(ids))) and n_xyz == (len(ids), 3),
      f"the last 2-rank snapshot holds every particle once ({len(ids)} ids, connectivity 0..N-1, positions {n_xyz})")
sw = json.load(open(os.path.join(d2, "summary.json")))["ranks"]["snapshot_writes"]
check(sw == args.snapshot_writes if args.snapshot_writes else sw in ("collective", "gathered"),
      f"summary.json says how the 2 ranks wrote their snapshots: {sw} (expected: {args.snapshot_writes or 'either'})")
print(f"snapshot writes of the 2-rank runs: {sw} ('collective': parallel HDF5, every rank its own rows)")
check(os.path.exists(os.path.join(d2, "particles.xdmf")), "2 ranks write particles.xdmf")

# a restart point written by 2 ranks, continued in one process: ends where the 2-rank run does
cont1 = os.path.join(args.work, "dambreak_2d_restart1")
p = run(1, os.path.join(args.work, "dambreak_2d.yaml"), cont1, ["--restart", os.path.join(d2, "snapshots", s2[10])])
check(p.returncode == 0, f"restart in one process from the 2-rank {s2[10]} ran ({p.returncode}) {p.stderr.strip()[-300:]}")
if p.returncode == 0:
    de, df, ta, tb = end_diff(d2, cont1)
    check(ta == tb and de <= 1e-4 and df <= 0.01 * 0.0125,
          f"it ends (t = {tb}) where the 2-rank run does: energy {de:.2e}, front {df / 0.0125:.2e} dx")

# a rank killed mid-run: the snapshots already written are whole, and the last one restarts on 2 ranks
killed = os.path.join(args.work, "dambreak_2d_killed")
cmd = mpirun(2) + [args.binary, "run", os.path.join(args.work, "dambreak_2d.yaml"), "-o", killed, "-q", "--threads", "1"]
proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
snapdir = os.path.join(killed, "snapshots")
t0 = time.time()
while proc.poll() is None and time.time() - t0 < 600:
    if os.path.isdir(snapdir) and len([x for x in os.listdir(snapdir) if x.endswith(".h5")]) >= 8:
        break
    time.sleep(0.01)
ranks_pids = subprocess.run(["pgrep", "-P", str(proc.pid)], capture_output=True, text=True).stdout.split()
if ranks_pids:
    os.kill(int(ranks_pids[-1]), signal.SIGKILL)  # one rank (not mpirun)
proc.wait(timeout=120)
left = sorted(x for x in os.listdir(snapdir) if x.endswith(".h5"))
check(proc.returncode != 0 and 8 <= len(left) < 21, f"killing one rank stops the run (exit {proc.returncode}) with {len(left)} snapshots")
whole = True
for x in left:
    try:
        with h5py.File(os.path.join(snapdir, x)) as f:
            whole &= len(f["id"]) == len(ids)
    except OSError:
        whole = False
check(whole, "every snapshot left is readable and holds every particle")
again = os.path.join(args.work, "dambreak_2d_after_kill")
p = run(2, os.path.join(args.work, "dambreak_2d.yaml"), again, ["--restart", os.path.join(snapdir, left[-1])])
check(p.returncode == 0, f"restart on 2 ranks from {left[-1]} after the kill ran ({p.returncode})")
if p.returncode == 0:
    de, df, ta, tb = end_diff(d2, again)
    check(ta == tb and de <= 1e-4 and df <= 0.01 * 0.0125,
          f"it ends (t = {tb}) where the uninterrupted 2-rank run does: energy {de:.2e}, front {df / 0.0125:.2e} dx")

# refused, with a message that names what
for what, case, needle, extra in [
        ("ISPH with Eigen's solver", os.path.join(ROOT, "cases", "dambreak_2d.yaml"), "bicgstab",
         ["--set=scheme.type=isph", "--set=scheme.solver.type=bicgstab"]),
        ("the dual integrator's kept pairs", os.path.join(ROOT, "cases", "dambreak_sphinxsys.yaml"), "scheme.pairs: advection",
         [])]:
    out = os.path.join(args.work, "refused")
    p = run(2, case, out, ["--set=time.end=0.01"] + extra)
    msg = [line for line in p.stderr.splitlines() if line.startswith("error:")]
    check(p.returncode == 2 and any(needle in line for line in msg), f"2 ranks refuse {what}: exit {p.returncode}, {msg[:1]}")

finish("check_ranks")
