#!/usr/bin/python3
"""SPHFlume vs PySPH throughput on the 2D dam break.

Run with the Debian python (it has numpy and PySPH):

    /usr/bin/python3 bench/compare.py                     # 5k, 20k, 80k fluid particles
    /usr/bin/python3 bench/compare.py --sizes 5k,20k --steps 40
    /usr/bin/python3 bench/compare.py --skip-pysph
    /usr/bin/python3 bench/compare.py --sphinxsys         # how to run SPHinXsys's 2D dam break set-up

See bench/README.md for what is measured and how.

SPHFlume side: `sphflume run cases/dambreak_2d.yaml --no-output --max-steps N --threads T
--set particles.dx=D`, numbers read from OUTDIR/summary.json (its wall clock covers the
initial rate evaluation and the N time steps; case set-up is excluded).

PySPH side: pysph.examples.dam_break_2d (WCSPH, PEC integrator, 1 rate evaluation per
step like SPHFlume's Verlet scheme, which the dam-break case uses) with `--openmp --nnps box --disable-output`,
OMP_NUM_THREADS threads. Timing is PySPH's own: the wall time of Application.solve(),
printed as "Run took: X secs" and stored as "cpu_time" in <output dir>/dam_break_2d.info.
Like SPHFlume's it covers the initial acceleration evaluation plus the N steps, not the
set-up (particle creation, kernel compilation). Kernels are compiled into ~/.pysph on the
first run, so a warm-up run is made before timing.

The stock example builds its particles with the module constants h = 1.3 * 0.03 and
m = 1000 * 0.03**2, whatever --dx is; its smoothing length then stays at 0.039 m (the
update-h equation sets h = hdx * sqrt(m / rho)). At dx = 0.01 that is 3.9 dx instead of
1.3 dx: ~190 neighbours per particle instead of ~21, i.e. ~9x the work per particle. By
default this script therefore runs the example through a tiny subclass that only sets
h = 1.3 dx and m = 1000 dx**2 (`--pysph-variant fixed`); `--pysph-variant stock` runs the
example unchanged. `--pysph-geometry sphflume` additionally puts PySPH's fluid column and
tank at SPHFlume's sizes (0.146 x 0.292 m in 0.584 x 0.73 m) so that the same dx gives the
same particle count; the default keeps PySPH's own geometry (1 x 2 m column in a 4 x 4 m
tank), which at the same dx holds ~47x as many fluid particles.
"""

import argparse
import datetime
import json
import math
import os
import platform

import resource
import shutil
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CASE = "cases/dambreak_2d.yaml"
# SPHFlume dam break: column a x 2a, a = 0.146 m, tank 4a x 5a
SF_COL_W, SF_COL_H = 0.146, 0.292
SF_TANK_W, SF_TANK_H = 0.584, 0.73
# PySPH dam_break_2d: column 1 x 2 m in a 4 x 4 m tank
PY_COL_W, PY_COL_H = 1.0, 2.0


