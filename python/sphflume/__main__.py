"""python3 -m sphflume plot RUN_FOLDER [--field pressure] [--snapshot -1] [--animate] [--out DIR]

Writes DIR/snapshot_*.png (the snapshot, fluid coloured by the field, walls grey), DIR/gauge_NAME.png for every
gauge, and with --animate DIR/FIELD.mp4 (ffmpeg) or .gif; prints each path. DIR defaults to RUN_FOLDER/plots.
Exit code 2 for a folder or field that does not exist."""
import argparse
import os
import sys

from . import Run, animate, plot_gauge, plot_snapshot


def main(argv=None):
    ap = argparse.ArgumentParser(prog="python3 -m sphflume", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = ap.add_subparsers(dest="command", required=True)
    p = sub.add_parser("plot", help="draw a run folder: the last (or a chosen) snapshot, every gauge")
    p.add_argument("run", help="the run folder (sphflume run ... --output RUN)")
    p.add_argument("--field", default="pressure", help="pressure, density, speed, velocity_x, velocity_z, nu_t, ...")
    p.add_argument("--snapshot", type=int, default=-1, help="snapshot index (negative from the end; default -1)")
    p.add_argument("--animate", action="store_true", help="also every snapshot as an MP4 (ffmpeg) or a GIF")
    p.add_argument("--out", default=None, help="folder for the pictures (default RUN/plots)")
    a = ap.parse_args(argv)
    try:
        run = Run(a.run)
        out = a.out or os.path.join(run.folder, "plots")
        snap = run.snapshot(a.snapshot)
        paths = [plot_snapshot(run, a.snapshot, a.field, os.path.join(out, f"snapshot_{snap['step']:08d}_{a.field}.png"))]
        paths += [plot_gauge(run, g, os.path.join(out, f"gauge_{g}.png")) for g in run.gauge_names()]
        if a.animate:
            from matplotlib import animation  # (MP4 where ffmpeg is, GIF otherwise)
            ext = ".mp4" if animation.writers.is_available("ffmpeg") else ".gif"
            paths.append(animate(run, a.field, None if a.out is None else os.path.join(out, a.field + ext)))
    except (FileNotFoundError, KeyError, IndexError) as e:
        print(f"sphflume plot: {e.args[0] if e.args else e}", file=sys.stderr)
        return 2
    for path in paths:
        print(path)
    return 0


if __name__ == "__main__":
    sys.exit(main())
