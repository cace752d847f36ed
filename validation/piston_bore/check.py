#!/usr/bin/python3
"""Piston paddle pushing into still water (issue 21 "moving walls", issue 22's paddle; cases/piston_bore.yaml).

A flume 3 m long holds h0 = 0.2 m of water; the paddle (a wall box 0.04 m thick at the left end, `motion: paddle`)
follows cases/piston_bore_paddle.csv: speed U (1 - cos(pi t/0.2))/2 up to 0.2 s, then U = 0.15 m/s. A compression
wave runs ahead of it (steepening into an undular bore); behind it the water stands at the simple-wave level
    sqrt(g (h0 + eta)) = sqrt(g h0) + U/2  ->  eta = (sqrt(g h0) + U/2)^2/g - h0 = 21.99 mm
(the Riemann invariant carried from still water; the weak-bore jump conditions U = eta W/(h0 + eta),
W^2 = g (h0 + eta)(2 h0 + eta)/(2 h0) give the same within 0.2 %). The water ahead of the paddle moves with it at U
under a hydrostatic pressure, so the paddle's x-force per metre width is -rho g (h0 + eta)^2/2 = -241.7 N (negative:
the water pushes the paddle back); at rest (t = 0) it is -rho g h0^2/2 = -196.2 N.

Metrics, for each scheme run (--scheme):
  a. the run reaches t_end (exit 0);
  b. plateau level rise: at each level gauge (x = 0.6, 0.9, 1.2 m) the mean of level - level(t = 0) over the output
     rows with t >= 0.2 + x/(sqrt(g h0) + 0.75 U) + 0.3 s (the ramp, the travel of the half-rise at the speed of
     its characteristic, u + c = sqrt(g h0) + 0.75 U, and 0.3 s for the front to pass) up to t_end; the mean of
     the three against eta: within 5 %. The front is an undular bore: its first undulation (crest ~+6.7 mm and
     trough ~-5.2 mm about eta, period ~0.5 s at dx = 0.01) is still in every window (0.70, 0.51, 0.31 s long,
     each opening near the first crest), so a single gauge's window mean is biased by a few % of eta (measured
     -6.4 ... +6.9 %; up to ~15 % in the worst phase for the 0.31 s window at 1.2 m); the mean over the three
     gauges, whose windows end at different phases, by less (2026-11-25: -2.8 % WCSPH and -3.5 % ISPH at
     dx = 0.01, +1.9 % WCSPH at dx = 0.005); plus the level
     gauge's resolution (fluid fraction 0.5 on a dx/4 scan); subtracting each gauge's t = 0 level cancels its
     lattice offset. Each gauge's value is printed (information). The far wall's reflection reaches no gauge
     before t_end (the front arrives at x = 3 m at about 2.2 s);
  c. paddle force_x, mean of the output rows with 0.8 < t < 1.55 s, against -rho g (h0 + eta)^2/2: within 5 %.
     The face pressure is interpolated by the pressure gauge's linear MLS one surface point per wall particle, and
     the first fluid column sits against a paddle that pushes it; the still-water thrust reads exactly at t = 0
     (metric d), so the 5 % covers the moving state. The window ends before the table's last sample (t = 1.6 s),
     where the paddle is brought to rest within 5 ms (the table law holds the last sample);
  d. paddle force_x at t = 0 within 1 % of -rho g h0^2/2 (the set-up's hydrostatic state, both schemes);
  e. no fluid particle behind the paddle face in any snapshot: the face lies at (max x of the paddle's wall
     particles) + dx/2, and a fluid centre must stay more than dx/2 in front of it: every fluid x > max paddle
     particle x (the minimum gap is printed, in dx);
  f. the paddle's displacement (gauge `paddle`) against the table, linearly interpolated at the gauge times:
     max |difference| <= 1e-6 m. The output times (every 0.02 s) fall on the table's samples (every 0.005 s), where
     the C1 Hermite curve passes through the sample values, so the motion layer following its law reads the
     table to its 8 printed decimals;
  g. closed flume: fluid particles final == initial, 0 removed, fluid mass (summary.json) balance |.| <= 1e-12.
Information: each gauge's plateau rise and its standard deviation, the arrival of the half rise at each gauge
against 0.1 + (x - X(0.1))/(sqrt(g h0) + 0.75 U) (the characteristic leaving the paddle at half speed), the bed
pressure p_120 over its plateau window against rho g (h0 + eta), the density of the first fluid column at the
paddle (x < max paddle particle x + 1.5 dx) over 0.8 < t < 1.55 s against the bulk's, wall time and steps.
ISPH runs its default formulation (lind, docs/numerics.md §13b): level +3.9 % and force −0.1 % at dx = 0.005; at
dx = 0.01 the 1.2 m gauge's short window opens on the undular bore's first crest (+5.6 %). Tsurudome's formulation
(--set scheme.formulation=tsurudome) compresses the first fluid column against the accelerating paddle (rho ~ 1034
against 1000 in the bulk) and reads the force +6.7 % high at dx = 0.01 (README). Only the default --scheme wcsph is in
CTest.

Options besides the common ones: --scheme wcsph|isph|both (default wcsph): which scheme(s) to run; each run goes to
--out/<scheme>_dx<dx>/ (ISPH: --set scheme.type=isph; other --set keys go to every run). Exit 1 when a metric fails,
2 when a run fails (the other scheme's run is still analysed).
Usage: /usr/bin/python3 validation/piston_bore/check.py [--mode coarse|fine] [--scheme wcsph|isph|both]
       [--sphflume PATH] [--out DIR] [--reuse]
"""
import glob
import math
import os
import sys

