#!/usr/bin/python3
"""SPHFlume against SPHinXsys on SPHinXsys's own dam breaks, side by side in one run of this script.

Builds (or finds) SPHinXsys from a source checkout the user gives, compiles its test_2d_dambreak
(and test_3d_dambreak) at the resolutions asked for, runs them and SPHFlume's matching cases one
after the other on the same machine, and reports the time-to-solution ratio together with the
results both codes give: the wall pressure at SPHinXsys's observer point, the surge front and the
mechanical energy, each from the code's own output.

Nothing of SPHinXsys is vendored: the script only reads the checkout (a copy of its Dambreak.cpp
with the particle spacing changed is compiled into the output folder with the exact command line
CMake recorded for the original, and linked the same way).

Usage:
  /usr/bin/python3 bench/vs_sphinxsys.py --sphinxsys-src PATH [--sphinxsys-build DIR]
        [--cases 2d,3d] [--dp2d 0.0125] [--dp3d 0.05,0.025] [--end 20] [--threads 2] [--out DIR]
  --sphinxsys-src   a checkout of https://github.com/Xiangyu-Hu/SPHinXsys (tested at 9f33297)
  --sphinxsys-build its CMake build folder; configured and built here (only the dam-break targets,
                    about 40 min per dimension on 2 cores) when it holds no library yet
  --cxx-flags       the flags SPHinXsys is built with (default "-O3 -march=native", the flags of
                    SPHFlume's default Release build on this machine, which also adds
                    -mprefer-vector-width=512 where the CPU has AVX-512)
  --reuse           re-read finished runs in --out instead of running again
  --skip-sphinxsys  SPHFlume only (the ratio is then not reported)

SPHinXsys needs (Debian 12): libsimbody-dev libtbb-dev libboost-dev libboost-program-options-dev
libeigen3-dev libspdlog-dev libgtest-dev (apt-get install -y ...).
"""
import argparse
import glob
import json
import math
import os
import re
import shlex
import shutil
import subprocess
import sys
import time

import numpy as np

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))

# SPHinXsys's tests and the SPHFlume cases set up the same way
SETUPS = {
    "2d": dict(test="test_2d_dambreak", src="tests/2d_examples/test_2d_dambreak/Dambreak.cpp",
               library="sphinxsys_2d", spacing_var="particle_spacing_ref",
               case=os.path.join(ROOT, "cases", "dambreak_sphinxsys.yaml"), probe_height=0.2),
    "3d": dict(test="test_3d_dambreak", src="tests/3d_examples/test_3d_dambreak/dambreak.cpp",
               library="sphinxsys_3d", spacing_var="global_resolution",
               case=os.path.join(ROOT, "cases", "dambreak_sphinxsys_3d.yaml"), probe_height=0.2),
}


def sh(cmd, cwd=None, log=None):
    print("  $", cmd if isinstance(cmd, str) else " ".join(cmd), flush=True)
    r = subprocess.run(cmd, cwd=cwd, shell=isinstance(cmd, str), capture_output=True, text=True)
    if log:
        with open(log, "a") as f:
            f.write(r.stdout + r.stderr)
    if r.returncode != 0:
        print(r.stdout[-2000:], r.stderr[-4000:], sep="\n")
        sys.exit(f"failed ({r.returncode}): {cmd}")
    return r