# ---------------------------------------------------------------------------
# PySPH driver: `compare.py --pysph-driver [--variant V] [--geometry G] -- <pysph args>`
# (run as a child process with OMP_NUM_THREADS set; prints one BENCH_JSON line)
# ---------------------------------------------------------------------------
def pysph_driver(argv):
    ap = argparse.ArgumentParser(prog="compare.py --pysph-driver")
    ap.add_argument("--variant", choices=["stock", "fixed"], default="fixed")
    ap.add_argument("--geometry", choices=["pysph", "sphflume"], default="pysph")
    ap.add_argument("--integrator", choices=["pec", "epec"], default="pec")
    ap.add_argument("rest", nargs=argparse.REMAINDER)
    a = ap.parse_args(argv)
    rest = a.rest[1:] if a.rest and a.rest[0] == "--" else a.rest

    import numpy as np
    import pysph.examples.dam_break_2d as db
    from pysph.base.utils import get_particle_array
    from pysph.tools.geometry import get_2d_tank, get_2d_block

    if a.variant == "stock" and a.geometry == "pysph" and a.integrator == "pec":
        App = db.DamBreak2D
    else:
        class App(db.DamBreak2D):
            def configure_scheme(self):
                if a.integrator == "pec":
                    return super().configure_scheme()
                # the example imports PECIntegrator inside configure_scheme: swap it for
                # EPEC (evaluate-predict-evaluate-correct, 2 rate evaluations per step)
                import pysph.sph.integrator as integ
                orig = integ.PECIntegrator
                integ.PECIntegrator = integ.EPECIntegrator
                try:
                    return super().configure_scheme()
                finally:
                    integ.PECIntegrator = orig

            def create_particles(self):
                if a.variant == "fixed":
                    # the only change: particle h and m follow --dx
                    db.h = self.h
                    db.m = self.dx ** 2 * db.ro
                if a.geometry == "pysph":
                    return super().create_particles()
                # same construction as the example (non-staggered branch),
                # at SPHFlume's column and tank sizes
                dx = self.dx
                xt, yt = get_2d_tank(dx=dx, length=SF_TANK_W, height=SF_TANK_H,
                                     base_center=[SF_TANK_W / 2, 0], num_layers=4)
                nx, ny = round(SF_COL_W / dx), round(SF_COL_H / dx)   # SPHFlume's counts
                xf, yf = get_2d_block(dx=dx, length=(nx - 1) * dx * (1 + 1e-9),
                                      height=(ny - 1) * dx * (1 + 1e-9),
                                      center=[SF_COL_W / 2, SF_COL_H / 2])
                xf += dx / 2
                yf += dx / 2
                fluid = get_particle_array(name="fluid", x=xf, y=yf, h=db.h, m=db.m, rho=db.ro)
                boundary = get_particle_array(name="boundary", x=xt, y=yt, h=db.h, m=db.m, rho=db.ro)
                self.scheme.setup_properties([fluid, boundary])
                self.kernel_corrections(fluid, boundary)
                return [fluid, boundary]

    app = App()
    t0 = time.time()
    app.setup(rest)
    first_step = []
    app.solver.add_pre_step_callback(
        lambda solver: first_step.append(time.time()) if not first_step else None)
    t1 = time.time()
    app.solve()
    t2 = time.time()
    info = {}
    try:
        with open(app.info_filename) as f:
            info = json.load(f)
    except (OSError, ValueError):
        pass
    counts = {pa.name: int(pa.get_number_of_particles()) for pa in app.particles}
    fluid = app.particles[[pa.name for pa in app.particles].index("fluid")]
    out = {
        "fluid": counts.get("fluid", 0),
        "boundary": counts.get("boundary", 0),
        "steps": int(app.solver.count),
        "run_seconds": float(info.get("cpu_time", t2 - t1)),   # PySPH's "Run took"
        "run_seconds_outer": t2 - t1,
        "setup_seconds": t1 - t0,
        # time of the steps alone (without the initial acceleration evaluation)
        "steps_seconds": (t2 - first_step[0]) if first_step else None,
        "h_final": float(np.mean(fluid.h)),
        "dx": float(app.dx),
        "integrator": type(app.solver.integrator).__name__,
        "threads_env": os.environ.get("OMP_NUM_THREADS"),
        "info_file": app.info_filename,
    }
    print("BENCH_JSON " + json.dumps(out), flush=True)


# ---------------------------------------------------------------------------
# helpers
# ---------------------------------------------------------------------------
def sh(cmd, **kw):
    return subprocess.run(cmd, capture_output=True, text=True, **kw)


def machine_info():
    model = "unknown"
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    model = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    mem = None
    try:
        with open("/proc/meminfo") as f:
            for line in f:
                if line.startswith("MemTotal"):
                    mem = round(int(line.split()[1]) / 1024 / 1024, 1)
    except OSError:
        pass
    return {"cpu": model, "cores": os.cpu_count(), "mem_gib": mem,
            "kernel": platform.release(), "python": sys.version.split()[0]}


def git_info():
    c = sh(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT)
    commit = c.stdout.strip() if c.returncode == 0 else "unknown"
    d = sh(["git", "status", "--porcelain", "--untracked-files=no"], cwd=ROOT)
    dirty = bool(d.stdout.strip()) if d.returncode == 0 else False
    return {"commit": commit, "dirty": dirty}


def cpu_busy(interval=1.0):
    """Fraction of all CPUs busy over `interval` seconds (from /proc/stat)."""
    def snap():
        with open("/proc/stat") as f:
            v = [int(x) for x in f.readline().split()[1:]]
        idle = v[3] + (v[4] if len(v) > 4 else 0)
        return sum(v), idle
    try:
        t0, i0 = snap()
        time.sleep(interval)
        t1, i1 = snap()
        return 1.0 - (i1 - i0) / max(1, t1 - t0)
    except OSError:
        return float("nan")


def wait_quiet(max_wait, threshold, log):
    """Wait (up to max_wait s) until the machine is quiet; return the busy fraction seen."""
    t_end = time.time() + max_wait
    busy = cpu_busy(2.0)
    while busy > threshold and time.time() < t_end:
        log(f"    machine busy ({busy:.0%} CPU used by others), waiting ...")
        time.sleep(3.0)
        busy = cpu_busy(2.0)
    return busy


def busy_seconds():
    """CPU-seconds spent busy by the whole machine so far (from /proc/stat)."""
    try:
        with open("/proc/stat") as f:
            v = [int(x) for x in f.readline().split()[1:]]
        idle = v[3] + (v[4] if len(v) > 4 else 0)
        return (sum(v[:8]) - idle) / os.sysconf("SC_CLK_TCK")
    except (OSError, ValueError):
        return float("nan")


LAST_OTHERS = {"value": None}