import h5py
import numpy as np
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from common import Report, band, fmt_band, parse_sets, read_rows, run_case, save_figure, validation_args  # noqa: E402

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
CASES = os.path.normpath(os.path.join(HERE, "..", "..", "cases"))
CASE = os.path.join(CASES, "piston_bore.yaml")
TABLE = os.path.join(CASES, "piston_bore_paddle.csv")  # the case's `motions: [{law: table, file: ...}]`
NAME = "piston_bore"
MODES = {
    # only resolution and end time differ between the modes
    "coarse": {"dx": 0.01, "end": 1.6},
    "fine": {"dx": 0.005, "end": 1.6},
}
SCHEMES = ("wcsph", "isph")

RHO, G, H0, U, T_RAMP = 1000.0, 9.81, 0.2, 0.15, 0.2
C0 = math.sqrt(G * H0)
ETA = (C0 + U / 2) ** 2 / G - H0                  # simple-wave level: 21.99 mm
F_REST = -RHO * G * H0 ** 2 / 2                   # -196.2 N/m
F_PLATEAU = -RHO * G * (H0 + ETA) ** 2 / 2        # -241.7 N/m
HALF_SPEED = C0 + 0.75 * U                        # u + c of the characteristic carrying u = U/2
GAUGES = {"level_060": 0.6, "level_090": 0.9, "level_120": 1.2}
PRESSURE_GAUGE, PRESSURE_X = "p_120", 1.2
FRONT_PASS = 0.3                                  # s after the half rise before the plateau window opens
FORCE_WINDOW = (0.8, 1.55)
LEVEL_TOL, FORCE_TOL, REST_TOL, DISP_TOL, MASS_TOL = 0.05, 0.05, 0.01, 1e-6, 1e-12


def pop_scheme(argv):
    """--scheme wcsph|isph|both, taken out of argv before the common options are parsed (default wcsph)."""
    val = "wcsph"
    for i, a in enumerate(argv):
        if a == "--scheme" and i + 1 < len(argv):
            val = argv[i + 1]
            del argv[i:i + 2]
            break
        if a.startswith("--scheme="):
            val = a.split("=", 1)[1]
            del argv[i]
            break
    if val not in SCHEMES + ("both",):
        print(f"--scheme {val}: expected wcsph, isph or both", file=sys.stderr)
        raise SystemExit(2)
    return list(SCHEMES) if val == "both" else [val]


def bore_eta():
    """eta of the weak bore (jump conditions) driven by a piston at U: U = eta W/(h0 + eta), bisection."""
    lo, hi = 1e-6, H0
    for _ in range(200):
        e = 0.5 * (lo + hi)
        w = math.sqrt(G * (H0 + e) * (2 * H0 + e) / (2 * H0))
        lo, hi = (e, hi) if e * w / (H0 + e) < U else (lo, e)
    return 0.5 * (lo + hi)


def paddle_x(t):
    """The law the table samples: X(t) = U/2 (t - (T/pi) sin(pi t/T)) during the ramp."""
    return U / 2 * (t - T_RAMP / math.pi * math.sin(math.pi * t / T_RAMP)) if t < T_RAMP else U * (t - T_RAMP / 2)


def gauge(out, name):
    hdr, rows = read_rows(os.path.join(out, "gauges", f"{name}.csv"))
    return {h: rows[:, k] for k, h in enumerate(hdr)}