def ensure_sphinxsys(a, dims):
    src, bld = os.path.abspath(a.sphinxsys_src), os.path.abspath(a.sphinxsys_build)
    if not os.path.exists(os.path.join(src, "CMakeLists.txt")):
        sys.exit(f"--sphinxsys-src {src}: no CMakeLists.txt (give a SPHinXsys checkout)")
    os.makedirs(bld, exist_ok=True)
    if not os.path.exists(os.path.join(bld, "compile_commands.json")):
        sh(["cmake", src, "-DCMAKE_BUILD_TYPE=Release", f"-DCMAKE_CXX_FLAGS={a.cxx_flags}",
            "-DSPHINXSYS_DEVELOPER_MODE=OFF", "-DSPHINXSYS_USE_ONEDPL=OFF",
            "-DSPHINXSYS_BUILD_OPTIMIZATION_EXAMPLES=OFF", "-DSPHINXSYS_BUILD_EXTRA_SOURCE_AND_TESTS=OFF",
            "-DSPHINXSYS_BUILD_MODULES=OFF", "-DSPHINXSYS_BUILD_PYTHON_INTERFACE=OFF",
            "-DSPHINXSYS_BUILD_UNIT_TESTS=OFF"], cwd=bld, log=os.path.join(bld, "sphflume-bench.log"))
    for d in dims:
        t = SETUPS[d]["test"]
        exe = glob.glob(os.path.join(bld, "tests", "*", t, "bin", t))
        if not exe:
            print(f"building SPHinXsys {t} in {bld} (long: the whole {SETUPS[d]['library']} library)", flush=True)
            sh(["make", f"-j{a.jobs}", t], cwd=bld, log=os.path.join(bld, "sphflume-bench.log"))
    return src, bld


def variant(a, bld, dim, dp, work):
    """Compile SPHinXsys's dam break at particle spacing dp with its recorded command line."""
    st = SETUPS[dim]
    exe = os.path.join(work, f"{st['test']}_dp{dp:g}")
    if os.path.exists(exe):
        return exe
    with open(os.path.join(bld, "compile_commands.json")) as f:
        cmds = json.load(f)
    entry = [e for e in cmds if os.path.normpath(e["file"]).endswith(os.path.normpath(st["src"]))]
    if not entry:
        sys.exit(f"{st['src']} is not in {bld}/compile_commands.json (was {st['test']} configured?)")
    e = entry[0]
    with open(e["file"]) as f:
        code = f.read()
    pat = re.compile(r"(Real\s+%s\s*=\s*)([0-9.eE+-]+)(\s*;)" % st["spacing_var"])
    if not pat.search(code):
        sys.exit(f"{e['file']}: no 'Real {st['spacing_var']} = ...;' to change (another SPHinXsys version?)")
    code = pat.sub(lambda m: f"{m.group(1)}{dp!r}{m.group(3)}", code, count=1)
    if a.end:
        code = re.sub(r"(Real\s+end_time\s*=\s*)([0-9.]+)(\s*;)", lambda m: f"{m.group(1)}{a.end!r}{m.group(3)}", code, count=1)
    csrc, obj = exe + ".cpp", exe + ".o"
    with open(csrc, "w") as f:
        f.write(code)
    args = shlex.split(e["command"]) if "command" in e else list(e["arguments"])
    args[args.index("-o") + 1] = obj
    args[args.index("-c") + 1] = csrc
    sh(args, cwd=e["directory"])
    tdir = os.path.dirname(os.path.dirname(e["directory"] + "/x"))
    link = glob.glob(os.path.join(e["directory"], "CMakeFiles", f"{st['test']}.dir", "link.txt"))[0]
    with open(link) as f:
        largs = shlex.split(f.read())
    largs = [obj if x.endswith(".o") and os.path.basename(x).lower().startswith("dambreak") else x for x in largs]
    largs[largs.index("-o") + 1] = exe
    sh(largs, cwd=e["directory"])
    return exe


