"""A run folder (docs/output.md) as numpy arrays: summary.json, the snapshots, the gauges."""
import csv
import glob
import json
import os

import numpy as np


class Run:
    """The output folder of `sphflume run CASE --output DIR`."""

    def __init__(self, folder):
        self.folder = os.path.abspath(folder)
        if not os.path.isdir(self.folder):
            raise FileNotFoundError(f"{folder}: no such run folder (the --output of sphflume run)")
        self._files = sorted(glob.glob(os.path.join(self.folder, "snapshots", "snap_*.h5")))
        self._times = None

    @property
    def summary(self):
        """summary.json as a dict (docs/output.md, "summary.json")."""
        with open(os.path.join(self.folder, "summary.json")) as f:
            return json.load(f)

    @property
    def snapshot_files(self):
        return list(self._files)

    @property
    def times(self):
        """The snapshots' times in s, in order (read from each file's `time` attribute)."""
        if self._times is None:
            import h5py
            ts = []
            for fn in self._files:
                with h5py.File(fn, "r") as f:
                    ts.append(float(f.attrs["time"]))
            self._times = np.array(ts)
        return self._times

    def __len__(self):
        return len(self._files)

    def snapshot(self, index=None, time=None):
        """One snapshot as a dict of numpy arrays, one row per particle (position N x 3, velocity N x 3,
        pressure, density, mass, kind, id and the extra scalar fields), plus "time", "step" and
        "dimension". By `index` (negative counts from the end; default the last) or by `time` (the
        snapshot nearest it). Rows are not in the same order from one snapshot to the next: match by id."""
        import h5py
        if not self._files:
            raise FileNotFoundError(f"{self.folder}: no snapshots (the run wrote none, or ran with --no-output)")
        if time is not None:
            index = int(np.argmin(np.abs(self.times - float(time))))
        if index is None:
            index = -1
        fn = self._files[index]
        out = {}
        with h5py.File(fn, "r") as f:
            for k, v in f.items():
                if isinstance(v, h5py.Dataset):
                    out[k] = v[()]
            out["time"] = float(f.attrs["time"])
            out["step"] = int(f.attrs["step"])
            out["dimension"] = int(f.attrs["dimension"])
        return out

    def gauge_names(self):
        """The gauges of the run (gauges/NAME.csv), without the .points and .mean companions."""
        names = []
        for fn in sorted(glob.glob(os.path.join(self.folder, "gauges", "*.csv"))):
            base = os.path.basename(fn)[:-4]
            if not base.endswith(".points") and not base.endswith(".mean"):
                names.append(base)
        return names

    def gauge(self, name):
        """gauges/NAME.csv as {column: numpy array} in the file's column order (comment lines skipped)."""
        fn = os.path.join(self.folder, "gauges", name + ".csv")
        if not os.path.exists(fn):
            raise FileNotFoundError(f"{fn}: no such gauge (this run has: {', '.join(self.gauge_names()) or 'none'})")
        with open(fn) as f:
            rows = list(csv.reader(line for line in f if not line.startswith("#")))
        header, body = rows[0], rows[1:]
        data = np.array([[float(v) for v in r] for r in body]) if body else np.zeros((0, len(header)))
        return {h: data[:, i] for i, h in enumerate(header)}
