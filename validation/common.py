"""Shared helpers of the validation scripts (validation/*/check.py)."""
import hashlib
import json
import math
import os
import shutil
import subprocess
import tempfile
import time


def parse_sets(pairs):
    """["a.b=1", ...] from --set options -> {"a.b": "1", ...}."""
    out = {}
    for kv in pairs:
        if "=" not in kv:
            raise SystemExit(f"--set {kv}: expected KEY=VALUE")
        k, v = kv.split("=", 1)
        out[k] = v
    return out


def add_set_option(ap):
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                    help="extra case overrides passed to sphflume (e.g. scheme.integrator=verlet)")


CHECKPOINT_EVERY = 600  # wall seconds between a run's checkpoints (a run killed outright resumes from the last)


def run_case(sphflume, case, out, sets, threads, reuse):
    """Runs sphflume into out (a folder this script owns); returns (summary or None, wall seconds, rc).

    With reuse: a finished run of the same dx and end is read back; an unfinished one goes on from out/checkpoint.h5:
    one stopped by a signal (its summary says interrupted), or one killed outright (no summary) whose out/run.json
    shows the same case file (path and text) and overrides. A run that failed starts afresh. Runs write a checkpoint
    every CHECKPOINT_EVERY wall seconds, so a long one loses at most that much."""
    summary_path = os.path.join(out, "summary.json")
    checkpoint = os.path.join(out, "checkpoint.h5")
    started = os.path.join(out, "run.json")
    with open(case, "rb") as f:  # the case's text too: an edited case file starts afresh
        case_hash = hashlib.sha256(f.read()).hexdigest()
    this_run = {"case": os.path.abspath(case), "case_sha256": case_hash, "sets": {k: str(v) for k, v in sets.items()}}
    resume = False
    s = None
    if reuse and os.path.exists(summary_path):
        with open(summary_path) as f:
            s = json.load(f)
        same = math.isclose(s.get("dx", -1), float(sets["particles.dx"]), rel_tol=1e-7) \
            and math.isclose(s.get("end_time", -1), float(sets["time.end"]), rel_tol=1e-7)
        if s.get("exit_code") == 0 and same:
            print(f"reusing {out} (dx = {s['dx']}, end = {s['end_time']})")
            return s, float(s.get("wall_seconds", float("nan"))), 0
        # A run stopped by a signal (the session ended) wrote checkpoint.h5: go on from there (issue 40).
        resume = same and s.get("exit_status") == "interrupted" and os.path.exists(checkpoint)
    if reuse and s is None and os.path.exists(checkpoint) and os.path.exists(started):
        # killed outright (no summary written at the end): its periodic checkpoint, if the run was this one
        with open(started) as f:
            resume = json.load(f) == this_run
    if os.path.isdir(out) and not resume:
        shutil.rmtree(out)
    os.makedirs(out, exist_ok=True)
    if not resume:
        with open(started, "w") as f:
            json.dump(this_run, f)
    cmd = [sphflume, "run", case, "--output", out, "-q", "--threads", str(threads),
           "--checkpoint-every", str(CHECKPOINT_EVERY)]
    if resume:
        cmd += ["--restart", checkpoint]
        print(f"resuming {out} from its checkpoint" + (f" (t = {s['simulated_time']:.4g} s)" if s else ""))
    for k, v in sets.items():
        cmd += ["--set", f"{k}={v}"]
    print("running:", " ".join(cmd), flush=True)
    t0 = time.time()
    r = subprocess.run(cmd, capture_output=True, text=True)
    wall = time.time() - t0
    if r.returncode != 0:
        print(f"RUN FAILED (exit code {r.returncode}) after {wall:.1f} s")
        print(r.stdout[-2000:], r.stderr[-2000:], sep="\n")
        return None, wall, r.returncode
    with open(summary_path) as f:
        s = json.load(f)
    print(f"  done in {wall:.1f} s wall: {s['steps']} steps, {s['particles']['total']} particles, "
          f"simulated {s['simulated_time']:.4g} s", flush=True)
    return s, wall, 0


def fluid_snapshots(out, fields):
    """[(time, {"x", "z", and each of `fields` (snapshot dataset names)})] of the fluid particles
    (kind 0), one per snapshot in OUT/snapshots, in time order. z is the vertical (last) coordinate."""
    import glob
    import h5py
    res = []
    for fn in sorted(glob.glob(os.path.join(out, "snapshots", "*.h5"))):
        with h5py.File(fn, "r") as f:
            k = f["kind"][:] == 0
            p = f["position"][:][k]
            d = {"x": p[:, 0], "z": p[:, -1]}
            for name in fields:
                d[name] = f[name][:][k]
            res.append((float(f.attrs["time"]), d))
    return res


def read_rows(path):
    """A CSV file (lines starting with '#' skipped) -> (header list, float array of the rows)."""
    import csv
    import numpy as np
    with open(path) as f:
        rows = list(csv.reader(line for line in f if not line.startswith("#")))
    return rows[0], np.array([[float(v) for v in r] for r in rows[1:]])


def level_series(out, name):
    """A water_level gauge of the run in OUT: (time, level relative to its own reading at t = 0: the lattice's offset
    of the SPH level cancels)."""
    hdr, rows = read_rows(os.path.join(out, "gauges", f"{name}.csv"))
    lev = rows[:, hdr.index("level")]
    return rows[:, 0], lev - lev[0]


def run_metrics(rep, label, s, end, mass_tol=1e-12):
    """The two metrics every closed-flume run gates: it reached t_end, and its fluid mass balance is exact."""
    rep.metric(f"{label}run reached t_end (s)", f"{s['simulated_time']:.4f}", s["simulated_time"] >= end * (1 - 1e-6),
               f">= {end}", "issue 22")
    rep.metric(f"{label}fluid mass (initial - removed - final) / initial", f"{s['mass']['relative_error']:.1e}",
               abs(s["mass"]["relative_error"]) <= mass_tol, f"|.| <= {mass_tol:g}", "closed flume")


