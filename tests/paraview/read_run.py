"""Check that ParaView itself reads an SPHFlume output folder correctly.

Usage:
    pvpython tests/paraview/read_run.py OUTPUT_DIR [--reader Xdmf3ReaderS|Xdmf3ReaderT|XDMFReader]

Opens OUTPUT_DIR/particles.xdmf with a ParaView reader (default: Xdmf3ReaderS, the reader
ParaView's File > Open picks for .xdmf), checks that the time steps are those of the snapshot
files, and at the first and last output time compares what ParaView hands out with the HDF5
snapshot (read with h5py): point count, positions, point arrays, particle kinds, vertex cells
(without cells ParaView's default Surface/Points views draw nothing), and that the fluid moved.
Prints one PASS/FAIL line per check and a summary; exits 0 when every check passes, 1 otherwise.

Reading needs no X display: nothing is rendered.

The HDF5 files are read with h5py inside pvpython when it is importable; otherwise this same
file is run with another Python that has h5py (set H5PY_PYTHON, else /usr/bin/python3, python3)
as  `python3 read_run.py --dump-h5 FILE OUT.npz`.
"""

import glob
import os
import subprocess
import sys
import tempfile
import traceback

import numpy as np

ARRAYS = {"velocity": 3, "pressure": 1, "density": 1, "mass": 1, "kind": 1, "id": 1}
FLUID, WALL = 0, 1


# ---------------------------------------------------------------------------------------------
# HDF5 side (h5py, in process or in a helper Python)


def read_h5_inprocess(path):
    import h5py

    with h5py.File(path, "r") as f:
        out = {name: np.asarray(f[name][()]) for name in f.keys() if isinstance(f[name], h5py.Dataset)}
        out["time"] = np.asarray(float(f.attrs["time"]))
        out["step"] = np.asarray(int(f.attrs["step"]))
    return out


def dump_h5(path, npz):
    np.savez(npz, **read_h5_inprocess(path))


def read_h5(path):
    try:
        import h5py  # noqa: F401
    except ImportError:
        pass
    else:
        return read_h5_inprocess(path)
    candidates = [os.environ.get("H5PY_PYTHON"), "/usr/bin/python3", "python3"]
    errors = []
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTHONHOME")}
    for py in filter(None, candidates):
        with tempfile.TemporaryDirectory() as tmp:
            npz = os.path.join(tmp, "h5.npz")
            try:
                r = subprocess.run([py, os.path.abspath(__file__), "--dump-h5", path, npz],
                                   capture_output=True, text=True, env=env)
            except OSError as e:
                errors.append(f"{py}: {e}")
                continue
            if r.returncode == 0 and os.path.exists(npz):
                with np.load(npz) as z:
                    return {k: z[k] for k in z.files}
            errors.append(f"{py}: {r.stderr.strip().splitlines()[-1:] or r.returncode}")
    raise RuntimeError("cannot read HDF5 without h5py: pvpython has no h5py and no helper Python "
                       "with h5py was found (install python3-h5py or set H5PY_PYTHON): "
                       + "; ".join(errors))


# ---------------------------------------------------------------------------------------------
# Checks bookkeeping


def say(text):
    # pvpython routes sys.stdout through vtkOutputWindow, which main() replaces to collect the
    # reader's messages; write to the process's real stdout instead.
    sys.__stdout__.write(text + "\n")
    sys.__stdout__.flush()


class Checks:
    def __init__(self):
        self.results = []

    def check(self, ok, what, detail=""):
        ok = bool(ok)
        self.results.append(ok)
        say(f"{'PASS' if ok else 'FAIL'}: {what}" + (f"  [{detail}]" if detail else ""))
        return ok

    def info(self, text):
        say(f"INFO: {text}")

    def summary(self):
        failed = self.results.count(False)
        if failed or not self.results:
            say(f"RESULT: FAIL ({failed} of {len(self.results)} checks failed)")
            return 1
        say(f"RESULT: PASS (all {len(self.results)} checks passed)")
        return 0


# ---------------------------------------------------------------------------------------------
# ParaView side


def single_dataset(data):
    """The reader's output as one vtkDataSet (unwraps a multiblock holding one leaf)."""
    if data is None:
        return None
    if data.IsA("vtkCompositeDataSet"):
        it = data.NewIterator()
        it.InitTraversal()
        leaves = []
        while not it.IsDoneWithTraversal():
            leaves.append(it.GetCurrentDataObject())
            it.GoToNextItem()
        return leaves[0] if len(leaves) == 1 else None
    return data


def vtk_array(point_data, name):
    from vtkmodules.util.numpy_support import vtk_to_numpy

    a = point_data.GetArray(name)
    return None if a is None else vtk_to_numpy(a)


