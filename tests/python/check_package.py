#!/usr/bin/python3
"""The Python package python/sphflume (issue 43) against a run it did not write itself.

Usage: check_package.py SPHFLUME_BINARY WORK_DIR

Runs the 2D dam break coarsely (dx = 0.0146, to 0.2 s, one thread) into WORK_DIR/output/dambreak_2d, then
  1. runs the example block of docs/output.md (the one after "<!-- example:") from WORK_DIR, as a user would;
  2. checks what the package reads against the run's own records: the fluid mass of the last snapshot equals
     summary.json's final mass (1e-12 relative: the same doubles summed), the snapshots are those of
     time.output_interval (t = 0 and every 0.01 s: 21), and the gauge rows carry the snapshots' times;
  3. checks the pictures: PNG files (signature, > 10 kB), one per gauge from the command line; the animation
     a GIF with one frame per snapshot;
  4. a missing folder and an unknown field exit with code 2 naming them.
Exit 0 when every check passes, 1 otherwise."""
import json
import os
import re
import shutil
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", ".."))
PY = os.path.join(ROOT, "python")


def main():
    binary, work = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
    shutil.rmtree(work, ignore_errors=True)
    out = os.path.join(work, "output", "dambreak_2d")
    os.makedirs(work)
    subprocess.run([binary, "run", os.path.join(ROOT, "cases", "dambreak_2d.yaml"), "--output", out, "-q",
                    "--threads", "1", "--set", "particles.dx=0.0146", "--set", "time.end=0.2"], check=True)
    failures = []

    def check(ok, what):
        print(("[PASS] " if ok else "[FAIL] ") + what)
        if not ok:
            failures.append(what)

    # 1. the documented example, verbatim
    doc = open(os.path.join(ROOT, "docs", "output.md")).read()
    m = re.search(r"<!-- example:.*?-->\s*```python\n(.*?)```", doc, re.S)
    check(m is not None, "docs/output.md has the example block")
    env = dict(os.environ, PYTHONPATH=PY, MPLBACKEND="Agg")
    r = subprocess.run([sys.executable, "-c", m.group(1)], cwd=work, env=env, capture_output=True, text=True)
    check(r.returncode == 0, f"the example runs (exit {r.returncode}) {r.stderr[-500:]}")
    for png in ("last_speed.png", "front.png"):
        p = os.path.join(out, png)
        check(os.path.exists(p) and open(p, "rb").read(8) == b"\x89PNG\r\n\x1a\n" and os.path.getsize(p) > 10_000,
              f"the example wrote {png} (a PNG over 10 kB)")

    # 2. what the package reads, against the run's own records
    sys.path.insert(0, PY)
    import numpy as np
    import sphflume
    run = sphflume.Run(out)
    summary = json.load(open(os.path.join(out, "summary.json")))
    last = run.snapshot()
    fluid = last["kind"] == 0
    mass = float(last["mass"][fluid].sum())
    check(abs(mass - summary["mass"]["final"]) <= 1e-12 * summary["mass"]["final"],
          f"fluid mass of the last snapshot {mass:.15g} = summary's final {summary['mass']['final']:.15g}")
    check(len(run) == 21 and np.allclose(run.times, np.arange(21) * 0.01, atol=1e-12, rtol=0),
          f"21 snapshots at t = 0, 0.01, ..., 0.2 s (read {len(run)}, last t = {run.times[-1]:.6g})")
    front = run.gauge("front")
    check(list(front)[0] == "time" and np.allclose(front["time"], run.times, atol=1e-12, rtol=0),
          "the front gauge's rows are at the snapshots' times")
    check(abs(run.snapshot(time=0.104)["time"] - 0.1) < 1e-12, "snapshot(time=0.104) is the one at t = 0.1 s")

    # 3. the command line
    r = subprocess.run([sys.executable, "-m", "sphflume", "plot", out, "--field", "speed"], env=env,
                       capture_output=True, text=True)
    paths = r.stdout.split()
    check(r.returncode == 0 and len(paths) == 1 + len(run.gauge_names()),
          f"python3 -m sphflume plot: exit {r.returncode}, {len(paths)} pictures for {len(run.gauge_names())} gauges")
    check(all(os.path.getsize(p) > 10_000 and open(p, "rb").read(4) == b"\x89PNG" for p in paths),
          "every picture is a PNG over 10 kB")

    anim = sphflume.animate(run, "pressure", os.path.join(work, "pressure.gif"))
    with open(anim, "rb") as f:
        head = f.read(6)
    from PIL import Image  # (matplotlib's own dependency)
    frames = Image.open(anim).n_frames
    check(head == b"GIF89a" and frames == len(run), f"the animation: a GIF of {frames} frames for {len(run)} snapshots")
    if shutil.which("ffmpeg") and shutil.which("ffprobe"):  # (scripts/install-deps.sh installs Debian's ffmpeg)
        mp4 = sphflume.animate(run, "pressure")  # the default: MP4 where ffmpeg is
        probe = subprocess.run(["ffprobe", "-v", "error", "-count_frames", "-select_streams", "v:0", "-show_entries",
                                "stream=codec_name,nb_read_frames", "-of", "csv=p=0", mp4], capture_output=True, text=True)
        fields = probe.stdout.strip().split(",")
        check(mp4.endswith(".mp4") and probe.returncode == 0 and len(fields) == 2 and fields[1] == str(len(run)),
              f"the animation with ffmpeg: an MP4 ({probe.stdout.strip()}) of one frame per snapshot ({len(run)})")
    else:
        print("[SKIP] no ffmpeg: the MP4 animation is not checked (GIF above)")

    # 4. bad input
    r = subprocess.run([sys.executable, "-m", "sphflume", "plot", os.path.join(work, "nosuch")], env=env,
                       capture_output=True, text=True)
    check(r.returncode == 2 and "nosuch" in r.stderr, f"a missing run folder: exit {r.returncode}, named")
    r = subprocess.run([sys.executable, "-m", "sphflume", "plot", out, "--field", "vorticity"], env=env,
                       capture_output=True, text=True)
    check(r.returncode == 2 and "vorticity" in r.stderr and "pressure" in r.stderr,
          f"an unknown field: exit {r.returncode}, named with the fields there are")
    print("check_package:", "FAILED: " + "; ".join(failures) if failures else "all passed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