def run_timed(cmd, env=None, cwd=ROOT, timeout=None):
    """Run a child; return (CompletedProcess, wall s, child cpu s).
    LAST_OTHERS['value'] is set to the fraction of the machine's CPU used by
    other processes while the child ran (contention indicator)."""
    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    b0 = busy_seconds()
    t0 = time.time()
    p = subprocess.run(cmd, capture_output=True, text=True, env=env, cwd=cwd, timeout=timeout)
    wall = time.time() - t0
    b1 = busy_seconds()
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)
    if wall > 0:
        LAST_OTHERS["value"] = max(0.0, (b1 - b0 - cpu) / (wall * (os.cpu_count() or 1)))
    return p, wall, cpu


def parse_size(s):
    s = s.strip().lower()
    mult = 1
    if s.endswith("k"):
        mult, s = 1000, s[:-1]
    elif s.endswith("m"):
        mult, s = 1000000, s[:-1]
    return int(round(float(s) * mult))


def dx_for_fluid(n):
    """dx giving ~n fluid particles in SPHFlume's 0.146 x 0.292 column."""
    return math.sqrt(SF_COL_W * SF_COL_H / n)


def fmt_dx(dx):
    return f"{dx:.6g}"


def locate_binary(path, log, wait=300):
    """The binary may be being rebuilt: wait for it, then copy it so all runs use one build."""
    t_end = time.time() + wait
    while True:
        if os.path.isfile(path) and os.access(path, os.X_OK):
            try:
                age = time.time() - os.path.getmtime(path)
                if age > 5:
                    return path
            except OSError:
                pass
        if time.time() > t_end:
            sys.exit(f"error: {path} not found (or still being written) after {wait} s")
        log(f"  waiting for {path} ...")
        time.sleep(5)


# ---------------------------------------------------------------------------
# SPHFlume
# ---------------------------------------------------------------------------
def run_sphflume(binary, dx, steps, threads, outdir, args, log, rnd=0):
    od = os.path.join(outdir, f"sphflume_dx{fmt_dx(dx)}_t{threads}")
    shutil.rmtree(od, ignore_errors=True)
    cmd = [binary, "run", args.case_copy, "-o", od, "-q", "--no-output", "--max-steps", str(steps),
           "--threads", str(threads), "--set", f"particles.dx={fmt_dx(dx)}"]
    best = None
    rep, retries = 0, 0
    while rep < 1:
        busy = wait_quiet(args.wait_idle, args.busy_threshold, log)
        p, wall, cpu = run_timed(cmd)
        if p.returncode != 0:
            raise RuntimeError(f"sphflume failed ({p.returncode}): {' '.join(cmd)}\n{p.stderr[-2000:]}")
        with open(os.path.join(od, "summary.json")) as f:
            s = json.load(f)
        r = {
            "dx": dx, "threads": s.get("threads", threads), "steps": s["steps"],
            "fluid": s["particles"]["fluid"], "wall": s["particles"]["wall"],
            "total": s["particles"]["total"],
            "wall_seconds": s["wall_seconds"],
            "particle_steps_per_second": s["particle_steps_per_second"],
            "fluid_particle_steps_per_second": s["fluid_particle_steps_per_second"],
            "pair_interactions_per_second": s["pair_interactions_per_second"],
            "bytes_per_particle": s["bytes_per_particle"],
            "h_over_dx": s["h"] / s["dx"] if s.get("h") and s.get("dx") else None,
            "kernel": s.get("kernel"),
            "integrator": s.get("integrator"), "passes_per_step": s.get("passes_per_step"),
            "exit_status": s.get("exit_status"),
            "process_wall_seconds": wall, "process_cpu_seconds": cpu,
            "cpu_utilisation": cpu / wall / max(1, threads) if wall > 0 else None,
            "background_busy_before": busy,
            "others_cpu_during": LAST_OTHERS["value"],
            "command": " ".join(cmd),
        }
        log(f"    SPHFlume dx={fmt_dx(dx)} T={threads}: {r['fluid']} fluid, {r['steps']} steps, "
            f"{r['wall_seconds']:.2f} s, {r['fluid_particle_steps_per_second'] / 1e6:.3f} M fluid-steps/s"
            f" (round {rnd + 1}/{args.repeat}, others busy {busy:.0%} before, "
            f"{LAST_OTHERS['value'] or 0:.0%} during)")
        if s.get("exit_status") not in (None, "done"):
            log(f"    warning: SPHFlume exit_status {s.get('exit_status')}: {s.get('message')}")
        if (LAST_OTHERS["value"] or 0) > args.max_others and retries < args.retries:
            retries += 1
            log(f"    ... discarded: other processes used {LAST_OTHERS['value']:.0%} of the CPUs during "
                f"the run (> --max-others {args.max_others:.0%}); retry {retries}/{args.retries}")
            continue
        rep += 1
        if best is None or r["wall_seconds"] < best["wall_seconds"]:
            best = r
    best["discarded_busy_runs"] = retries
    return best


