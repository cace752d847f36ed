#!/usr/bin/python3
"""ISPH against WCSPH, side by side in one run of this script (issues 21 and 57, performance).

Part 1, time to solution: cases/dambreak_2d.yaml to t = 0.4 s at a/40 (and a/80 with --full), and with --flume or
--full Flume A at the thesis's d0 (cases/runup_flume_a.yaml, dx = 0.005, H/h0 = 0.163, to 4.5 s), once with the case's
WCSPH and once under ISPH (`--formulation`, default lind: its own cfl 0.4; tsurudome: shifting A = 2); wall time, the
ratio ISPH / WCSPH (issue 57: <= 2, goal <= 1), steps, the PPE's share (assembly + solve) and the ISPH step's passes
(prediction, assembly, solve, correction with shifting), bytes per particle (summary.json, matrix included).
Part 2, the pressure solver against N: cases/hydrostatic_isph.yaml at dx giving about 5 k, 20 k and 80 k fluid
particles (--full; 5 k and 20 k otherwise), a fixed number of steps, for each solver (--solvers: Eigen's
Jacobi BiCGSTAB, hypre's BoomerAMG-preconditioned BiCGSTAB); mean iterations per solve,
solve time per solve and iterations x N relative to the smallest (issue 21: at most linear growth of
iterations x N means iterations constant; a Jacobi-preconditioned Krylov solver on a 2D Poisson matrix needs
iterations ~ N^(1/2), so iterations x N grows as N^1.5).
Prints the machine (CPU model, cores) and the commit. Usage:
  /usr/bin/python3 bench/isph_vs_wcsph.py [--sphflume PATH] [--threads 2] [--full] [--flume] [--part 1|2|both]
                                          [--formulation lind|tsurudome] [--out DIR]
"""
import argparse
import json
import os
import platform
import subprocess
import tempfile
import time

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
A = 0.146


def run(exe, case, out, sets, threads):
    cmd = [exe, "run", os.path.join(ROOT, "cases", case), "--output", out, "-q", "--threads", str(threads)]
    for k, v in sets.items():
        cmd += ["--set", f"{k}={v}"]
    t0 = time.time()
    r = subprocess.run(cmd, capture_output=True, text=True)
    wall = time.time() - t0
    if r.returncode != 0:
        raise SystemExit(f"run failed ({r.returncode}): {' '.join(cmd)}\n{r.stderr[-1500:]}")
    with open(os.path.join(out, "summary.json")) as f:
        return json.load(f), wall


def cpu_and_commit():
    """The CPU model and the tree's short commit ('?' where unknown); bench/isph_vs_pysph.py uses it too."""
    cpu = "?"
    try:
        with open("/proc/cpuinfo") as f:
            cpu = next(line.split(":", 1)[1].strip() for line in f if line.startswith("model name"))
    except (OSError, StopIteration):
        pass
    commit = subprocess.run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"], capture_output=True, text=True).stdout.strip()
    return cpu, commit or "?"


def machine():
    cpu, commit = cpu_and_commit()
    return f"{cpu}, {os.cpu_count()} cores, {platform.system()}; commit {commit}"


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--sphflume", default=os.environ.get("SPHFLUME", os.path.join(ROOT, "build", "sphflume")))
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--full", action="store_true", help="also a/80, Flume A at d0 and the 80 k tank")
    ap.add_argument("--flume", action="store_true", help="also Flume A at d0 (part 1)")
    ap.add_argument("--formulation", choices=["lind", "tsurudome"], default="lind", help="the ISPH runs' formulation")
    ap.add_argument("--part", choices=["1", "2", "both"], default="both")
    ap.add_argument("--solvers", default="bicgstab,boomeramg", help="scheme.solver.type values for part 2")
    ap.add_argument("--out", default=os.path.join(tempfile.gettempdir(), "sphflume-bench-isph"))
    a = ap.parse_args()
    print(f"machine: {machine()}; {a.threads} threads")
    if a.part in ("1", "both"):
        dambreak(a)
    if a.part in ("2", "both"):
        solver_scaling(a)


def isph_sets(a):
    """The ISPH run's keys: the formulation, and under lind its own Courant number (the cases' `cfl` is WCSPH's
    acoustic one) and its default shifting; under tsurudome its shifting A = 2 (docs/numerics.md §13)."""
    if a.formulation == "lind":
        return {"scheme.type": "isph", "scheme.formulation": "lind", "scheme.cfl": 0.4}
    return {"scheme.type": "isph", "scheme.formulation": "tsurudome", "scheme.shifting": "{coefficient: 2}"}