def run_sphinxsys(exe, dim, src, run_dir, reuse):
    log = os.path.join(run_dir, "stdout.log")
    if not (reuse and os.path.exists(log)):
        shutil.rmtree(run_dir, ignore_errors=True)
        os.makedirs(run_dir)
        # its regression-test reference files: read at start-up (the comparison at the end is not used)
        shutil.copytree(os.path.join(src, os.path.dirname(SETUPS[dim]["src"]), "regression_test_tool"),
                        os.path.join(run_dir, "input"))
        t0 = time.time()
        with open(log, "w") as f:
            subprocess.run([exe, "--state_recording=1"], cwd=run_dir, stdout=f, stderr=subprocess.STDOUT)
        with open(os.path.join(run_dir, "process_seconds"), "w") as f:
            f.write(f"{time.time() - t0:.3f}\n")
    text = open(log).read()
    m = re.search(r"Total wall time for computation:\s*([0-9.eE+-]+)", text)
    if not m:
        sys.exit(f"SPHinXsys run in {run_dir} did not finish (no 'Total wall time'); see {log}")
    steps = re.findall(r"N=(\d+)", text)
    out = os.path.join(run_dir, "output")
    p = np.loadtxt(os.path.join(out, "FluidObserver_Pressure.dat"), skiprows=1)
    pcol = 1 if dim == "2d" else 3  # 3D: its third observer point, height 0.2
    e = np.loadtxt(os.path.join(out, "WaterBody_TotalMechanicalEnergy.dat"), skiprows=1)
    fronts = []
    for v in sorted(glob.glob(os.path.join(out, "WaterBody_*.vtp"))):
        t, x = read_vtp(v)
        fronts.append((t, front(x, dim)))
    fronts.sort()
    return dict(wall=float(m.group(1)), process=float(open(os.path.join(run_dir, "process_seconds")).read()),
                advection_steps=int(steps[-1]) if steps else None,
                p=(p[:, 0], p[:, pcol]), energy=(e[:, 0], e[:, 1] / e[0, 1]),
                front=(np.array([f[0] for f in fronts]), np.array([f[1] for f in fronts])))


def read_vtp(path):
    text = open(path).read()
    t = float(re.search(r'Name="TimeValue"[^>]*>\s*([0-9.eE+-]+)', text).group(1))
    body = re.search(r'Name="Position"[^>]*>(.*?)</DataArray>', text, re.S).group(1)
    return t, np.array(body.split(), dtype=float).reshape(-1, 3)


def front(x, dim, dx=None):
    """Furthest particle along x with at least 3 others within 2 dx (SPHFlume's front gauge)."""
    if dx is None:  # the lattice spacing, from the nearest-neighbour distances of the first particles
        d = np.sort(np.linalg.norm(x[:200, None, :] - x[None, :, :], axis=2), axis=1)[:, 1]
        dx = float(np.median(d))
    order = np.argsort(-x[:, 0])
    for i in order[:2000]:
        n = np.count_nonzero(np.linalg.norm(x - x[i], axis=1) < 2.0 * dx) - 1
        if n >= 3:
            return float(x[i, 0])
    return float("nan")


def run_sphflume(a, dim, dp, run_dir, reuse):
    st = SETUPS[dim]
    summ = os.path.join(run_dir, "summary.json")
    if not (reuse and os.path.exists(summ)):
        cmd = [a.sphflume, "run", st["case"], "-o", run_dir, "-q", "--threads", str(a.threads),
               "--set", f"particles.dx={dp!r}"]
        if a.end:
            cmd += ["--set", f"time.end={a.end!r}"]
        for kv in a.set:
            cmd += ["--set", kv]
        t0 = time.time()
        r = subprocess.run(cmd, capture_output=True, text=True)
        if r.returncode != 0:
            print(r.stdout[-2000:], r.stderr[-2000:], sep="\n")
            sys.exit(f"SPHFlume run failed ({r.returncode})")
        with open(os.path.join(run_dir, "process_seconds"), "w") as f:
            f.write(f"{time.time() - t0:.3f}\n")
    s = json.load(open(summ))
    g = os.path.join(run_dir, "gauges")
    p = np.genfromtxt(os.path.join(g, "p_wall.csv"), delimiter=",", names=True)
    e = np.genfromtxt(os.path.join(g, "energy.csv"), delimiter=",", names=True)
    fr = np.genfromtxt(os.path.join(g, "front.csv"), delimiter=",", names=True)
    pcol = "pressure" if "pressure" in p.dtype.names else p.dtype.names[1]
    sensor = None  # the lab-sensor gauge (face and time window), when the case has one
    if os.path.exists(os.path.join(g, "p_sensor.csv")):
        q = np.genfromtxt(os.path.join(g, "p_sensor.csv"), delimiter=",", names=True)
        sensor = (q["time"], np.nan_to_num(q["pressure"]), np.nan_to_num(q["pressure_std"]))
    return dict(sensor=sensor, wall=float(s["wall_seconds"]), process=float(open(os.path.join(run_dir, "process_seconds")).read()),
                steps=int(s["steps"]), summary=s, p=(p["time"], np.nan_to_num(p[pcol])),
                energy=(e["time"], e["total"] / e["total"][0]), front=(fr["time"], fr["front"]))