# ---------------------------------------------------------------------------
# PySPH
# ---------------------------------------------------------------------------
def pysph_cmd(dx, steps, outdir, args, geometry, hdx):
    return [sys.executable, os.path.abspath(__file__), "--pysph-driver",
            "--variant", args.pysph_variant, "--geometry", geometry,
            "--integrator", args.pysph_integrator, "--",
            "--openmp", "--nnps", "box", "--dx", fmt_dx(dx), "--hdx", f"{hdx:.6g}",
            "--max-steps", str(steps),
            "--disable-output", "-q", "-d", outdir]


def pysph_env(threads):
    env = dict(os.environ)
    env["OMP_NUM_THREADS"] = str(threads)
    return env


def parse_driver(p):
    for line in p.stdout.splitlines():
        if line.startswith("BENCH_JSON "):
            return json.loads(line[len("BENCH_JSON "):])
    raise RuntimeError(f"PySPH run failed ({p.returncode}):\n{p.stdout[-2000:]}\n{p.stderr[-3000:]}")


def pysph_warmup(outdir, args, log):
    """First run compiles the kernels into ~/.pysph; do it untimed, at a coarse dx."""
    od = os.path.join(outdir, "pysph_warmup")
    t0 = time.time()
    p, _, _ = run_timed(pysph_cmd(0.03, 2, od, args, "pysph", 1.3), env=pysph_env(args.pysph_threads))
    r = parse_driver(p)
    log(f"  PySPH warm-up (compile if not cached): {time.time() - t0:.1f} s, "
        f"setup {r['setup_seconds']:.1f} s")


def pysph_expected_fluid(dx, geometry):
    if geometry == "sphflume":
        return (SF_COL_W / dx) * (SF_COL_H / dx)
    return (PY_COL_W / dx + 1) * (PY_COL_H / dx + 1)


def run_pysph(dx, steps, outdir, args, geometry, hdx, log, rnd=0):
    od = os.path.join(outdir, f"pysph_{geometry}_dx{fmt_dx(dx)}")
    shutil.rmtree(od, ignore_errors=True)
    cmd = pysph_cmd(dx, steps, od, args, geometry, hdx)
    best = None
    rep, retries = 0, 0
    while rep < 1:
        busy = wait_quiet(args.wait_idle, args.busy_threshold, log)
        p, wall, cpu = run_timed(cmd, env=pysph_env(args.pysph_threads))
        d = parse_driver(p)
        run_s = d["run_seconds"]
        # PySPH's timed region = initial acceleration + `steps` steps, like SPHFlume's
        r = {
            "dx": dx, "threads": args.pysph_threads, "steps": d["steps"],
            "fluid": d["fluid"], "boundary": d["boundary"], "total": d["fluid"] + d["boundary"],
            "run_seconds": run_s, "setup_seconds": d["setup_seconds"],
            "steps_seconds": d["steps_seconds"],
            "fluid_particle_steps_per_second": d["fluid"] * d["steps"] / run_s,
            "particle_steps_per_second": (d["fluid"] + d["boundary"]) * d["steps"] / run_s,
            "h_over_dx_final": d["h_final"] / dx,
            "hdx_option": hdx,
            "variant": args.pysph_variant, "geometry": geometry,
            "integrator": d["integrator"],
            "evaluations_per_step": 2 if args.pysph_integrator == "epec" else 1,
            "process_wall_seconds": wall, "process_cpu_seconds": cpu,
            "background_busy_before": busy,
            "others_cpu_during": LAST_OTHERS["value"],
            "command": f"OMP_NUM_THREADS={args.pysph_threads} " + " ".join(cmd),
        }
        log(f"    PySPH ({geometry} geometry) dx={fmt_dx(dx)} T={args.pysph_threads}: {r['fluid']} fluid "
            f"(+{r['boundary']} boundary), {r['steps']} steps, {run_s:.2f} s "
            f"(set-up {d['setup_seconds']:.1f} s), {r['fluid_particle_steps_per_second'] / 1e6:.3f} M fluid-steps/s, "
            f"h/dx {r['h_over_dx_final']:.2f} (round {rnd + 1}/{args.repeat}, others busy {busy:.0%} before, "
            f"{LAST_OTHERS['value'] or 0:.0%} during)")
        if (LAST_OTHERS["value"] or 0) > args.max_others and retries < args.retries:
            retries += 1
            log(f"    ... discarded: other processes used {LAST_OTHERS['value']:.0%} of the CPUs during "
                f"the run (> --max-others {args.max_others:.0%}); retry {retries}/{args.retries}")
            continue
        rep += 1
        if best is None or r["run_seconds"] < best["run_seconds"]:
            best = r
    best["discarded_busy_runs"] = retries
    return best


