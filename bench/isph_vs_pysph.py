#!/usr/bin/python3
"""SPHFlume against PySPH, each code with its weakly-compressible and its incompressible scheme, side by side in
one run of this script, on two of PySPH's own cases:

1. dambreak: PySPH's 2D dam break, `python3 -m pysph.examples.dam_break_2d` (a column 1 m x 2 m in a tank 4 m
   long, dx = 0.03, h = 1.3 dx, tf = 2.5 s) with `--scheme wcsph` (WendlandQuintic, PEC, adaptive dt) and
   `--scheme sisph` (Muta, Ramachandran & Negi 2020; QuinticSpline); SPHFlume runs cases/dambreak_pysph.yaml (the
   same particles) as written (WCSPH) and with `--set scheme.type=isph` (its default formulation, lind since
   issue 57; Tsurudome's with `--isph-set scheme.formulation=tsurudome`). Metrics: the surge front against Martin &
   Moyce (1952, n^2 = 2; bench/data/martin_moyce_1952.csv), the bed pressure next to the downstream wall, energy.
2. tank: PySPH's hydrostatic tank, `python3 -m pysph.examples.hydrostatic_tank` (WCSPH; H = 0.9 m, g = 1 m/s^2,
   dx = 0.02, h = 1.2 dx, QuinticSpline, tf = 2 s) and the same tank under SISPHScheme
   (bench/pysph_hydrostatic_sisph.py); SPHFlume runs cases/hydrostatic_pysph.yaml under both schemes. Metrics:
   the bottom pressure at the tank centre against rho g H (mean over the last quarter of the run), max |u|.

Both codes are read by the same gauges from their particle output (fluid particles only, in SPHFlume's frame:
wall faces at x = 0 and z = 0; PySPH's dam break is shifted by dx/2 to it): the front is the furthest fluid
particle with at least 3 others within 2 dx (SPHFlume's `front` gauge; the raw max x is reported beside it),
pressures are a linear MLS fit of the fluid pressure at the point (Wendland C2, h = 1.3 dx). SPHFlume's own
gauges are kept in results.json too. The front error is the RMS of Z_sim - Z_exp (Z = front / a, a = 1.02 m,
the column's width in both codes: 34 particles of the same mass) at the measured points with Z < 3.8 and T =
t sqrt(2 g / a) inside the simulated range; the primary data set is a = 2.25 in (the larger column), a = 1.125 in
is in results.json.

Time to solution: each run is a separate process, strictly one after the other; the process wall time is
measured here (PySPH: with its set-up but after an untimed warm-up run that compiles its kernels into ~/.pysph),
and each code's own time-loop figure is recorded beside it (PySPH's `cpu_time` in its .info file, which is the
wall time of Application.solve(); SPHFlume's summary.json `wall_seconds`).

PySPH 1.0b1 (Debian) needs, and gets here: `--nnps box` (its default linked-list search dies with SIGSEGV in the
WCSPH dam break at t = 1.01 s), `--timestep` for the SISPH dam break (the example loses its own dt), `-z`. A run
that goes on with NaNs (PySPH's WCSPH dam break from t = 1.016 s) is flagged, and its metrics use the outputs before.
Details and measured times: bench/README.md.

Prints the machine, the commit and one table; writes results.json and isph_vs_pysph.png to --out.
Usage:
  /usr/bin/python3 bench/isph_vs_pysph.py [--sphflume PATH] [--threads 1] [--out DIR] [--cases dambreak,tank]
        [--codes sphflume,pysph] [--schemes wcsph,isph] [--quick] [--reuse [CODES]] [--pysph-dir DIR]
        [--set KEY=VALUE ...] [--isph-set KEY=VALUE ...]
  --quick          end times 0.4 s (a smoke test: the front reaches T = 1.75, two measured points)
  --reuse [CODES]  re-analyse the runs already complete in --out (or --pysph-dir) instead of running them again;
                   CODES limits it, e.g. `--reuse pysph` re-runs SPHFlume and reads PySPH's earlier runs
  --pysph-dir DIR  where PySPH's runs are written and read (default: --out)
  --isph-set       extra `--set` for SPHFlume's ISPH runs only (e.g. 'scheme.shifting={coefficient: 2}')
"""
import argparse
import csv
import glob
import json
import math
import os
import platform
import shutil
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from isph_vs_wcsph import cpu_and_commit  # noqa: E402