def observer_series(run_dir, dim, dp, h_over_dp=1.3):
    """SPHinXsys's observer applied to SPHFlume's snapshots: the kernel (Shepard) average of the
    fluid pressure at the probe, sum p W V / sum W V with V = m / rho, Wendland C2 at SPHinXsys's
    smoothing length h = 1.3 dp, so that both codes' pressures are read by one gauge. None when
    the run wrote no snapshots or h5py is missing."""
    try:
        import h5py
    except ImportError:
        return None
    files = sorted(glob.glob(os.path.join(run_dir, "snapshots", "snap_*.h5")))
    if not files:
        return None
    probe = np.array([5.366, 0.2]) if dim == "2d" else np.array([5.366, 0.25, 0.2])  # (SPHFlume's axes)
    cols = [0, 2] if dim == "2d" else [0, 1, 2]  # (2D snapshots hold (x, 0, z))
    h = h_over_dp * dp
    ts, ps = [], []
    for fn in files:
        with h5py.File(fn, "r") as f:
            fl = f["kind"][:] == 0
            x = f["position"][:][:, cols][fl]
            p = f["pressure"][:][fl]
            v = (f["mass"][:] / f["density"][:])[fl]
            t = float(f.attrs["time"])
        q = np.linalg.norm(x - probe, axis=1) / h
        w = np.clip(1.0 - 0.5 * q, 0.0, None) ** 4 * (2.0 * q + 1.0) * v  # (the constant cancels)
        ts.append(t)
        ps.append(float((w * p).sum() / w.sum()) if w.sum() > 0 else 0.0)
    order = np.argsort(ts)
    return np.array(ts)[order], np.array(ps)[order]


def metrics(r, H=1.0, g=1.0, sensor=False):
    """Impact time (first p > 0.1 rho g H), peak, post-impact mean over t sqrt(g/H) in [2.8, 7]."""
    t, p = r["sensor"][:2] if sensor else r["p"]
    hit = np.nonzero(p > 0.1)[0]
    win = (t >= 2.8) & (t <= 7.0)
    ft, fx = r["front"]
    arrive = np.interp(4.0, fx[ft < 3.5], ft[ft < 3.5]) if np.count_nonzero(ft < 3.5) > 2 else float("nan")
    et, ee = r["energy"]
    return dict(impact=float(t[hit[0]]) if len(hit) else float("nan"), peak=float(p.max()),
                post_mean=float(p[win].mean()) if win.any() else float("nan"),
                post_std=float(p[win].std()) if win.any() else float("nan"), front_at_x4=float(arrive),
                energy_t7=float(np.interp(7.0, et, ee)), energy_end=float(ee[-1]))