# ---------------------------------------------------------------------------
# SPHinXsys mode
# ---------------------------------------------------------------------------
SPHINXSYS_CASE = """\
# SPHinXsys tests/2d_examples/test_2d_dambreak (dambreak.cpp), nondimensional:
#   tank DL x DH = 5.366 x 5.366, water column LL x LH = 2.0 x 1.0,
#   particle_spacing_ref = 0.025 (LH/40), wall thickness BW = 4 dx outside the tank,
#   rho0 = 1, g = 1, U_ref = 2 sqrt(g LH) = 2, c = 10 U_ref = 20, end_time = 20.
# -> 80 x 40 = 3200 fluid particles at dx = 0.025 (set particles.dx to refine).
name: dambreak_2d_sphinxsys
dimension: 2
gravity: [0.0, -1.0]
particles:
  dx: 0.025
  kernel: wendland_c2
  h_over_dx: 1.3
fluid:
  density: 1.0
  viscosity: 0.0
  sound_speed: 20.0
  eos: tait
scheme:
  integrator: symplectic
  density_diffusion: fourtakas
  delta: 0.1
  viscosity: artificial
  alpha: 0.02
  cfl: 0.2
walls:
  type: dummy
  slip: free_slip
geometry:
  - {type: tank, fill: wall, min: [0.0, 0.0], max: [5.366, 5.366]}
  - {type: box, fill: fluid, min: [0.0, 0.0], max: [2.0, 1.0]}
time:
  end: 20.0
  output_interval: 0.1
"""


SPHINXSYS_CASE_FILE = "cases/dambreak_sphinxsys.yaml"


def print_sphinxsys():
    print("SPHinXsys 2D dam break (tests/2d_examples/test_2d_dambreak) with SPHFlume")
    print("=" * 72)
    print("SPHinXsys set-up: tank 5.366 x 5.366, water column 2 x 1 (LH = 1), rho0 = 1, g = 1,")
    print("c0 = 10 * 2 sqrt(g LH) = 20, particle_spacing_ref = 0.025 (80 x 40 = 3200 fluid), to t = 20.")
    print("SPHinXsys itself uses Riemann-based WCSPH with dual time stepping; only the set-up is matched.\n")
    case = SPHINXSYS_CASE_FILE
    if os.path.isfile(os.path.join(ROOT, case)):
        print(f"Case file: {case}")
    else:
        case = "cases/dambreak_2d_sphinxsys.yaml"
        print(f"No case file yet; a proposal (save as {case}):\n")
        print(SPHINXSYS_CASE)
    print("\nThroughput, as for the PySPH comparison (fluid counts 2/dx * 1/dx):")
    print(f"  build/sphflume check {case} --set particles.dx=0.025")
    for n, dx in ((3200, 0.025), (12800, 0.0125), (51200, 0.00625)):
        print(f"  build/sphflume run {case} -o /tmp/bench/sphinxsys_{n} -q --no-output "
              f"--max-steps 200 --threads 2 --set particles.dx={dx}    # {n} fluid")
    print("  -> fluid_particle_steps_per_second etc. in /tmp/bench/sphinxsys_N/summary.json")
    print("\nTime to solution (the whole run to t = 20, snapshots off):")
    print(f"  build/sphflume run {case} -o /tmp/bench/sphinxsys_full --no-output --threads 2")
    print("  -> wall_seconds in summary.json; SPHinXsys prints "
          "'Total wall time for computation: X seconds' at the end of its run.")


# ---------------------------------------------------------------------------
# report
# ---------------------------------------------------------------------------
def m(x, nd=2):
    return "-" if x is None else f"{x / 1e6:.{nd}f}"


def pysph_geoms(res):
    return [g.strip() for g in res["args"]["pysph_geometry"].split(",") if g.strip()] \
        if not res["args"]["skip_pysph"] else []


def pysph_hdx(res):
    v = sorted({f"{p.get('hdx_option', 1.3):.3g}" for r in res["sizes"] for p in (r.get("pysph") or {}).values()})
    return "/".join(v) if v else "-"


def table(res):
    geoms = pysph_geoms(res)
    hdr = ["dx [m]", "SF fluid (total)", "SF M fluid-st/s 1T", "SF M fluid-st/s 2T", "speed-up 1->2",
           "SF M part-st/s 2T", "SF M pairs/s 2T", "SF B/particle"]
    for g in geoms:
        tag = "PySPH" if g == "pysph" else "PySPH@SF-geom"
        hdr += [f"{tag} fluid (total)", f"{tag} M fluid-st/s 2T", f"SF/{tag}"]
    rows = []
    for r in res["sizes"]:
        s1, s2 = r.get("sphflume_1t"), r.get("sphflume_2t")
        sf = s2 or s1
        sp = (s2["fluid_particle_steps_per_second"] / s1["fluid_particle_steps_per_second"]
              if s1 and s2 else None)
        row = [
            fmt_dx(r["dx"]),
            f"{sf['fluid']} ({sf['total']})" if sf else "-",
            m(s1 and s1["fluid_particle_steps_per_second"], 3),
            m(s2 and s2["fluid_particle_steps_per_second"], 3),
            "-" if sp is None else f"{sp:.2f}",
            m(s2 and s2["particle_steps_per_second"], 3),
            m(s2 and s2["pair_interactions_per_second"], 1),
            f"{sf['bytes_per_particle']:.0f}" if sf else "-",
        ]
        for g in geoms:
            py = (r.get("pysph") or {}).get(g)
            ratio = (s2["fluid_particle_steps_per_second"] / py["fluid_particle_steps_per_second"]
                     if s2 and py else None)
            row += [f"{py['fluid']} ({py['total']})" if py else "-",
                    m(py and py["fluid_particle_steps_per_second"], 3),
                    "-" if ratio is None else f"{ratio:.2f}"]
        rows.append(row)
    out = ["| " + " | ".join(hdr) + " |", "|" + "|".join("---" for _ in hdr) + "|"]
    out += ["| " + " | ".join(row) + " |" for row in rows]
    return "\n".join(out)


