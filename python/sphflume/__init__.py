"""SPHFlume's run folders in Python: read them into numpy arrays and draw them (issue 43).

    import sphflume
    run = sphflume.Run("output/dambreak_2d")
    snap = run.snapshot(time=0.3)            # the snapshot nearest t = 0.3 s: dict of numpy arrays
    gauge = run.gauge("front")               # {"time": ..., "front": ...}
    sphflume.plot_snapshot(run, -1, "pressure", "last.png")

Needs numpy, h5py and matplotlib (Debian: python3-numpy python3-h5py python3-matplotlib; installed by
scripts/install-deps.sh). docs/output.md describes the files; `python3 -m sphflume --help` the command line.
"""
from .run import Run  # noqa: F401
from .plot import animate, plot_gauge, plot_snapshot  # noqa: F401

__all__ = ["Run", "plot_snapshot", "plot_gauge", "animate"]