def check_snapshot(C, reader, t, h5, label):
    from paraview import servermanager
    from vtkmodules.util.numpy_support import vtk_to_numpy

    reader.UpdatePipeline(t)
    ds = single_dataset(servermanager.Fetch(reader))
    if not C.check(ds is not None and ds.IsA("vtkDataSet"), f"{label}: reader produced one dataset",
                   "got " + (ds.GetClassName() if ds is not None else "nothing")):
        return None
    n_h5 = len(h5["position"])
    n = ds.GetNumberOfPoints()
    C.check(n == n_h5, f"{label}: point count equals HDF5 dataset length", f"ParaView {n}, HDF5 {n_h5}")
    if n != n_h5 or n == 0:
        return None

    pos = vtk_to_numpy(ds.GetPoints().GetData()).astype(np.float64)
    ref = np.asarray(h5["position"], dtype=np.float64).reshape(n_h5, 3)
    scale = max(1.0, float(np.abs(ref).max()))
    err = float(np.abs(pos - ref).max())
    C.check(err <= 1e-12 * scale, f"{label}: positions match HDF5", f"max |diff| = {err:.3g}")

    pd = ds.GetPointData()
    have = [pd.GetArrayName(i) for i in range(pd.GetNumberOfArrays())]
    arrays = {}
    for name, ncomp in ARRAYS.items():
        a = vtk_array(pd, name)
        if a is None:
            C.check(False, f"{label}: point array '{name}'", f"missing; point arrays: {have}")
            continue
        a = a.reshape(n, -1)
        r = np.asarray(h5[name]).reshape(n, -1)
        if a.shape[1] != ncomp:
            C.check(False, f"{label}: point array '{name}'", f"{a.shape[1]} components, expected {ncomp}")
            continue
        if name in ("kind", "id"):
            ok, detail = np.array_equal(a.astype(np.int64), r.astype(np.int64)), "identical"
        else:
            d = float(np.abs(a - r).max())
            ok, detail = d <= 1e-12 * max(1.0, float(np.abs(r).max())), f"max |diff| = {d:.3g}"
        C.check(ok, f"{label}: point array '{name}' ({ncomp} comp., {a.dtype}) matches HDF5", detail)
        arrays[name] = a[:, 0] if ncomp == 1 else a

    if "kind" in arrays:
        k = arrays["kind"]
        nf, nw = int((k == FLUID).sum()), int((k == WALL).sum())
        C.check(nf > 0 and nw > 0, f"{label}: kind has fluid (0) and wall (1) particles",
                f"{nf} fluid, {nw} wall, values {sorted(set(k.tolist()))}")

    # Cells: ParaView's Surface and Points representations draw cells, not bare points, so a
    # particle set must come with one vertex / poly-vertex cell per particle to be visible
    # (only the Point Gaussian representation draws cell-less points).
    ncells = ds.GetNumberOfCells()
    covered = 0
    types = set()
    if ncells and ds.IsA("vtkUnstructuredGrid"):
        covered = ds.GetCells().GetNumberOfConnectivityIds()
        types = set(vtk_to_numpy(ds.GetCellTypesArray()).tolist())
    elif ncells and ds.IsA("vtkPolyData"):
        covered = ds.GetVerts().GetNumberOfConnectivityIds()
        types = {1, 2} if covered else set()
    C.check(ncells > 0 and covered == n and types <= {1, 2},  # VTK_VERTEX, VTK_POLY_VERTEX
            f"{label}: every particle is a vertex cell (visible in ParaView's default view)",
            f"{ncells} cells covering {covered} of {n} points, cell types {sorted(types)}"
            + ("; the XDMF <Topology> has no connectivity DataItem" if ncells == 0 else ""))

    return {"pos": pos, **arrays}


XDMF_TYPES = {("Float", 8): "float64", ("Float", 4): "float32", ("Int", 4): "int32",
              ("Int", 8): "int64", ("UInt", 4): "uint32", ("UInt", 8): "uint64"}


def check_xdmf_references(C, xdmf, h5_by_path):
    """Every HDF DataItem must name an existing file and dataset of the stated shape and type.

    ParaView's XDMF3 reader aborts the whole process (uncaught XdmfError) on a missing file or
    a shape mismatch, so this is checked first, without ParaView.
    """
    import xml.etree.ElementTree as ET

    base = os.path.dirname(xdmf)
    problems, count = [], 0
    for item in ET.parse(xdmf).getroot().iter("DataItem"):
        if item.get("Format", "XML") != "HDF":
            continue
        count += 1
        ref = (item.text or "").strip()
        fname, _, dset = ref.partition(":")
        path = os.path.normpath(os.path.join(base, fname))
        if path not in h5_by_path:
            if not os.path.isfile(path):
                problems.append(f"{ref}: file missing")
                continue
            h5_by_path[path] = read_h5(path)
        data = h5_by_path[path].get(dset.lstrip("/"))
        if data is None:
            problems.append(f"{ref}: no such dataset")
            continue
        dims = tuple(int(x) for x in item.get("Dimensions", "").split())
        if dims != tuple(data.shape):
            problems.append(f"{ref}: Dimensions {dims} but dataset shape {tuple(data.shape)}")
        want = XDMF_TYPES.get((item.get("NumberType", "Float"), int(item.get("Precision", "4"))))
        if want != str(data.dtype):
            problems.append(f"{ref}: NumberType/Precision say {want} but dataset is {data.dtype}")
    C.check(count > 0 and not problems, "XDMF DataItems reference existing HDF5 datasets of matching shape/type",
            f"{count} HDF DataItems" + ("; " + "; ".join(problems[:10]) if problems else ""))
    return not problems