import numpy as np

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
PY = "/usr/bin/python3" if os.path.exists("/usr/bin/python3") else sys.executable
MM_CSV = os.path.join(ROOT, "bench", "data", "martin_moyce_1952.csv")
PRIMARY = "a2.25in"
Z_MAX = 3.8  # measured points used: Z < 3.8 (the tank is 3.99 / 1.02 = 3.91 a long)

# The two cases, as PySPH's examples set them up (read from pysph/examples/*.py, PySPH 1.0b1)
CASES = {
    "dambreak": dict(
        case="dambreak_pysph.yaml", dx=0.03, g=9.81, tf=2.5, quick_tf=0.4, a=1.02, H=2.01, rho0=1000.0,
        pysph_shift=0.015,  # PySPH's first wall rows are at x = 0, y = 0: its faces at dx/2
        points={"p_bed_right": (3.89, 0.0), "p_wall_right": (3.99, 0.102)}),
    "tank": dict(
        case="hydrostatic_pysph.yaml", dx=0.02, g=1.0, tf=2.0, quick_tf=0.4, H=0.9, rho0=1000.0,
        pysph_shift=0.0,  # the example's lattice already has its faces at 0
        points={"p_bottom": (1.0, 0.0), "p_mid": (1.0, 0.45)}),
}
# PySPH's dam_break_2d.py prints "SISPH dt = 0.125 h / vref" and passes it to configure_solver, but then calls
# configure_solver a second time without it, which makes a new Solver with the default dt = 1e-3 and pfreq = 100:
# --timestep restores the dt the example means.
SISPH_DB_DT = 0.125 * 1.3 * 0.03 / math.sqrt(2 * 9.81 * 2.0)


def machine():
    cpu, commit = cpu_and_commit()
    dirty = subprocess.run(["git", "-C", ROOT, "status", "--porcelain", "--untracked-files=no", "--", "src", "app"],
                           capture_output=True, text=True).stdout.strip()
    try:
        import pysph
        pv = pysph.__version__
    except ImportError:
        pv = "not installed"
    return dict(cpu=cpu, cores=os.cpu_count(), system=platform.system(), commit=commit,
                src_modified=bool(dirty), pysph=pv)


# ---------------------------------------------------------------- runs

def pysph_cmd(case, scheme, quick, threads):
    c = CASES[case]
    if case == "dambreak":
        cmd = [PY, "-m", "pysph.examples.dam_break_2d", "--scheme", scheme]
        cmd += ["--timestep", f"{SISPH_DB_DT:.6g}", "--pfreq", "10"] if scheme == "sisph" else ["--pfreq", "50"]
    elif scheme == "sisph":
        cmd = [PY, os.path.join(ROOT, "bench", "pysph_hydrostatic_sisph.py"), "--pfreq", "10"]
    else:
        cmd = [PY, "-m", "pysph.examples.hydrostatic_tank", "--pfreq", "50"]
    # compressed HDF5 output; box-sort neighbour search: the default linked list ("ll") of PySPH 1.0b1 in Debian 12
    # crashes (SIGSEGV) in the WCSPH dam break at t = 1.01 s, after the run-up on the far wall (bench/README.md)
    cmd += ["-z", "--nnps", "box"]
    if quick:
        cmd += ["--tf", f"{c['quick_tf']:g}"]
    if threads > 1:
        cmd += ["--openmp"]
    return cmd


def pysph_env(threads):
    env = dict(os.environ)
    env["OMP_NUM_THREADS"] = str(threads)
    return env


def file_sha1(path):
    import hashlib
    with open(path, "rb") as f:
        return hashlib.sha1(f.read()).hexdigest()


def binary_id(path):
    st = os.stat(path)
    return f"{st.st_size} bytes, modified {time.strftime('%Y-%m-%d %H:%M:%S', time.localtime(st.st_mtime))}"


def read_json(path):
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError):
        return None


def fresh_dir(d, parent):
    """Empties d (a run folder of this script, inside parent) for a new run."""
    d, parent = os.path.abspath(d), os.path.abspath(parent)
    if os.path.isdir(d):
        if os.path.dirname(d) != parent:
            raise SystemExit(f"refusing to remove {d}: not a run folder of {parent}")
        shutil.rmtree(d)
    os.makedirs(d)


