#!/usr/bin/python3
"""Numerical failure, escaping particles, unwritable output and a full disk, through the CLI.

- A run that blows up (sound speed far too small, CFL 1) stops with exit code 3 and a message naming the step,
  time, particle id, kind, position and a likely cause; its last snapshot is the last good step (failure step - 1),
  with finite fields and fluid densities inside the sane band; summary.json says failed and names that snapshot.
- Water running off the end of a bed leaves the domain: the particles are removed and counted per face, and the
  mass balance initial - removed = final holds to round-off (summary and snapshots).
- An output folder that cannot be created: exit 2, a message naming the folder, nothing written.
- A full disk (a file-size limit): exit 3, a message naming the file and the reason, and every snapshot file left
  behind opens and is complete (no truncated file that looks valid, no temporary left).
- A geometry mesh that is open (a box with a face missing): exit 2, a message naming the case file's line, the key,
  the mesh file and its border edges, nothing written.
Usage: check_failures.py SPHFLUME [WORKDIR]
"""
import json
import os
import re
import resource
import shutil
import signal
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from common import FIELDS, ROOT, check, finish, load_last, run, snapshots  # noqa: E402

binary = sys.argv[1]
work = sys.argv[2] if len(sys.argv) > 2 else "/tmp/sphflume_failure_test"
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
dam = os.path.join(ROOT, "cases", "dambreak_2d.yaml")
coarse = ["--set", "particles.dx=0.0073", "-q", "--threads", "2"]

# 1. blow-up
out = os.path.join(work, "blowup")
rc, log = run(binary, ["run", dam, "-o", out, "--set", "fluid.sound_speed=3", "--set", "scheme.cfl=1.0",
                       "--set", "time.end=0.5"] + coarse)
m = re.search(r"at step (\d+), t = ([0-9.eE+-]+) s: particle id (\d+) \((\w+)\) at \(([^)]*)\)", log)
check(rc == 3, f"blow-up: exit code 3 (got {rc})")
check(m is not None and "likely cause" in log, f"blow-up: message names step, time, particle id, kind, position, cause: {log.strip().splitlines()[-2] if log.strip() else ''}")
with open(os.path.join(out, "summary.json")) as f:
    sm = json.load(f)
check(sm["exit_status"] == "failed" and sm["exit_code"] == 3 and sm["message"], "blow-up: summary.json says failed, with the message")
if m:
    fail_step = int(m.group(1))
    path, fields, attrs = load_last(out)
    check(sm["last_good_snapshot"].endswith(os.path.basename(path)), f"blow-up: summary names the last snapshot {os.path.basename(path)}")
    check(int(attrs["step"]) == fail_step - 1, f"blow-up: last snapshot is step {attrs['step']} = failure step {fail_step} - 1")
    fl = fields["kind"] == 0
    finite = all(np.isfinite(fields[k]).all() for k in ["position", "velocity", "density", "pressure"])
    r = fields["density"][fl] / 1000.0
    check(finite and r.min() >= 0.7 and r.max() <= 1.3,
          f"blow-up: last good state finite, fluid density in [{r.min():.3f}, {r.max():.3f}] within [0.7, 1.3] rho0")

# 2. water running off a bed out of the domain
case = os.path.join(work, "runoff.yaml")
with open(case, "w") as f:
    f.write("""name: runoff
dimension: 2
particles: {dx: 0.01}
fluid: {density: 1000.0}
scheme: {viscosity: artificial, alpha: 0.02}
domain: {min: [-0.06, -0.3], max: [0.4, 0.6]}
geometry:
  - {type: box, fill: wall, min: [-0.04, -0.04], max: [0.25, 0.0]}
  - {type: box, fill: wall, min: [-0.04, 0.0], max: [0.0, 0.3]}
  - {type: box, fill: fluid, min: [0.0, 0.0], max: [0.1, 0.2]}
time: {end: 0.6, output_interval: 0.05}
""")
out = os.path.join(work, "runoff")
rc, log = run(binary, ["run", case, "-o", out, "-q", "--threads", "2"])
with open(os.path.join(out, "summary.json")) as f:
    sm = json.load(f)
mass = sm["mass"]
removed = sm["removed_particles_total"]
faces = sm["removed_particles"]
check(rc == 0 and removed > 0, f"run-off: exit 0 and particles removed ({removed}, by face {faces})")
check(sum(faces.values()) == removed and sm["particles"]["fluid"] + removed == sm["particles"]["initial_fluid"],
      f"run-off: removed per face add up; final fluid {sm['particles']['fluid']} + removed {removed} = initial {sm['particles']['initial_fluid']}")