def dambreak(a):
    print(f"\n1. time to solution, same dx, same script run (ISPH formulation: {a.formulation})")
    print(f"{'case':>14} {'scheme':>6} {'particles':>9} {'steps':>6} {'wall s':>8} {'PPE share':>9} {'iter/solve':>10} "
          f"{'B/particle':>10}  passes (s): predict / assemble / solve / correct")
    runs = [(f"dam break a/{n}", "dambreak_2d.yaml", {"particles.dx": A / n, "time.end": 0.4, "time.output_interval": 0.1})
            for n in ([40, 80] if a.full else [40])]
    if a.full or a.flume:
        # Flume A at the thesis's d0 (dx = 0.005), H/h0 = 0.163, to the run-up's end (validation/runup_flume_a)
        runs.append(("Flume A d0", "runup_flume_a.yaml", {"particles.dx": 0.005, "time.end": 4.5, "time.output_interval": 0.5,
                                                          "time.snapshot_interval": 0.5,
                                                          "motions.0.height": 0.163 * 0.21}))
    for label, case, sets in runs:
        walls = {}
        for scheme, extra in (("wcsph", {}), ("isph", isph_sets(a))):
            out = os.path.join(a.out, f"{case[:-5]}_{sets['particles.dx']:g}_{scheme}")
            s, wall = run(a.sphflume, case, out, {**sets, **extra}, a.threads)
            walls[scheme] = wall
            ps = s.get("pressure_solver")
            share = f"{100 * (ps['assemble_seconds'] + ps['solve_seconds']) / s['wall_seconds']:.0f} %" if ps else "-"
            it = f"{ps['mean_iterations']:.1f}" if ps else "-"
            split = (f"{ps['predict_seconds']:.1f} / {ps['assemble_seconds']:.1f} / {ps['solve_seconds']:.1f} / "
                     f"{ps['correct_seconds']:.1f}") if ps and "predict_seconds" in ps else ""
            print(f"{label:>14} {scheme:>6} {s['particles']['total']:>9} {s['steps']:>6} {wall:>8.2f} {share:>9} {it:>10} "
                  f"{s.get('bytes_per_particle', float('nan')):>10.0f}  {split}", flush=True)
        print(f"{'':>14} ISPH / WCSPH time to solution: {walls['isph'] / walls['wcsph']:.2f} (issue 57: <= 2 bar, <= 1 goal)")


def solver_scaling(a):
    print("\n2. the pressure solver against N (still tank, 20 steps each)")
    print(f"{'solver':>10} {'dx':>8} {'N fluid':>8} {'unknowns':>8} {'iter/solve':>10} {'ms/solve':>9} {'iter x N (rel.)':>15}"
          f" {'ms/solve/unknown (rel.)':>23}")
    for solver in a.solvers.split(","):
        base = base_t = None
        for dx in ([0.0046, 0.0023, 0.00115] if a.full else [0.0046, 0.0023]):
            dt = 0.2 * dx / (0.1 * 10 * (2 * 9.81 * 0.21) ** 0.5)  # the scheme's cap cfl dx / U_ref
            out = os.path.join(a.out, f"tank_{solver}_dx{dx:g}")
            s, wall = run(a.sphflume, "hydrostatic_isph.yaml", out,
                          {"particles.dx": dx, "time.end": 20.5 * dt, "time.output_interval": 20.5 * dt,
                           "scheme.solver": f"{{type: {solver}}}", **isph_sets(a)}, a.threads)
            ps = s["pressure_solver"]
            n = s["particles"]["fluid"]
            work = ps["mean_iterations"] * n
            per = ps["solve_seconds"] / ps["solves"] / ps["unknowns"]
            base = base or work
            base_t = base_t or per
            print(f"{solver:>10} {dx:>8g} {n:>8} {ps['unknowns']:>8} {ps['mean_iterations']:>10.1f} "
                  f"{1e3 * ps['solve_seconds'] / ps['solves']:>9.2f} {work / base:>15.2f} {per / base_t:>23.2f}", flush=True)


if __name__ == "__main__":
    main()