def targets(res):
    """The issue's targets; the throughput ones at the size closest to 20k fluid particles."""
    lines = []
    sizes = [r for r in res["sizes"] if r.get("sphflume_2t")]
    if not sizes:
        return lines
    r20 = min(sizes, key=lambda r: abs(r["sphflume_2t"]["fluid"] - 20000))
    s2 = r20["sphflume_2t"]
    n = s2["fluid"]
    ok = lambda b: "MET" if b else "NOT MET"
    v = s2["particle_steps_per_second"] / 1e6
    vf = s2["fluid_particle_steps_per_second"] / 1e6
    lines.append(f"- >= 4 M particle-steps/s at ~20k fluid ({n} fluid, 2 threads): "
                 f"{v:.2f} M (all particles), {vf:.2f} M (fluid only) -> {ok(v >= 4)}")
    geoms = pysph_geoms(res)
    for g in geoms:
        py = (r20.get("pysph") or {}).get(g)
        if py:
            ratio = s2["fluid_particle_steps_per_second"] / py["fluid_particle_steps_per_second"]
            lines.append(f"- >= 5x PySPH (fluid particle-steps/s, dx {fmt_dx(r20['dx'])}, PySPH {g} geometry "
                         f"with {py['fluid']} fluid, 2 threads): {ratio:.2f}x -> {ok(ratio >= 5)}")
    if not geoms:
        lines.append("- >= 5x PySPH: not measured (--skip-pysph)")
    sps = [(r["sphflume_2t"]["fluid"], r["sphflume_2t"]["fluid_particle_steps_per_second"] /
            r["sphflume_1t"]["fluid_particle_steps_per_second"])
           for r in res["sizes"] if r.get("sphflume_1t") and r.get("sphflume_2t")]
    if sps:
        lines.append("- 1->2 thread speed-up >= 1.7: " + ", ".join(f"{x:.2f} at {nf} fluid" for nf, x in sps)
                     + f" -> {ok(all(x >= 1.7 for _, x in sps))}")
    bpp = [(r["sphflume_2t"]["fluid"], r["sphflume_2t"]["bytes_per_particle"]) for r in sizes]
    lines.append("- <= 150 bytes/particle (2D): " + ", ".join(f"{b:.0f} at {nf} fluid" for nf, b in bpp)
                 + f" -> {ok(all(b <= 150 for _, b in bpp))}")
    return lines