def open_reader(reader_name, xdmf):
    import paraview.simple as pvs

    ctor = getattr(pvs, reader_name)
    prop = "FileNames" if reader_name == "XDMFReader" else "FileName"
    return ctor(**{prop: [xdmf]})


def main(argv):
    if len(argv) >= 1 and argv[0] == "--dump-h5":  # helper mode (plain python3 with h5py)
        dump_h5(argv[1], argv[2])
        return 0
    reader_name = "Xdmf3ReaderS"
    args = list(argv)
    if "--reader" in args:
        i = args.index("--reader")
        reader_name = args[i + 1]
        del args[i:i + 2]
    if len(args) != 1:
        say(__doc__)
        return 2
    out = os.path.abspath(args[0])
    xdmf = os.path.join(out, "particles.xdmf")

    C = Checks()
    try:
        import paraview.simple as pvs
        from vtkmodules.vtkCommonCore import vtkOutputWindow, vtkStringOutputWindow

        log = vtkStringOutputWindow()  # collect VTK/ParaView warnings and errors
        vtkOutputWindow.SetInstance(log)
        C.info(f"ParaView {pvs.GetParaViewVersion()}, reader {reader_name}, {xdmf}")
        if not C.check(os.path.isfile(xdmf), "particles.xdmf exists"):
            return C.summary()
        C.info(f"OpenDataFile would pick: {pvs.OpenDataFile(xdmf).GetXMLName()}")

        snaps = sorted(glob.glob(os.path.join(out, "snapshots", "snap_*.h5")))
        h5 = [read_h5(s) for s in snaps]
        if not check_xdmf_references(C, xdmf, {os.path.normpath(p): h for p, h in zip(snaps, h5)}):
            return C.summary()  # ParaView would abort on this file
        h5_times = [float(h["time"]) for h in h5]
        C.info(f"{len(snaps)} snapshot files, times {h5_times}")

        reader = open_reader(reader_name, xdmf)
        reader.UpdatePipelineInformation()
        tv = reader.TimestepValues
        times = [float(t) for t in (tv if isinstance(tv, (list, tuple)) or hasattr(tv, "__len__") else [tv])]
        C.info(f"reader TimestepValues {times}")
        same = len(times) == len(h5_times) and all(
            abs(a - b) <= 1e-9 * max(1.0, abs(b)) for a, b in zip(times, h5_times))
        C.check(same, "reader time steps equal the snapshot files' time attributes",
                f"{len(times)} reader times vs {len(h5_times)} snapshots")
        if not C.check(len(times) >= 2 and len(h5) >= 2, "at least two output times to compare"):
            return C.summary()

        first = check_snapshot(C, reader, times[0], h5[0], f"t={times[0]:g} (first)")
        last = check_snapshot(C, reader, times[-1], h5[-1], f"t={times[-1]:g} (last)")

        if first and last and all("id" in s and "kind" in s for s in (first, last)):
            # Match particles by id (the engine may reorder them between outputs).
            order0, order1 = np.argsort(first["id"]), np.argsort(last["id"])
            same_ids = np.array_equal(first["id"][order0], last["id"][order1])
            if C.check(same_ids, "same particle ids at first and last time"):
                fluid = first["kind"][order0] == FLUID
                disp = np.linalg.norm(last["pos"][order1] - first["pos"][order0], axis=1)
                moved = float(disp[fluid].max()) if fluid.any() else 0.0
                C.check(moved > 1e-6, "fluid particles moved between first and last time",
                        f"max fluid displacement {moved:.4g}, mean {float(disp[fluid].mean()):.4g}")
                C.info(f"max wall displacement {float(disp[~fluid].max()) if (~fluid).any() else 0.0:.3g}")

        msgs = log.GetOutput() or ""
        errors = [l for l in msgs.splitlines() if "ERR" in l.upper()]
        C.check(not errors, "reader reported no errors", "; ".join(errors)[:2000])
        if msgs.strip():
            C.info("VTK/ParaView messages:\n" + msgs.strip())
    except Exception:
        sys.__stderr__.write(traceback.format_exc())
        C.check(False, "test ran without exceptions")
    return C.summary()


if __name__ == "__main__":
    code = main(sys.argv[1:])
    sys.__stdout__.flush()
    sys.__stderr__.flush()
    # pvpython may swallow sys.exit(); os._exit forces the status through.
    os._exit(code)