def window_start(x):
    return T_RAMP + x / HALF_SPEED + FRONT_PASS


def snapshot_checks(out, dx):
    """Per snapshot: (time, fluid x min - max paddle particle x, first-column density mean / max, bulk density)."""
    res = []
    for fn in sorted(glob.glob(os.path.join(out, "snapshots", "*.h5"))):
        with h5py.File(fn, "r") as f:
            t = float(f.attrs["time"])
            kind = f["kind"][:]
            x = f["position"][:][:, 0]
            paddle = (kind == 1) & (f["motion_group"][:] > 0)
            fl = kind == 0
            rho = f["density"][:]
        px = float(np.max(x[paddle]))
        col = fl & (x < px + 1.5 * dx)
        bulk = fl & (x > px + 10 * dx) & (x < px + 30 * dx)
        res.append((t, float(np.min(x[fl])) - px, float(np.mean(rho[col])), float(np.max(rho[col])),
                    float(np.mean(rho[bulk]))))
    return np.array(res)


def analyse(scheme, out, s, wall, m, rep):
    """The metrics of one scheme's run; returns what the figure draws."""
    tag = scheme.upper()
    rep.metric(f"{tag} run reached t_end (s)", f"{s['simulated_time']:.4f}", s["simulated_time"] >= m["end"] * (1 - 1e-6),
               f">= {m['end']}", "the case")

    # b. plateau level rise
    levels, rises = {}, []
    for name, x in GAUGES.items():
        g = gauge(out, name)
        t, rise = g["time"], g["level"] - g["level"][0]
        levels[name] = (t, rise)
        win = (t >= window_start(x) - 1e-9) & (t <= m["end"] + 1e-9)
        r = float(np.mean(rise[win]))
        rises.append(r)
        k = np.nonzero(rise >= ETA / 2)[0]
        if len(k) and k[0] > 0:
            j = k[0]
            t_half = t[j - 1] + (ETA / 2 - rise[j - 1]) / (rise[j] - rise[j - 1]) * (t[j] - t[j - 1])
        else:
            t_half = float("nan")
        t_th = 0.1 + (x - paddle_x(0.1)) / HALF_SPEED
        print(f"  (info) {name} (x = {x} m): level(0) = {g['level'][0]:.5f} m; plateau t in [{window_start(x):.3f}, "
              f"{m['end']}] s ({int(win.sum())} rows): rise {1000 * r:.2f} mm ({100 * (r / ETA - 1):+.1f} % of eta), "
              f"sd {1000 * float(np.std(rise[win])):.2f} mm; half rise at t = {t_half:.3f} s (characteristic {t_th:.3f} s)")
    mean_rise = float(np.mean(rises))
    err = mean_rise / ETA - 1
    rep.metric(f"{tag} plateau level rise, mean of the three gauges, vs eta = {1000 * ETA:.2f} mm",
               f"{1000 * mean_rise:.2f} mm ({100 * err:+.2f} %)", abs(err) <= LEVEL_TOL, f"within {100 * LEVEL_TOL:g} %",
               "simple wave (Riemann invariant); undular-bore window bias + gauge resolution")
    p = gauge(out, PRESSURE_GAUGE)
    win = p["time"] >= window_start(PRESSURE_X) - 1e-9
    p_pl = band(p["pressure"][win])
    p_th = RHO * G * (H0 + ETA)
    print(f"  (info) {PRESSURE_GAUGE}: {p['pressure'][0]:.1f} Pa at t = 0 (rho g h0 = {RHO * G * H0:.1f}); plateau mean "
          f"{p_pl['mean']:.1f} Pa against rho g (h0 + eta) = {p_th:.1f} Pa ({fmt_band(p_pl, p_th)})")

    # c, d. paddle force
    pg = gauge(out, "paddle")
    tp, fx = pg["time"], pg["force_x"]
    fw = (tp > FORCE_WINDOW[0]) & (tp < FORCE_WINDOW[1])
    fb = band(fx[fw])
    f_mean = fb["mean"]
    err_f = f_mean / F_PLATEAU - 1
    print(f"  (info) paddle force_x over {FORCE_WINDOW[0]} < t < {FORCE_WINDOW[1]} s: {int(fw.sum())} rows, sd {fb['sd']:.1f} N, "
          f"se {fb['se']:.1f} N, min {float(np.min(fx[fw])):.1f}, max {float(np.max(fx[fw])):.1f} N; vs {F_PLATEAU:.1f} N: "
          f"{fmt_band(fb, F_PLATEAU)}")
    rep.metric(f"{tag} paddle force_x, mean over {FORCE_WINDOW[0]} < t < {FORCE_WINDOW[1]} s, vs -rho g (h0+eta)^2/2 = "
               f"{F_PLATEAU:.1f} N", f"{f_mean:.1f} N ({100 * err_f:+.2f} %)",
               abs(err_f) <= FORCE_TOL, f"within {100 * FORCE_TOL:g} %", "hydrostatic thrust of the plateau; MLS face pressure")
    i0 = int(np.argmin(np.abs(tp)))
    err_0 = fx[i0] / F_REST - 1
    rep.metric(f"{tag} paddle force_x at t = {tp[i0]:g} s vs -rho g h0^2/2 = {F_REST:.1f} N", f"{fx[i0]:.2f} N ({100 * err_0:+.3f} %)",
               abs(tp[i0]) < 1e-12 and abs(err_0) <= REST_TOL, f"within {100 * REST_TOL:g} %", "hydrostatic set-up")
    print(f"  (info) paddle force_x in the last row (t = {tp[-1]:.3f} s, the paddle brought to rest at the table's end, "
          f"acceleration {pg['acceleration'][-1]:.1f} m/s^2): {fx[-1]:.1f} N")

    # e. nothing behind the paddle; first-column density (information)
    snap = snapshot_checks(out, m["dx"])
    k = int(np.argmin(snap[:, 1]))
    rep.metric(f"{tag} fluid behind the paddle: min over {len(snap)} snapshots of (fluid x min - paddle particle x max)",
               f"{snap[k, 1] / m['dx']:.3f} dx at t = {snap[k, 0]:.2f} s", len(snap) > 0 and bool(np.all(snap[:, 1] > 0)),
               "> 0 (every fluid centre more than dx/2 in front of the face)", "moving wall impermeable")
    sw = (snap[:, 0] > FORCE_WINDOW[0]) & (snap[:, 0] < FORCE_WINDOW[1])
    col_rho, col_max, bulk_rho = (float(np.mean(snap[sw, j])) for j in (2, 3, 4))
    print(f"  (info) density of the first fluid column at the paddle over {FORCE_WINDOW[0]} < t < {FORCE_WINDOW[1]} s "
          f"({int(sw.sum())} snapshots): mean {col_rho:.1f} (its particles' max {float(np.max(snap[sw, 3])):.1f}), bulk "
          f"{bulk_rho:.1f} kg/m^3; at t = 0: {snap[0, 2]:.1f}")

    # f. the motion follows the table
    _, tab = read_rows(TABLE)
    d_tab = np.interp(tp, tab[:, 0], tab[:, 1])
    d_err = float(np.max(np.abs(pg["displacement"] - d_tab)))
    rep.metric(f"{tag} paddle displacement vs the table at the {len(tp)} gauge times, max |diff|", f"{d_err:.2e} m",
               d_err <= DISP_TOL, f"<= {DISP_TOL:g} m", "the table law passes through its samples")

    # g. closed flume
    P = s["particles"]
    rep.metric(f"{tag} fluid particles final / initial, removed", f"{P['fluid']} / {P['initial_fluid']}, {s['mass']['removed']}",
               P["fluid"] == P["initial_fluid"] and s["mass"]["removed"] == 0, "equal, 0", "closed flume")
    rep.metric(f"{tag} fluid mass (initial - removed - final) / initial", f"{s['mass']['relative_error']:.1e}",
               abs(s["mass"]["relative_error"]) <= MASS_TOL, f"|.| <= {MASS_TOL:g} (round-off)", "closed flume")
    ps = s.get("pressure_solver")
    extra = (f"; PPE {ps['solves']} solves, {ps['mean_iterations']} iterations on average (max {ps['max_iterations']})"
             if ps else "")
    print(f"  (info) {scheme}: {s['steps']} steps, last dt {s['last_dt']:.3g} s, {wall:.1f} s wall{extra}")
    return {"levels": levels, "rises": rises, "mean_rise": mean_rise, "force": (tp, fx), "f_mean": f_mean,
            "f_band": (tp[fw], fb), "col_rho": col_rho}