def report(res):
    mi, gi = res["machine"], res["git"]
    out = []
    out.append(f"date:    {res['date']}")
    out.append(f"machine: {mi['cpu']}, {mi['cores']} cores, {mi['mem_gib']} GiB")
    out.append(f"commit:  {gi['commit']}{' (+ uncommitted changes)' if gi['dirty'] else ''}")
    out.append(f"command: {res['command']}")
    sf_any = next((r.get("sphflume_2t") or r.get("sphflume_1t") for r in res["sizes"]
                   if r.get("sphflume_2t") or r.get("sphflume_1t")), None)
    if sf_any:
        out.append(f"SPHFlume: {res.get('sphflume_version', '')}, case {res.get('case', CASE)}, "
                   f"kernel {sf_any.get('kernel')}, h/dx {sf_any.get('h_over_dx') or 0:.3g}")
    if res.get("pysph_version"):
        out.append(f"PySPH:   {res['pysph_version']}, variant '{res['args']['pysph_variant']}', "
                   f"geometry '{res['args']['pysph_geometry']}', integrator "
                   f"'{res['args'].get('pysph_integrator', 'pec')}', {res['args']['pysph_threads']} threads, "
                   f"kernel WendlandQuintic (Wendland C2), h/dx {pysph_hdx(res)}")
    out.append("")
    out.append(table(res))
    out.append("")
    out.append(f"SF = SPHFlume ({res.get('case', CASE)}); st/s = particle-steps per second; 'fluid' counts "
               "fluid particles only, 'part' all particles incl. walls; 1T/2T = threads.")
    evals = sorted({v.get("evaluations_per_step", 1) for r in res["sizes"]
                    for v in (r.get("pysph") or {}).values()})
    if evals:
        sf_any = next((v for r in res["sizes"] for k, v in r.items() if k.startswith("sphflume") and v), {})
        sf_passes = sf_any.get("passes_per_step") or 2
        if evals == [sf_passes]:
            note = ", the same work per step."
        elif sf_passes > evals[-1]:
            note = (", so for the same work SPHFlume's lead is up to twice that (PySPH's profile_info.csv: "
                    "rate evaluation ~80-85 % of its step).")
        else:
            note = "."
        out.append(f"rate evaluations per step: SPHFlume {sf_passes} ({sf_any.get('integrator') or 'symplectic'}), "
                   f"PySPH {'/'.join(map(str, evals))} "
                   f"({res['args'].get('pysph_integrator', 'pec').upper()}); SF/PySPH compares steps" + note)
    steps = []
    for r in res["sizes"]:
        sf = r.get("sphflume_2t") or r.get("sphflume_1t")
        py = ", ".join(f"PySPH[{g}] {v['steps']}" for g, v in (r.get("pysph") or {}).items())
        steps.append(f"dx {fmt_dx(r['dx'])}: SF {sf['steps'] if sf else '-'}" + (f", {py}" if py else ""))
    out.append("steps per run: " + "; ".join(steps))
    busy = [v["background_busy_before"] for r in res["sizes"] for k, v in r.items()
            if k.startswith("sphflume_")]
    busy += [v["background_busy_before"] for r in res["sizes"] for v in (r.get("pysph") or {}).values()]
    during = [v.get("others_cpu_during") or 0 for r in res["sizes"] for k, v in r.items()
              if k.startswith("sphflume_")]
    during += [v.get("others_cpu_during") or 0 for r in res["sizes"] for v in (r.get("pysph") or {}).values()]
    if busy:
        out.append(f"CPU used by other processes (share of all cores), kept runs: max {max(busy):.0%} "
                   f"just before, max {max(during):.0%} during")
    out.append("")
    out.append("targets (issue):")
    out += targets(res)
    return "\n".join(out)