def band(samples):
    """The uncertainty band of a time-mean: {"mean", "sd", "se", "n", "n_eff"} of the samples (e.g. a gauge's output
    rows in the averaging window; NaN propagates). sd: the samples' standard deviation (ddof = 1), the signal's
    scatter (noise band). se: the standard error of the mean, sd / sqrt(n_eff), with the effective sample count
    from the lag-1 autocorrelation r1 of the samples, n_eff = n (1 - r1) / (1 + r1) clipped to [1, n] (an AR(1)
    estimate: successive output rows are not independent; a slow oscillation longer than the window is not
    caught). n < 2: sd and se are NaN."""
    import numpy as np
    x = np.asarray(samples, dtype=float).ravel()
    n = len(x)
    mean = float(np.mean(x)) if n else float("nan")
    if n < 2:
        return {"mean": mean, "sd": float("nan"), "se": float("nan"), "n": n, "n_eff": float(n)}
    d = x - mean
    ss = float(np.sum(d * d))
    r1 = float(np.sum(d[:-1] * d[1:]) / ss) if ss > 0 else 0.0
    n_eff = min(max(n * (1 - r1) / (1 + r1), 1.0), float(n)) if r1 > -1 else float(n)
    sd = float(np.std(x, ddof=1))
    return {"mean": mean, "sd": sd, "se": sd / math.sqrt(n_eff), "n": n, "n_eff": n_eff}


def fmt_band(b, ref=None, unit="", scale=1.0, digits=2):
    """A band (band()) as text: with ref, the mean's relative error mean / ref - 1 and sd, se in % of |ref|, e.g.
    "+0.84 % (sd 0.69 %, se 0.10 %, n_eff 12/51)"; without, mean, sd, se times scale, followed by unit."""
    mean = b["mean"] * scale
    if ref is not None:  # the relative error mean / ref - 1 (its sign as the checks print it, also for ref < 0)
        mean, scale, unit = 100.0 * (b["mean"] / ref - 1), 100.0 / abs(ref), " %"
    return (f"{mean:+.{digits}f}{unit} (sd {scale * b['sd']:.{digits}f}{unit}, "
            f"se {scale * b['se']:.{digits}f}{unit}, n_eff {b['n_eff']:.0f}/{b['n']})")


def info(name, value, ok, threshold, source):
    """A metric printed but not gated: same arguments as Report.metric."""
    print(f"  (info) {name} = {value} ({'meets' if ok else 'misses'} {threshold}; {source})")


def save_figure(fig, here, name, mode, out, dpi=110):
    """The fine run's figure goes next to the script (committed), any other mode's into --out."""
    png = os.path.join(here if mode == "fine" else out, f"{name}.png")
    os.makedirs(os.path.dirname(png), exist_ok=True)
    fig.savefig(png, dpi=dpi)
    print(f"figure: {png}")
    return png


class Report:
    """Prints each metric as [PASS]/[FAIL] with its threshold and source; finish() exits 1 on a failure."""

    def __init__(self):
        self.failed = []

    def metric(self, name, value, ok, threshold, source):
        print(f"[{'PASS' if ok else 'FAIL'}] {name} = {value}   (threshold: {threshold}; source: {source})")
        if not ok:
            self.failed.append(name)

    def finish(self, name, mode):
        if self.failed:
            print(f"\n{name} {mode}: FAILED: {', '.join(self.failed)}")
            raise SystemExit(1)
        print(f"\n{name} {mode}: PASSED")


REPO = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))


def default_binary():
    """$SPHFLUME if set, else build/sphflume of the repository that holds this script."""
    return os.environ.get("SPHFLUME") or os.path.join(REPO, "build", "sphflume")


def add_spacing_option(ap, flag="--dx"):
    """`--dx DX` (or `--dp`), repeatable: only the mode's runs at these spacings (a check whose runs are long runs one
    spacing per call; with --set, a variant at one spacing). Read it with select_spacings."""
    ap.add_argument(flag, type=float, action="append", default=[], dest="only_spacings",
                    help="only the mode's runs at this spacing, the finest of them gated (repeatable)")


def select_spacings(runs, only, flag="--dx", key=lambda r: r):
    """The runs (spacings, or tuples whose spacing key() gives) at the spacings `only` names (all of them when it names
    none); a SystemExit naming the spacings there are when it names none of them."""
    chosen = [r for r in runs if not only or any(math.isclose(key(r), d, rel_tol=1e-9) for d in only)]
    if not chosen:
        raise SystemExit(f"{flag} {only}: no run at that spacing (the mode's: {sorted({key(r) for r in runs})})")
    return chosen


def validation_args(name, doc, modes, extra=None):
    """The options every check.py takes: --sphflume, --mode, --out, --threads, --set, --reuse; extra(ap) adds a
    check's own options."""
    import argparse
    ap = argparse.ArgumentParser(description=doc, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--sphflume", default=default_binary(),
                    help="the sphflume binary (default: build/sphflume of this repository, or $SPHFLUME)")
    ap.add_argument("--mode", choices=modes, default="coarse")
    ap.add_argument("--out", default=os.path.join(tempfile.gettempdir(), "sphflume-validation", name))
    ap.add_argument("--threads", type=int, default=2)
    add_set_option(ap)
    ap.add_argument("--reuse", action="store_true", help="reuse a finished run in --out with the same dx and end time")
    if extra:
        extra(ap)
    return ap.parse_args()
