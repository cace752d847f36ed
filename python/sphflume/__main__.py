"""python3 -m sphflume plot RUN_FOLDER [--field pressure] [--snapshot -1] [--animate] [--out DIR]
python3 -m sphflume waves RUN_FOLDER [--depth H] [--reflection NAME=X NAME=X NAME=X] [--from T0] [--to T1] [--out DIR]

Writes DIR/snapshot_*.png (the snapshot, fluid coloured by the field, walls grey), DIR/gauge_NAME.png for every
gauge, and with --animate DIR/FIELD.mp4 (ffmpeg) or .gif; prints each path. DIR defaults to RUN_FOLDER/plots.
`waves` analyses every water_level gauge (spectrum, Hm0, Tp, H1/3, Hmax), the three named gauges'
incident and reflected waves (with --depth), and every overtopping gauge's discharge (sphflume.waves);
writes DIR/waves.json and DIR/waves_NAME.png and prints the report.
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
    w = sub.add_parser("waves", help="wave analysis: spectra, heights, reflection, overtopping")
    w.add_argument("run", help="the run folder")
    w.add_argument("--depth", type=float, default=None, help="still-water depth [m] (for --reflection)")
    w.add_argument("--reflection", nargs=3, metavar="NAME=X", default=None,
                   help="three water_level gauges and their x [m] for the incident/reflected separation")
    w.add_argument("--from", dest="t0", type=float, default=None, help="start of the window [s]")
    w.add_argument("--to", dest="t1", type=float, default=None, help="end of the window [s]")
    w.add_argument("--out", default=None, help="folder for waves.json and the pictures (default RUN/plots)")
    a = ap.parse_args(argv)
    if a.command == "waves":
        return waves_command(a)
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


def waves_command(a):
    from . import waves
    try:
        refl = None
        if a.reflection:
            refl = {}
            for item in a.reflection:
                name, _, x = item.partition("=")
                refl[name] = float(x)
        rep = waves.analyse(a.run, depth=a.depth, reflection_gauges=refl, t0=a.t0, t1=a.t1, out=a.out)
    except (FileNotFoundError, KeyError, ValueError) as e:
        print(f"sphflume waves: {e.args[0] if e.args else e}", file=sys.stderr)
        return 2
    import json
    print(json.dumps({k: v for k, v in rep.items() if k != "figures"}, indent=1))
    for p in rep["figures"]:
        print(p)
    return 0


if __name__ == "__main__":
    sys.exit(main())