bal = abs(mass["initial"] - mass["removed"] - mass["final"]) / mass["initial"]
check(bal <= 1e-12 and abs(mass["relative_error"]) <= 1e-12, f"run-off: mass balance initial - removed - final = {bal:.1e} of initial (<= 1e-12)")
_, fields, _ = load_last(out)
m_final = fields["mass"][fields["kind"] == 0].sum()
check(abs(m_final - mass["final"]) <= 1e-12 * mass["initial"], "run-off: the last snapshot's fluid mass equals the summary's final mass")
check("left the domain" in log, "run-off: the end-of-run summary line reports the removed particles")

# 3. an output folder that cannot be created (a path below a regular file)
blocker = os.path.join(work, "a_file")
open(blocker, "w").close()
out = os.path.join(blocker, "out")
rc, log = run(binary, ["run", dam, "-o", out, "--set", "time.end=0.01"] + coarse)
check(rc == 2 and out in log and "not writable" in log, f"unwritable output: exit 2 naming the folder (got {rc}: {log.strip()[-150:]})")
check(not os.path.exists(out), "unwritable output: nothing written")

# 4. a full disk: the process may not write files over 100 kB, less than one snapshot (SIGXFSZ ignored: writes fail with EFBIG)
def limit():
    signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
    resource.setrlimit(resource.RLIMIT_FSIZE, (100_000, 100_000))

out = os.path.join(work, "full")
rc, log = run(binary, ["run", dam, "-o", out, "--set", "time.end=0.1", "--set", "time.output_interval=0.01",
                       "--set", "particles.dx=0.0073", "--threads", "2", "-q"], preexec_fn=limit)
check(rc == 3 and "snap_" in log and ("too large" in log or "disk full" in log),
      f"full disk: exit 3, message names the file and the reason (got {rc}: {log.strip()[-200:]})")
ok = True
for s in snapshots(out):
    try:
        with h5py.File(s, "r") as h:
            ok &= all(h[k].shape[0] == h["id"].shape[0] for k in FIELDS)
    except OSError:
        ok = False
tmps = [p for p in os.listdir(os.path.join(out, "snapshots"))] if os.path.isdir(os.path.join(out, "snapshots")) else []
check(ok and not any(p.endswith(".tmp") for p in tmps), f"full disk: the {len(snapshots(out))} snapshot files left open and are complete; no temporary left")

# 5. an open mesh (an STL box without its top): refused at set-up, before anything is written
stl = os.path.join(work, "open_box.stl")
corner = [(x, y, z) for z in (0.1, 0.2) for y in (0.1, 0.2) for x in (0.3, 0.4)]
quads = [(0, 2, 3, 1), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]  # (the top 4 5 7 6 left out)
with open(stl, "w") as f:
    f.write("solid open\n")
    for q in quads:
        for t in ((q[0], q[1], q[2]), (q[0], q[2], q[3])):
            f.write(" facet normal 0 0 0\n  outer loop\n")
            f.writelines(f"   vertex {corner[i][0]} {corner[i][1]} {corner[i][2]}\n" for i in t)
            f.write("  endloop\n endfacet\n")
    f.write("endsolid open\n")
case = os.path.join(work, "mesh_case.yaml")
with open(case, "w") as f:
    f.write("dimension: 3\nparticles: {dx: 0.02}\nfluid: {density: 1000.0}\ngeometry:\n"
            "  - {type: tank, min: [0.0, 0.0, 0.0], max: [0.6, 0.3, 0.3]}\n"
            "  - {type: mesh, fill: wall, file: open_box.stl}\n"
            "  - {type: box, fill: fluid, min: [0.0, 0.0, 0.0], max: [0.2, 0.3, 0.1]}\ntime: {end: 0.01}\n")
out = os.path.join(work, "mesh_out")
rc, log = run(binary, ["run", case, "-o", out, "-q"])
check(rc == 2 and "line 6" in log and "geometry.1.file" in log and stl in log and "open mesh (4 border edges)" in log,
      f"open mesh: exit 2 naming the line, the key, the file and its border edges (got {rc}: {log.strip()[-220:]})")
check(not os.path.exists(os.path.join(out, "snapshots")), "open mesh: no snapshot written")

finish("check_failures")