def run_pysph(a, case, scheme, d, tf, reuse):
    """Runs one PySPH case into d; returns its run record (dict)."""
    rec = read_json(os.path.join(d, "run.json"))
    cmd = pysph_cmd(case, scheme, a.quick, a.threads)
    if reuse and rec and rec.get("returncode") == 0 and rec.get("completed") and rec.get("command") == cmd + ["-d", d]:
        print(f"  reusing {d} ({rec['process_seconds']:.1f} s when run, {rec.get('date', '?')})", flush=True)
        return rec
    # untimed warm-up: compiles (or finds in ~/.pysph) this scheme's kernels
    warm = tempfile.mkdtemp(prefix="pysph-warm-")
    t0 = time.perf_counter()
    w = subprocess.run(cmd + ["--max-steps", "1", "--disable-output", "-d", warm], env=pysph_env(a.threads),
                       capture_output=True, text=True)
    shutil.rmtree(warm, ignore_errors=True)
    print(f"  warm-up (kernel compilation) {time.perf_counter() - t0:.1f} s, exit {w.returncode}", flush=True)
    fresh_dir(d, os.path.dirname(d))
    full = cmd + ["-d", d]
    print("  running: OMP_NUM_THREADS=%d %s" % (a.threads, " ".join(full)), flush=True)
    t0 = time.perf_counter()
    with open(os.path.join(d, "stdout.log"), "w") as log:
        r = subprocess.run(full, env=pysph_env(a.threads), stdout=log, stderr=subprocess.STDOUT)
    wall = time.perf_counter() - t0
    info = {}
    for fn in glob.glob(os.path.join(d, "*.info")):
        info = read_json(fn) or {}
    if not info.get("completed"):
        info["cpu_time"] = None  # (a crashed run leaves 0 there)
    rec = dict(code="pysph", case=case, scheme=scheme, command=full, threads=a.threads, tf=tf, returncode=r.returncode,
               process_seconds=wall, loop_seconds=info.get("cpu_time"), completed=bool(info.get("completed")),
               date=time.strftime("%Y-%m-%d %H:%M:%S"))
    with open(os.path.join(d, "run.json"), "w") as f:
        json.dump(rec, f, indent=1)
    print(f"  done: exit {r.returncode}, {wall:.1f} s (PySPH's solve: {fmt(info.get('cpu_time'), '.1f')} s)", flush=True)
    if r.returncode != 0:
        with open(os.path.join(d, "stdout.log")) as f:
            print(f.read()[-2000:])
    return rec


def run_sphflume(a, case, scheme, d, tf, reuse):
    rec = read_json(os.path.join(d, "run.json"))
    s = read_json(os.path.join(d, "summary.json"))
    cmd = [a.sphflume, "run", os.path.join(ROOT, "cases", CASES[case]["case"]), "--output", d, "-q",
           "--threads", str(a.threads)]
    sets = [f"time.end={tf:g}"] if a.quick else []
    if scheme == "isph":
        sets += ["scheme.type=isph"] + a.isph_set
    sets += a.set
    for kv in sets:
        cmd += ["--set", kv]
    case_sha = file_sha1(os.path.join(ROOT, "cases", CASES[case]["case"]))
    binary = binary_id(a.sphflume)
    if reuse and rec and s and rec.get("command") == cmd and rec.get("case_sha1") == case_sha:
        print(f"  reusing {d} ({rec['process_seconds']:.1f} s when run, {rec.get('date', '?')}, exit {rec['returncode']})",
              flush=True)
        if rec.get("binary") != binary:
            print(f"  (the binary has changed since: {rec.get('binary')} then, {binary} now)", flush=True)
        return rec
    fresh_dir(d, os.path.dirname(d))
    print("  running:", " ".join(cmd), flush=True)
    t0 = time.perf_counter()
    r = subprocess.run(cmd, capture_output=True, text=True)
    wall = time.perf_counter() - t0
    with open(os.path.join(d, "stdout.log"), "w") as f:
        f.write(r.stdout + r.stderr)
    s = read_json(os.path.join(d, "summary.json")) or {}
    rec = dict(code="sphflume", case=case, scheme=scheme, command=cmd, case_sha1=case_sha, binary=binary,
               threads=a.threads, tf=tf, returncode=r.returncode,
               process_seconds=wall, loop_seconds=s.get("wall_seconds"), completed=r.returncode == 0,
               date=time.strftime("%Y-%m-%d %H:%M:%S"))
    with open(os.path.join(d, "run.json"), "w") as f:
        json.dump(rec, f, indent=1)
    print(f"  done: exit {r.returncode}, {wall:.1f} s (time loop {s.get('wall_seconds', float('nan')):.1f} s, "
          f"{s.get('steps', '?')} steps)", flush=True)
    if r.returncode != 0:
        print((r.stdout + r.stderr)[-2000:])
    return rec