# ---------------------------------------------------------------------------
def main():
    if len(sys.argv) > 1 and sys.argv[1] == "--pysph-driver":
        return pysph_driver(sys.argv[2:])

    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--sizes", default="5k,20k,80k",
                    help="fluid particle counts of SPHFlume's case, e.g. 5k,20k,80k (dx = sqrt(0.146*0.292/N))")
    ap.add_argument("--dx", default=None, help="explicit dx list instead of --sizes, e.g. 0.00292,0.00146")
    ap.add_argument("--steps", type=int, default=None,
                    help="SPHFlume steps per run (default: --work / fluid particles, at least 20)")
    ap.add_argument("--work", type=float, default=1.5e6,
                    help="fluid particle-steps per run when --steps is not given (default 1.5e6)")
    ap.add_argument("--pysph-steps", type=int, default=None,
                    help="PySPH steps per run (default: --steps, capped by --pysph-work / fluid particles, at least 5)")
    ap.add_argument("--pysph-work", type=float, default=3e6,
                    help="cap on PySPH fluid particle-steps per run (default 3e6)")
    ap.add_argument("--threads", default="1,2", help="SPHFlume thread counts (default 1,2)")
    ap.add_argument("--pysph-threads", type=int, default=2)
    ap.add_argument("--pysph-variant", choices=["fixed", "stock"], default="fixed",
                    help="fixed: h = 1.3 dx, m = rho dx^2 (default); stock: the example unchanged "
                         "(h stays 0.039 m whatever dx)")
    ap.add_argument("--pysph-geometry", default="pysph",
                    help="comma list of pysph (the example's 1x2 m column in a 4x4 m tank, default) "
                         "and/or sphflume (SPHFlume's 0.146x0.292 m column in its 0.584x0.73 m tank: "
                         "same dx -> same particle count); the first one is used for the targets")
    ap.add_argument("--pysph-integrator", choices=["pec", "epec"], default="pec",
                    help="pec: the example's PECIntegrator, 1 rate evaluation per step (default); "
                         "epec: EPECIntegrator, 2 per step like SPHFlume's symplectic scheme")
    ap.add_argument("--pysph-hdx", default="auto",
                    help="PySPH h/dx (its --hdx); auto (default): the h/dx of SPHFlume's case, so that both "
                         "codes have the same kernel support and neighbour count (the example's default is 1.3)")
    ap.add_argument("--skip-pysph", action="store_true")
    ap.add_argument("--sphinxsys", action="store_true",
                    help="print how to run SPHinXsys's 2D dam-break set-up with SPHFlume and exit")
    ap.add_argument("--repeat", type=int, default=1,
                    help="rounds per size (each round runs every configuration once); the fastest run is kept")
    ap.add_argument("--wait-idle", type=float, default=60.0,
                    help="before each timed run wait up to this many s for other processes to go quiet")
    ap.add_argument("--max-others", type=float, default=0.10,
                    help="discard and redo a run if other processes used more than this fraction of "
                         "the CPUs while it ran (default 0.10) ...")
    ap.add_argument("--retries", type=int, default=3, help="... at most this many times per point (default 3)")
    ap.add_argument("--busy-threshold", type=float, default=0.15,
                    help="'quiet' = less than this fraction of all CPUs busy (default 0.15)")
    ap.add_argument("--binary", default=os.path.join(ROOT, "build", "sphflume"))
    ap.add_argument("--case", default=CASE, help=f"SPHFlume case (default {CASE})")
    ap.add_argument("--out", default="/tmp/bench", help="output folder (results.json, run folders)")
    args = ap.parse_args()

    if args.sphinxsys:
        print_sphinxsys()
        return

    os.makedirs(args.out, exist_ok=True)
    log = lambda s: print(s, file=sys.stderr, flush=True)

    if args.dx:
        dxs = [float(x) for x in args.dx.split(",") if x.strip()]
    else:
        dxs = [round(dx_for_fluid(parse_size(s)), 8) for s in args.sizes.split(",") if s.strip()]
    threads = [int(t) for t in args.threads.split(",") if t.strip()]
    geoms = [g.strip() for g in args.pysph_geometry.split(",") if g.strip()]
    for g in geoms:
        if g not in ("pysph", "sphflume"):
            sys.exit(f"error: unknown --pysph-geometry '{g}' (pysph, sphflume)")

    # one copy of the binary for every run (the build folder may be rebuilt meanwhile)
    src = locate_binary(args.binary, log)
    binary = os.path.join(args.out, "sphflume")
    shutil.copy2(src, binary)
    ver = sh([binary, "--version"])
    # and one copy of the case file (it may be edited meanwhile too)
    args.case_copy = os.path.join(args.out, os.path.basename(args.case))
    shutil.copy2(os.path.join(ROOT, args.case), args.case_copy)
    with open(args.case_copy) as f:
        case_text = f.read()

    res = {
        "date": datetime.datetime.now().astimezone().isoformat(timespec="seconds"),
        "machine": machine_info(), "git": git_info(),
        "command": "/usr/bin/python3 bench/compare.py " + " ".join(sys.argv[1:]),
        "sphflume_version": ver.stdout.strip(),
        "case": args.case, "case_text": case_text,
        "args": vars(args), "sizes": [],
    }
    if not args.skip_pysph:
        try:
            import pysph
            res["pysph_version"] = getattr(pysph, "__version__", "?")
        except ImportError:
            sys.exit("error: PySPH not importable by this python; use /usr/bin/python3 "
                     "(apt-get install python3-pysph) or pass --skip-pysph")
        pysph_warmup(args.out, args, log)

    for dx in dxs:
        nf = SF_COL_W * SF_COL_H / dx ** 2
        steps = args.steps or max(20, int(args.work / nf))
        log(f"dx = {fmt_dx(dx)} (~{nf:.0f} SPHFlume fluid particles), {steps} steps")
        entry = {"dx": dx}
        # rounds interleave the configurations (SF 1T, SF 2T, PySPH ...) so that slow drifts
        # of the machine hit all of them alike; the fastest run of each is kept
        runs = {}
        for rnd in range(args.repeat):
            for t in threads:
                runs.setdefault(f"sphflume_{t}t", []).append(
                    run_sphflume(binary, dx, steps, t, args.out, args, log, rnd))
            if not args.skip_pysph:
                for geom in geoms:
                    npf = pysph_expected_fluid(dx, geom)
                    psteps = args.pysph_steps or max(10, min(steps, int(args.pysph_work / npf)))
                    hdx = (float(args.pysph_hdx) if args.pysph_hdx != "auto"
                           else runs[f"sphflume_{threads[0]}t"][-1]["h_over_dx"] or 1.3)
                    runs.setdefault(f"pysph:{geom}", []).append(
                        run_pysph(dx, psteps, os.path.join(args.out, "pysph_runs"), args, geom, hdx,
                                  log, rnd))
        for key, lst in runs.items():
            tkey = "run_seconds" if key.startswith("pysph") else "wall_seconds"
            best = dict(min(lst, key=lambda r: r[tkey]))
            best["repeats"] = len(lst)
            best["all_" + tkey] = [r[tkey] for r in lst]
            if key.startswith("pysph:"):
                entry.setdefault("pysph", {})[key.split(":", 1)[1]] = best
            else:
                entry[key] = best
        res["sizes"].append(entry)
        with open(os.path.join(args.out, "results.json"), "w") as f:
            json.dump(res, f, indent=2)

    text = report(res)
    res["report"] = text
    with open(os.path.join(args.out, "results.json"), "w") as f:
        json.dump(res, f, indent=2)
    with open(os.path.join(args.out, "report.md"), "w") as f:
        f.write(text + "\n")
    print(text)
    log(f"\nwrote {os.path.join(args.out, 'results.json')} and report.md")


if __name__ == "__main__":
    main()