def main():
    schemes = pop_scheme(sys.argv)
    a = validation_args(NAME, __doc__, MODES)
    m = MODES[a.mode]
    os.makedirs(a.out, exist_ok=True)
    base = {"particles.dx": m["dx"], "time.end": m["end"], **parse_sets(a.set)}
    runs = {}
    for scheme in schemes:
        out = os.path.join(a.out, f"{scheme}_dx{m['dx']:g}")
        runs[scheme] = (out, *run_case(a.sphflume, CASE, out, {**base, "scheme.type": scheme}, a.threads, a.reuse))
    rep = Report()
    print(f"\n== {NAME} ({a.mode}: dx = {m['dx']} m, t_end = {m['end']} s; schemes {', '.join(schemes)})")
    print(f"  theory: eta = {1000 * ETA:.2f} mm (simple wave; weak bore {1000 * bore_eta():.2f} mm), force at rest "
          f"{F_REST:.1f} N, on the plateau {F_PLATEAU:.1f} N per metre")
    res, failed_runs = {}, []
    for scheme, (out, s, wall, rc) in runs.items():
        print(f"\n-- {scheme} (run wall time {wall:.1f} s)")
        if s is None:
            print(f"[FAIL] {scheme.upper()} run exit code = {rc}   (threshold: 0)")
            failed_runs.append(scheme)
            continue
        res[scheme] = analyse(scheme, out, s, wall, m, rep)

    if res:
        fig, ax = plt.subplots(1, 2, figsize=(14, 5))
        styles = {"wcsph": "-", "isph": "--"}
        for scheme, r in res.items():
            for j, (name, (t, rise)) in enumerate(r["levels"].items()):
                ax[0].plot(t, 1000 * rise, styles[scheme], color=f"C{j}", lw=1,
                           label=f"{scheme} x = {GAUGES[name]} m (plateau {1000 * r['rises'][j]:.2f} mm)")
        for j, x in enumerate(GAUGES.values()):
            ax[0].axvline(window_start(x), color=f"C{j}", ls=":", lw=0.8)
        ax[0].axhline(1000 * ETA, color="k", lw=1, label=f"simple wave eta = {1000 * ETA:.2f} mm")
        ax[0].axhspan(1000 * ETA * (1 - LEVEL_TOL), 1000 * ETA * (1 + LEVEL_TOL), color="g", alpha=0.12,
                      label=f"±{100 * LEVEL_TOL:g} %")
        ax[0].set_xlabel("t (s)")
        ax[0].set_ylabel("level - level(t = 0) (mm)")
        ax[0].set_title(f"level rise at the gauges, dx = {m['dx']} m (dotted: plateau windows open)")
        ax[0].legend(fontsize=7, loc="lower right")
        shown = []
        for scheme, r in res.items():
            tp, fx = r["force"]
            ax[1].plot(tp, fx, styles[scheme], lw=1, label=f"{scheme} (window mean {r['f_mean']:.1f} N)")
            tw, fb = r["f_band"]
            ax[1].fill_between(tw, fb["mean"] - fb["sd"], fb["mean"] + fb["sd"], alpha=0.4, zorder=1.5,
                               label=f"{scheme} window mean ± sd ({fb['sd']:.1f} N)")
            shown.append(fx[tp < FORCE_WINDOW[1] + 0.03])
        ax[1].axhline(F_REST, color="0.4", lw=1, label=f"at rest -rho g h0^2/2 = {F_REST:.1f} N")
        ax[1].axhline(F_PLATEAU, color="k", lw=1, label=f"plateau -rho g (h0+eta)^2/2 = {F_PLATEAU:.1f} N")
        ax[1].axvspan(*FORCE_WINDOW, color="0.9", label="averaging window")
        allf = np.concatenate(shown + [np.array([F_REST, F_PLATEAU])])
        pad = 0.1 * (allf.max() - allf.min())
        ax[1].set_ylim(allf.min() - pad, allf.max() + pad)
        ax[1].set_xlabel("t (s)")
        ax[1].set_ylabel("paddle force_x (N per m)")
        ax[1].set_title("paddle thrust (the last row, paddle stopping at t = 1.6 s, is off scale)", fontsize=9)
        ax[1].legend(fontsize=7, loc="upper right")
        fig.tight_layout()
        save_figure(fig, HERE, NAME, a.mode, a.out)

    if failed_runs:
        print(f"\n{NAME} {a.mode}: RUN FAILED: {', '.join(failed_runs)}"
              + (f"; metrics failed: {', '.join(rep.failed)}" if rep.failed else ""))
        return 2
    if rep.failed:
        print(f"\n{NAME} {a.mode}: FAILED: {', '.join(rep.failed)}")
        return 1
    print(f"\n{NAME} {a.mode}: all metrics pass")
    return 0


if __name__ == "__main__":
    sys.exit(main())
