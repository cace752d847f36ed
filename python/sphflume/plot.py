"""Pictures of a run without ParaView: a snapshot (fluid coloured by a field, walls grey, the time in the
title), a gauge (every column against time) and an animation of the snapshots (MP4 through ffmpeg when it is
installed, GIF otherwise)."""
import os

import numpy as np

UNITS = {"pressure": "Pa", "density": "kg/m³", "speed": "m/s", "velocity_x": "m/s", "velocity_z": "m/s",
         "nu_t": "m²/s", "mass": "kg"}


def _mpl():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def field_values(snap, field):
    """A per-particle scalar of a snapshot: a dataset name, or speed / velocity_x / velocity_y / velocity_z."""
    v = snap["velocity"]
    derived = {"speed": lambda: np.linalg.norm(v, axis=1), "velocity_x": lambda: v[:, 0],
               "velocity_y": lambda: v[:, 1], "velocity_z": lambda: v[:, 2]}
    if field in derived:
        return derived[field]()
    if field not in snap or np.ndim(snap[field]) != 1:
        names = sorted(k for k, a in snap.items() if np.ndim(a) == 1 and k not in ("kind", "id"))
        raise KeyError(f"no per-particle field '{field}' (this snapshot has: {', '.join(names + sorted(derived))})")
    return snap[field]


def _draw(ax, run, snap, field, vmin=None, vmax=None):
    x, z = snap["position"][:, 0], snap["position"][:, 2]
    fluid = snap["kind"] != 1
    dx = run.summary.get("dx", None)
    width = float(np.ptp(x)) or 1.0
    # marker area in points²: about one particle spacing on a 7-inch-wide axis
    size = max(0.5, (0.6 * 72 * 7 * dx / width) ** 2) if dx else 4.0
    ax.scatter(x[~fluid], z[~fluid], s=size, c="0.6", marker="s", linewidths=0, label="walls")
    c = field_values(snap, field)[fluid]
    sc = ax.scatter(x[fluid], z[fluid], s=size, c=c, cmap="viridis", vmin=vmin, vmax=vmax, linewidths=0)
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("z (m)")
    name = run.summary.get("case", os.path.basename(run.folder))
    ax.set_title(f"{name}: {field}, t = {snap['time']:.3f} s")
    return sc


def _save(plt, fig, out):
    """Writes the figure as the PNG `out` (its folder made if needed), closes it, returns the path."""
    fig.tight_layout()
    os.makedirs(os.path.dirname(os.path.abspath(out)), exist_ok=True)
    fig.savefig(out, dpi=120)
    plt.close(fig)
    return out


def plot_snapshot(run, index=-1, field="pressure", out=None, time=None):
    """Draws one snapshot (by index, or the one nearest `time`) into the PNG `out`; returns its path.
    3D runs are drawn as their x-z projection."""
    plt = _mpl()
    snap = run.snapshot(index=index if time is None else None, time=time)
    fig, ax = plt.subplots(figsize=(8, 5))
    sc = _draw(ax, run, snap, field)
    unit = UNITS.get(field, "")
    fig.colorbar(sc, ax=ax, label=f"{field} ({unit})" if unit else field)
    return _save(plt, fig, out or os.path.join(run.folder, "plots", f"snapshot_{snap['step']:08d}_{field}.png"))


def plot_gauge(run, name, out=None):
    """Every column of gauges/NAME.csv against time, one panel each, into the PNG `out`; returns its path."""
    plt = _mpl()
    g = run.gauge(name)
    cols = [c for c in g if c != "time"]
    fig, axes = plt.subplots(len(cols), 1, figsize=(8, 1.8 + 1.6 * len(cols)), sharex=True, squeeze=False)
    for ax, c in zip(axes[:, 0], cols):
        ax.plot(g["time"], g[c], lw=1.2)
        ax.set_ylabel(c)
        ax.grid(alpha=0.3)
    axes[-1, 0].set_xlabel("t (s)")
    axes[0, 0].set_title(f"{run.summary.get('case', '')}: gauge {name}")
    return _save(plt, fig, out or os.path.join(run.folder, "plots", f"gauge_{name}.png"))


def animate(run, field="pressure", out=None, fps=10):
    """Every snapshot as one frame, the colour scale fixed over the run: MP4 (ffmpeg) or GIF; returns the path."""
    plt = _mpl()
    from matplotlib import animation
    vals = [field_values(run.snapshot(i), field)[run.snapshot(i)["kind"] != 1] for i in range(len(run))]
    vmin = min(float(np.min(v)) for v in vals if len(v))
    vmax = max(float(np.max(v)) for v in vals if len(v))
    fig, ax = plt.subplots(figsize=(8, 5))

    def frame(i):
        ax.clear()
        return [_draw(ax, run, run.snapshot(i), field, vmin, vmax)]

    sc = frame(0)[0]
    fig.colorbar(sc, ax=ax, label=field)
    mp4 = animation.writers.is_available("ffmpeg")
    out = out or os.path.join(run.folder, "plots", f"{field}.{'mp4' if mp4 else 'gif'}")
    os.makedirs(os.path.dirname(os.path.abspath(out)), exist_ok=True)
    anim = animation.FuncAnimation(fig, frame, frames=len(run), blit=False)
    writer = animation.FFMpegWriter(fps=fps) if out.endswith(".mp4") else animation.PillowWriter(fps=fps)
    anim.save(out, writer=writer, dpi=100)
    plt.close(fig)
    return out