# ---------------------------------------------------------------- reading the particles

def pysph_frames(d, shift):
    """[(t, step, {x, z, u, w, p, m, rho})] of PySPH's fluid, in SPHFlume's frame (x, z - shift)."""
    from pysph.solver.utils import get_files, load
    files = [f for f in get_files(d) if not os.path.basename(f).startswith("results")]
    out = []
    for fn in files:
        data = load(fn)
        sd, fl = data["solver_data"], data["arrays"]["fluid"]
        # (copies: get() returns views of the array's buffers, freed with it)
        out.append((float(sd["t"]), int(sd["count"]), dict(
            x=np.array(fl.get("x")) - shift, z=np.array(fl.get("y")) - shift, u=np.array(fl.get("u")),
            w=np.array(fl.get("v")), p=np.array(fl.get("p")), m=np.array(fl.get("m")), rho=np.array(fl.get("rho")))))
    out.sort(key=lambda f: f[0])
    return out


def sphflume_frames(d):
    import h5py
    out = []
    for i, fn in enumerate(sorted(glob.glob(os.path.join(d, "snapshots", "snap_*.h5")))):
        with h5py.File(fn, "r") as f:
            k = f["kind"][:] == 0
            pos, vel = f["position"][:][k], f["velocity"][:][k]
            out.append((float(f.attrs["time"]), i, dict(
                x=pos[:, 0], z=pos[:, -1], u=vel[:, 0], w=vel[:, -1], p=f["pressure"][:][k], m=f["mass"][:][k],
                rho=f["density"][:][k])))
    out.sort(key=lambda f: f[0])
    return out


def front(x, z, dx):
    """The furthest fluid particle along x with at least 3 others within 2 dx (SPHFlume's front gauge)."""
    r2 = (2.0 * dx) ** 2
    for i in np.argsort(-x)[:2000]:
        if np.count_nonzero((x - x[i]) ** 2 + (z - z[i]) ** 2 < r2) - 1 >= 3:
            return float(x[i])
    return float("nan")


def mls_pressure(f, point, h):
    """Linear MLS fit of the fluid pressure at point (Wendland C2 weights times the volume m / rho); a Shepard
    mean where the fit is ill-conditioned, NaN with fewer than 3 fluid particles in the support (dry)."""
    dx_, dz_ = f["x"] - point[0], f["z"] - point[1]
    q = np.sqrt(dx_ * dx_ + dz_ * dz_) / h
    s = q < 2.0
    n = np.count_nonzero(s)
    if n < 3:
        return float("nan")
    w = (1.0 - 0.5 * q[s]) ** 4 * (2.0 * q[s] + 1.0) * f["m"][s] / f["rho"][s]
    P = np.column_stack([np.ones(n), dx_[s], dz_[s]])
    A = P.T @ (w[:, None] * P)
    b = P.T @ (w * f["p"][s])
    if not np.all(np.isfinite(A)) or not np.all(np.isfinite(b)):
        return float("nan")
    if n < 6 or np.linalg.cond(A) > 1e6:  # a few particles (a film, spray): no gradient to fit
        return float((w * f["p"][s]).sum() / w.sum())
    return float(np.linalg.solve(A, b)[0])


def series(frames, c):
    """The common gauges over the frames of one run."""
    h = 1.3 * c["dx"]
    r = {"t": [], "front": [], "max_x": [], "max_u": [], "energy": [], "nonfinite": []}
    r.update({k: [] for k in c["points"]})
    for t, _, f in frames:
        r["t"].append(t)
        r["nonfinite"].append(int(sum(np.count_nonzero(~np.isfinite(f[k])) for k in ("x", "z", "u", "w", "p", "rho"))))
        r["front"].append(front(f["x"], f["z"], c["dx"]))
        r["max_x"].append(float(f["x"].max()))
        r["max_u"].append(float(np.sqrt(f["u"] ** 2 + f["w"] ** 2).max()))
        r["energy"].append(float((f["m"] * (0.5 * (f["u"] ** 2 + f["w"] ** 2) + c["g"] * f["z"])).sum()))
        for k, pt in c["points"].items():
            r[k].append(mls_pressure(f, pt, h))
    return {k: np.array(v) for k, v in r.items()}