def buchner():
    """validation/dambreak_buchner's rules and Buchner's (2002) measurement at the probe (None if not found)."""
    import importlib.util
    path = os.path.join(ROOT, "validation", "dambreak_buchner", "check.py")
    spec = importlib.util.spec_from_file_location("buchner_check", path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    exp = mod.measurement()
    return mod, dict(impact=exp["impact"], rise=exp["rise"], mean=exp["mean"], sd=exp["sd"])


def buchner_metrics(mod, exp, series):
    """The impact (last reading <= 0.2 before the first >= the measured post-impact mean) and the time mean over
    [2.8, 7] of one pressure series, by the validation check's rules (the same for the measurement)."""
    t, p = np.asarray(series[0], float), np.asarray(series[1], float)
    w = (t >= 2.8) & (t <= 7.0)
    return dict(impact=float(mod.impact(t, p, exp["mean"])[0]),
                mean=float(mod.time_mean(t, p, 2.8, 7.0)[0]) if np.count_nonzero(w) > 1 else float("nan"))


def plot(dim, dp, sx, sf, png):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(1, 3, figsize=(15, 4.2))
    for r, lab, sty in ((sf, "SPHFlume", "b-"), (sx, "SPHinXsys", "r.-")):
        if r is None:
            continue
        ax[0].plot(*r["p"], sty, lw=1, ms=3, label=lab + " (point)")
        if r.get("sensor") is not None:
            t, m, sd = r["sensor"]
            ax[0].plot(t, m, "g-", lw=1, label=lab + " sensor (face 0.03 H, window 0.02)")
            ax[0].fill_between(t, m - sd, m + sd, color="g", alpha=0.25, lw=0, label="sensor +- 1 std in its window")
        ax[1].plot(*r["front"], sty, lw=1, ms=3, label=lab)
        ax[2].plot(*r["energy"], sty, lw=1, ms=3, label=lab)
    ax[0].set_title("pressure at (5.366, 0.2) [rho0 g H]")
    ax[1].set_title("surge front x [H]")
    ax[1].set_xlim(0, 3)
    ax[2].set_title("total mechanical energy / initial")
    for x in ax:
        x.set_xlabel("t sqrt(g/H)")
        x.grid(alpha=0.3)
        x.legend()
    fig.suptitle(f"{dim.upper()} dam break (SPHinXsys set-up), dp = {dp:g}")
    fig.tight_layout()
    fig.savefig(png, dpi=100)
    plt.close(fig)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--sphinxsys-src")
    ap.add_argument("--sphinxsys-build")
    ap.add_argument("--cxx-flags", default="-O3 -march=native")
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 2)
    ap.add_argument("--cases", default="2d")
    ap.add_argument("--dp2d", default="0.0125")
    ap.add_argument("--dp3d", default="0.05,0.025")
    ap.add_argument("--end", type=float, default=None, help="end time (default: the cases' 20)")
    ap.add_argument("--threads", type=int, default=2, help="SPHFlume threads (SPHinXsys's TBB takes every core)")
    ap.add_argument("--sphflume", default=os.path.join(ROOT, "build", "sphflume"))
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE", help="SPHFlume --set overrides")
    ap.add_argument("--out", default="/tmp/bench/vs_sphinxsys")
    ap.add_argument("--reuse", action="store_true")
    ap.add_argument("--skip-sphinxsys", action="store_true")
    ap.add_argument("--png-dir", default=os.path.join(ROOT, "bench"))
    a = ap.parse_args()
    dims = [d.strip() for d in a.cases.split(",") if d.strip()]
    os.makedirs(a.out, exist_ok=True)
    if not a.skip_sphinxsys:
        if not a.sphinxsys_src:
            sys.exit("give --sphinxsys-src PATH (a SPHinXsys checkout), or --skip-sphinxsys")
        a.sphinxsys_build = a.sphinxsys_build or os.path.join(a.out, "sphinxsys-build")
        src, bld = ensure_sphinxsys(a, dims)
    cpu = next((l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo") if l.startswith("model name")), "?")
    print(f"machine: {cpu}, {os.cpu_count()} cores; SPHFlume {a.threads} threads; SPHinXsys flags '{a.cxx_flags}'")
    rows = []
    bmod, bexp = buchner()
    for dim in dims:
        for dp in [float(v) for v in (a.dp2d if dim == "2d" else a.dp3d).split(",")]:
            tag = f"{dim}_dp{dp:g}"
            sx = None
            if not a.skip_sphinxsys:
                exe = variant(a, bld, dim, dp, a.out)
                print(f"[{tag}] SPHinXsys ...", flush=True)
                sx = run_sphinxsys(exe, dim, src, os.path.join(a.out, f"sphinxsys_{tag}"), a.reuse)
            print(f"[{tag}] SPHFlume ...", flush=True)
            sf = run_sphflume(a, dim, dp, os.path.join(a.out, f"sphflume_{tag}"), a.reuse)
            png = os.path.join(a.png_dir, f"vs_sphinxsys_{tag}.png")
            plot(dim, dp, sx, sf, png)
            row = dict(case=tag, fluid=sf["summary"]["particles"]["fluid"], sphflume_wall=sf["wall"],
                       sphflume_process=sf["process"], sphflume_steps=sf["steps"], sphflume=metrics(sf),
                       integrator=sf["summary"].get("integrator"), figure=os.path.relpath(png, ROOT))
            if sf.get("sensor") is not None:
                row["sphflume_sensor"] = metrics(sf, sensor=True)
                win = (sf["sensor"][0] >= 2.8) & (sf["sensor"][0] <= 7.0)
                row["sphflume_sensor"]["band_std_mean"] = float(sf["sensor"][2][win].mean())
            obs = observer_series(os.path.join(a.out, f"sphflume_{tag}"), dim, dp)
            if obs is not None:  # (SPHinXsys's gauge on SPHFlume's fields)
                row["sphflume_observer"] = metrics(dict(sf, p=obs))
            # Buchner's measurement at the probe, its rules applied alike to each code's series (3D runs to t < 7:
            # the mean over what the window holds)
            row["buchner"] = dict(measured=bexp, sphflume_probe=buchner_metrics(bmod, bexp, sf["p"]))
            if sf.get("sensor") is not None:
                row["buchner"]["sphflume_sensor"] = buchner_metrics(bmod, bexp, sf["sensor"][:2])
            if obs is not None:
                row["buchner"]["sphflume_observer"] = buchner_metrics(bmod, bexp, obs)
            if sx:
                row["buchner"]["sphinxsys"] = buchner_metrics(bmod, bexp, sx["p"])
            if sx:
                row.update(sphinxsys_wall=sx["wall"], sphinxsys_process=sx["process"],
                           sphinxsys_advection_steps=sx["advection_steps"], sphinxsys=metrics(sx),
                           ratio=sf["wall"] / sx["wall"], ratio_process=sf["process"] / sx["process"])
            rows.append(row)
            print(json.dumps(row, indent=1), flush=True)
    with open(os.path.join(a.out, "results.json"), "w") as f:
        json.dump(rows, f, indent=1)
    print("\n| case | fluid particles | SPHFlume wall [s] | SPHinXsys wall [s] | ratio (target <= 0.5) | "
          "impact t SF / SX | post-impact p SF / SX | energy at t=7 SF / SX |")
    print("|---|---|---|---|---|---|---|---|")
    for r in rows:
        sfm, sxm = r["sphflume"], r.get("sphinxsys", {})
        f = lambda v: "-" if v is None or (isinstance(v, float) and math.isnan(v)) else f"{v:.3g}"
        print(f"| {r['case']} | {r['fluid']} | {r['sphflume_wall']:.1f} | {f(r.get('sphinxsys_wall'))} | "
              f"{f(r.get('ratio'))} | {f(sfm['impact'])} / {f(sxm.get('impact'))} | "
              f"{f(sfm['post_mean'])} / {f(sxm.get('post_mean'))} | {f(sfm['energy_t7'])} / {f(sxm.get('energy_t7'))} |")
    print(f"\nBuchner (2002) at the probe, validation/dambreak_buchner's rules: impact {bexp['impact']:.3f} +- "
          f"{bexp['rise']:.3f}, post-impact mean {bexp['mean']:.3f} +- {bexp['sd']:.3f}")
    print("| case | SPHFlume point gauge | SPHFlume sensor | SPHFlume read by SPHinXsys's observer | SPHinXsys |")
    print("|---|---|---|---|---|")
    for r in rows:
        b = r["buchner"]
        cell = lambda k: "-" if k not in b else f"{b[k]['impact']:.3f} / {b[k]['mean']:.3f}"
        print(f"| {r['case']} | {cell('sphflume_probe')} | {cell('sphflume_sensor')} | {cell('sphflume_observer')} | "
              f"{cell('sphinxsys')} |")


if __name__ == "__main__":
    main()