def sphflume_gauges(d):
    g = {}
    for fn in glob.glob(os.path.join(d, "gauges", "*.csv")):
        try:
            arr = np.genfromtxt(fn, delimiter=",", names=True)
            g[os.path.basename(fn)[:-4]] = {n: arr[n].tolist() for n in arr.dtype.names}
        except ValueError:
            pass
    return g


# ---------------------------------------------------------------- metrics

def read_mm():
    with open(MM_CSV) as f:
        rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
    out = {}
    for r in rows:
        out.setdefault(r["series"], []).append((float(r["T"]), float(r["Z"])))
    return {k: np.array(v) for k, v in out.items()}


def front_error(T, Z, exp):
    ok = np.isfinite(Z)
    T, Z = T[ok], Z[ok]
    if len(T) < 2:
        return dict(rms=float("nan"), mean_rel=float("nan"), n=0)
    sel = (exp[:, 1] < Z_MAX) & (exp[:, 0] >= T[0]) & (exp[:, 0] <= T[-1])
    if not sel.any():
        return dict(rms=float("nan"), mean_rel=float("nan"), n=0)
    Te, Ze = exp[sel, 0], exp[sel, 1]
    Zs = np.interp(Te, T, Z)
    return dict(rms=float(np.sqrt(np.mean((Zs - Ze) ** 2))), mean_rel=float(np.mean(np.abs(Zs - Ze) / Ze)),
                mean_signed_rel=float(np.mean((Zs - Ze) / Ze)), n=int(sel.sum()), T=Te.tolist(), Z_sim=Zs.tolist(),
                Z_exp=Ze.tolist())


def first_nonfinite(s):
    """The first output time with a non-finite fluid value (PySPH's runs go on with NaNs), else None."""
    bad = np.nonzero(s["nonfinite"] > 0)[0]
    return float(s["t"][bad[0]]) if len(bad) else None


def valid(s):
    """The output rows before the first non-finite value."""
    t_bad = first_nonfinite(s)
    return s["t"] < t_bad if t_bad is not None else np.ones(len(s["t"]), bool)


def dambreak_metrics(s, c, mm):
    a, g = c["a"], c["g"]
    ok = valid(s)
    s = {k: v[ok] for k, v in s.items()}
    T = s["t"] * math.sqrt(2 * g / a)
    res = {"a": a, "T_scale": math.sqrt(2 * g / a), "valid_until": float(s["t"][-1])}
    for key in ("front", "max_x"):
        res[key] = {k: front_error(T, s[key] / a, v) for k, v in mm.items()}
        Z = s[key] / a
        hit = np.nonzero(Z >= 3.0)[0]
        res[key]["T_at_Z3"] = float(np.interp(3.0, Z[:hit[0] + 1], T[:hit[0] + 1])) if len(hit) and hit[0] > 0 else float("nan")
    pgh = c["rho0"] * g * c["H"]
    for k in c["points"]:
        p = np.nan_to_num(s[k]) / pgh
        hit = np.nonzero(p > 0.1)[0]
        t_imp = float(s["t"][hit[0]]) if len(hit) else float("nan")
        win = (s["t"] >= t_imp) & (s["t"] <= t_imp + 0.25)
        res[k] = dict(impact_t=t_imp, peak=float(p.max()),
                      mean_after_impact=float(p[win].mean()) if win.any() else float("nan"),
                      sd_after_impact=float(p[win].std()) if win.any() else float("nan"),
                      window="impact to impact + 0.25 s", unit="rho0 g H, H = %.3g m" % c["H"])
    res["energy_end_over_start"] = float(s["energy"][-1] / s["energy"][0])
    return res


def tank_metrics(s, c):
    pgh = c["rho0"] * c["g"] * c["H"]
    ok = valid(s)
    s = {k: v[ok] for k, v in s.items()}
    t = s["t"]
    win = t >= 0.75 * t[-1]
    pb = s["p_bottom"]
    return dict(rho_g_H=pgh, p_bottom_mean_last_quarter=float(np.nanmean(pb[win])),
                p_bottom_error=float(np.nanmean(pb[win]) / pgh - 1.0), p_bottom_end_error=float(pb[-1] / pgh - 1.0),
                p_bottom_sd_last_quarter=float(np.nanstd(pb[win])),
                p_mid_error=float(np.nanmean(s["p_mid"][win]) / (0.5 * pgh) - 1.0),
                max_u_end=float(s["max_u"][-1]), max_u_last_quarter=float(s["max_u"][win].max()),
                window=[float(t[win][0]), float(t[-1])])


# ---------------------------------------------------------------- output

LABEL = {("pysph", "wcsph"): "PySPH WCSPH", ("pysph", "sisph"): "PySPH SISPH",
         ("sphflume", "wcsph"): "SPHFlume WCSPH", ("sphflume", "isph"): "SPHFlume ISPH"}
STYLE = {("pysph", "wcsph"): "r-", ("pysph", "sisph"): "m-", ("sphflume", "wcsph"): "b-", ("sphflume", "isph"): "c-"}


def plot(results, mm, png):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(2, 2, figsize=(13, 9))
    db, tk = results.get("dambreak", {}), results.get("tank", {})
    c = CASES["dambreak"]
    def upto(r):  # the output rows before the first non-finite value
        s = r.get("series")
        if not s:
            return None
        n = len(s["t"]) if r.get("first_nonfinite_t") is None else int(np.searchsorted(s["t"], r["first_nonfinite_t"]))
        return {k: v[:n] for k, v in s.items()}
    for key, r in db.items():
        code, scheme = key.split("/")
        s = upto(r)
        if not s:
            continue
        T = np.array(s["t"]) * math.sqrt(2 * c["g"] / c["a"])
        ax[0, 0].plot(T, np.array(s["front"]) / c["a"], STYLE[(code, scheme)], lw=1.2, label=LABEL[(code, scheme)])
        ax[0, 1].plot(T, np.nan_to_num(np.array(s["p_bed_right"], dtype=float)) / (c["rho0"] * c["g"] * c["H"]),
                      STYLE[(code, scheme)], lw=0.8, label=LABEL[(code, scheme)])
    for k, v in mm.items():
        ax[0, 0].plot(v[:, 0], v[:, 1], "ko" if k == PRIMARY else "ks", mfc="none",
                      label=f"Martin & Moyce 1952, {k.replace('a', 'a = ', 1).replace('in', ' in')}")
    ax[0, 0].axhline(3.99 / c["a"], color="grey", lw=0.8, ls=":")
    ax[0, 0].set(xlim=(0, 4), ylim=(0.8, 4.2), xlabel="T = t sqrt(2g/a)", ylabel="Z / a (front, 3 neighbours within 2 dx)",
                 title="dam break: surge front (a = 1.02 m)")
    ax[0, 1].set(xlabel="T = t sqrt(2g/a)", ylabel="p / (rho g H), H = 2.01 m", ylim=(-2, 6),
                 title="dam break: bed pressure at x = 3.89 m (0.10 m from the wall)")
    c = CASES["tank"]
    for key, r in tk.items():
        code, scheme = key.split("/")
        s = upto(r)
        if not s:
            continue
        ax[1, 0].plot(s["t"], np.array(s["p_bottom"], dtype=float) / (c["rho0"] * c["g"] * c["H"]), STYLE[(code, scheme)],
                      lw=1, label=LABEL[(code, scheme)])
        ax[1, 1].semilogy(s["t"], np.maximum(np.array(s["max_u"]), 1e-6), STYLE[(code, scheme)], lw=1, label=LABEL[(code, scheme)])
    ax[1, 0].axhline(1.0, color="k", lw=0.8, ls="--")
    ax[1, 0].set(xlabel="t [s]", ylabel="p / (rho g H)", ylim=(0.0, 1.3),
                 title="still tank: bottom pressure at the centre (PySPH WCSPH ramps g over 1 s)")
    ax[1, 1].set(xlabel="t [s]", ylabel="max |u| [m/s]", title="still tank: largest fluid speed")
    for x in ax.ravel():
        x.grid(alpha=0.3)
        x.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(png, dpi=100)
    plt.close(fig)


def fmt(v, spec):
    return "-" if v is None or (isinstance(v, float) and not math.isfinite(v)) else format(v, spec)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--sphflume", default=os.environ.get("SPHFLUME", os.path.join(ROOT, "build", "sphflume")))
    ap.add_argument("--threads", type=int, default=1, help="SPHFlume threads; PySPH runs with OpenMP on as many when > 1")
    ap.add_argument("--out", default=os.path.join(tempfile.gettempdir(), "sphflume-bench-pysph"))
    ap.add_argument("--pysph-dir", default=None, help="where PySPH's runs go (default: --out)")
    ap.add_argument("--cases", default="dambreak,tank")
    ap.add_argument("--codes", default="sphflume,pysph")
    ap.add_argument("--schemes", default="wcsph,isph", help="wcsph and/or isph (PySPH's isph is SISPH)")
    ap.add_argument("--quick", action="store_true", help="end times 0.4 s (smoke test)")
    ap.add_argument("--reuse", nargs="?", const="sphflume,pysph", default="",
                    help="re-analyse complete runs in --out instead of running again (optionally only these codes)")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE", help="SPHFlume --set, every run")
    ap.add_argument("--isph-set", action="append", default=[], metavar="KEY=VALUE", help="SPHFlume --set, ISPH runs only")
    a = ap.parse_args()
    cases = [c for c in a.cases.split(",") if c]
    codes = [c for c in a.codes.split(",") if c]
    schemes = [s for s in a.schemes.split(",") if s]
    reuse = set(c for c in a.reuse.split(",") if c)
    for lst, ok, what in ((cases, CASES, "--cases"), (codes, ("sphflume", "pysph"), "--codes"), (schemes, ("wcsph", "isph"), "--schemes")):
        bad = [v for v in lst if v not in ok]
        if bad:
            ap.error(f"{what}: unknown {bad}")
    a.out = os.path.abspath(a.out)
    pysph_dir = os.path.abspath(a.pysph_dir or a.out)
    os.makedirs(a.out, exist_ok=True)
    os.makedirs(pysph_dir, exist_ok=True)
    if "sphflume" in codes and not os.access(a.sphflume, os.X_OK):
        raise SystemExit(f"no SPHFlume binary at {a.sphflume} (build it, or give --sphflume)")
    m = machine()
    print(f"machine: {m['cpu']}, {m['cores']} cores, {m['system']}; commit {m['commit']}"
          f"{' (src/ or app/ modified)' if m['src_modified'] else ''}; PySPH {m['pysph']}; {a.threads} thread(s)"
          f"{'; --quick' if a.quick else ''}", flush=True)
    mm = read_mm()
    sfx = "_quick" if a.quick else ""
    results = {}
    for case in cases:
        c = CASES[case]
        tf = c["quick_tf"] if a.quick else c["tf"]
        results[case] = {}
        for code in codes:
            for scheme in schemes:
                sch = "sisph" if (code == "pysph" and scheme == "isph") else scheme
                key = f"{code}/{sch}"
                print(f"\n[{case}] {LABEL[(code, sch)]}", flush=True)
                if code == "pysph":
                    d = os.path.join(pysph_dir, f"{case}_pysph_{sch}{sfx}")
                    rec = run_pysph(a, case, sch, d, tf, "pysph" in reuse)
                    frames = pysph_frames(d, c["pysph_shift"]) if os.path.isdir(d) else []
                    steps = frames[-1][1] if frames else None
                    s_own, summ = None, None
                else:
                    d = os.path.join(a.out, f"{case}_sphflume_{sch}{sfx}")
                    rec = run_sphflume(a, case, sch, d, tf, "sphflume" in reuse)
                    frames = sphflume_frames(d)
                    summ = read_json(os.path.join(d, "summary.json")) or {}
                    steps = summ.get("steps")
                    s_own = sphflume_gauges(d)
                entry = dict(run=rec, dir=d, steps=steps, outputs=len(frames), fluid=int(len(frames[0][2]["x"])) if frames else None)
                if summ:
                    entry["summary"] = {k: summ.get(k) for k in ("steps", "wall_seconds", "cpu_seconds", "simulated_time",
                                                                 "exit_status", "message", "pressure_solver", "particles",
                                                                 "ignored_keys", "warnings", "integrator")}
                    entry["sphflume_gauges"] = s_own
                if len(frames) >= 2:
                    s = series(frames, c)
                    entry["simulated_time"] = float(s["t"][-1])
                    entry["series"] = {k: [None if not math.isfinite(x) else x for x in v.tolist()] for k, v in s.items()}
                    entry["metrics"] = dambreak_metrics(s, c, mm) if case == "dambreak" else tank_metrics(s, c)
                    entry["first_nonfinite_t"] = first_nonfinite(s)
                    if entry["first_nonfinite_t"] is not None:
                        print(f"  NOTE: non-finite fluid values from t = {entry['first_nonfinite_t']:.4g} s on "
                              f"({int(s['nonfinite'][-1])} values at the end): metrics use the outputs before it", flush=True)
                results[case][key] = entry
                met = entry.get("metrics", {})
                if case == "dambreak" and met:
                    e = met["front"][PRIMARY]
                    print(f"  front RMS vs Martin & Moyce ({PRIMARY}, {e['n']} points): {fmt(e['rms'], '.3f')} a; "
                          f"T at Z = 3: {fmt(met['front']['T_at_Z3'], '.3f')}; bed pressure impact t = "
                          f"{fmt(met['p_bed_right']['impact_t'], '.3f')} s, mean over 0.25 s after it "
                          f"{fmt(met['p_bed_right']['mean_after_impact'], '.3f')} +- {fmt(met['p_bed_right']['sd_after_impact'], '.3f')} "
                          f"rho g H",
                          flush=True)
                elif met:
                    print(f"  bottom pressure {met['p_bottom_mean_last_quarter']:.2f} Pa (rho g H = {met['rho_g_H']:.1f}): "
                          f"{100 * met['p_bottom_error']:+.2f} %; max |u| at the end {met['max_u_end']:.3g} m/s", flush=True)

    # the table
    print("\n| code | scheme | dam break: time [s] (loop) | steps | front RMS vs M&M [a] (max x) | T at Z=3 | "
          "tank: time [s] (loop) | steps | p_bottom error | max abs u at end [m/s] |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for code in codes:
        for scheme in schemes:
            sch = "sisph" if (code == "pysph" and scheme == "isph") else scheme
            key = f"{code}/{sch}"
            db = results.get("dambreak", {}).get(key, {})
            tk = results.get("tank", {}).get(key, {})

            def tcell(e):
                r = e.get("run")
                if not r:
                    return "-"
                fail = "" if r.get("returncode") == 0 else f" FAILED (exit {r.get('returncode')})"
                if e.get("first_nonfinite_t") is not None:
                    fail += f" NaN from t = {e['first_nonfinite_t']:.3g} s"
                return f"{r['process_seconds']:.1f} ({fmt(r.get('loop_seconds'), '.1f')}){fail}"
            dm, tm = db.get("metrics", {}), tk.get("metrics", {})
            fr = dm.get("front", {}).get(PRIMARY, {})
            fx = dm.get("max_x", {}).get(PRIMARY, {})
            print(f"| {'PySPH' if code == 'pysph' else 'SPHFlume'} | {sch.upper()} | {tcell(db)} | {db.get('steps', '-')} | "
                  f"{fmt(fr.get('rms'), '.3f')} ({fmt(fx.get('rms'), '.3f')}), {fr.get('n', 0)} pts | "
                  f"{fmt(dm.get('front', {}).get('T_at_Z3'), '.3f')} | {tcell(tk)} | {tk.get('steps', '-')} | "
                  f"{fmt(100 * tm['p_bottom_error'] if tm else None, '+.2f')} % | {fmt(tm.get('max_u_end'), '.3g')} |")
    print(f"\nfront: Z = front / a against Martin & Moyce (1952) a = 2.25 in, points with Z < {Z_MAX} inside the run; "
          "p_bottom: mean over the last quarter of the run, against rho g H = 900 Pa")
    res = dict(machine=m, args=vars(a), pysph_dir=pysph_dir, results=results,
               notes=dict(front="furthest fluid particle with >= 3 others within 2 dx; max_x: the furthest fluid particle",
                          pressure="linear MLS of the fluid pressure, Wendland C2 at h = 1.3 dx",
                          sisph_dambreak_dt=SISPH_DB_DT))
    with open(os.path.join(a.out, "results.json"), "w") as f:
        json.dump(res, f, indent=1, default=lambda o: o.tolist() if hasattr(o, "tolist") else str(o))
    png = os.path.join(a.out, "isph_vs_pysph.png")
    plot(results, mm, png)
    print(f"wrote {os.path.join(a.out, 'results.json')} and {png}")


if __name__ == "__main__":
    main()
