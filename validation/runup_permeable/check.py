#!/usr/bin/python3
"""Solitary-wave run-up on permeable beaches and porous layers: Tsurudome §5.4-5.5, §6.4 (issue 22, validation 6;
cases/runup_permeable_a.yaml, runup_layer_a.yaml, runup_permeable_b.yaml).

The porous bodies have porosity 0.49 and grain diameter Dc; Tsurudome's Ergun closure (eq 4.1.2, c1 = 150, c2 = 1.75)
and porous-particle field (eq 4.2.1), WCSPH with h = 2 dx (h/spacing 1.4 inside). There are no experiments for
permeable run-up (the thesis says so); the references are the thesis's own power-law fits of his ISPH runs
(eqs 5.4.1, 5.4.2, 6.4.1), and the run-up on the solid slope from the same flume, dx and h run here.
Parts (--parts, comma-separated; default all):
  a:      the 1:2.08 triangular beach (Flume A), H = 0.03423 m, Dc = 0.25, 1, 2, 10, 100 mm (§5.4; 2 mm for the layers);
          fit R = 73.157 Dc^-0.050 mm;
  layers: the 1:2.08 porous layer 0.13 m thick on an impermeable slope, Dc = 2 and 100 mm, against the beach, which
          is also the thesis's 0.433 m layer in the 3 m flume (§5.5);
  b:      the 1:20 triangular beach (Flume B), H = 0.0588 m (breaking), Dc = 0.25, 1, 2, 10, 100 mm (the thesis ran
          0.25, 1 and 10, §6.4; issue 40's decision 5 asks for the full series on both slopes); fit
          R = 41.824 Dc^-0.119 mm (extrapolated at 2 and 100 mm);
  a2:     the 1:2.08 beach with the larger wave, H = 0.0525 m (H/h0 = 0.25, the thesis's second wave), Dc = 1,
          100 mm; fit R = 131.46 Dc^-0.054 mm (eq 5.4.2);
  layers_b: the 1:20 porous layer 0.075 m thick on an impermeable slope (cases/runup_layer_b.yaml), Dc = 10 mm,
          against the beach (part b, the thesis's 0.40 m layer) (§6.5).
Metrics (dx = 0.01 m, twice the thesis's d0):
  1. every run reaches t_end, fluid mass conserved exactly;
  2. R within 10 % of the thesis's fit at each Dc (issue 22, validation 6); and R/R_solid within 10 % of the thesis's
     final law R = k3 R_s (Dc/H)^k2 (eqs 5.4.6, 6.4.3: k3 = 0.61, k2 = -0.052 on 1:2.08; 0.27, -0.120 on 1:20), with
     R_s the solid-slope run-up of the same model, dx and h, as the thesis defines it (his R_s overshoots Li &
     Raichlen by 7 %, so the fit in mm carries his solid-slope error);
  3. R falls with Dc (strictly; §5.4, §6.4), and every permeable R is below the solid slope's R (same dx and h);
  4. layers: at Dc = 2 mm the 0.13 m layer's R equals the beach's within 3 % (thickness does not matter for fine
     grains, §5.5); at Dc = 100 mm the beach's (the 0.433 m layer's) R is below the 0.13 m layer's (§5.5).
Information: at Dc = 0.25 mm the mean speed of the water inside the beach (more than 2h below the face) at the time of the
run-up (< 0.05 m/s: the beach acts as solid, §5.4.2); wall times.
Modes: fine = all parts; coarse = part a at Dc = 1 mm (CTest).
--refine L: every run of the call with a band of level L (dx/2^L) along the face that follows the waterline (the solid
slopes' on geometry 2, the porous cases' on porous region 0; issue 58: the 1:20 beach with 2.5 mm and 1.25 mm at its
face); runs go to OUT/PART/refineL_TAG.
Usage: /usr/bin/python3 validation/runup_permeable/check.py [--mode coarse|fine] [--parts a,layers,b] [--dcs 1,10] [--out DIR] [--reuse]
       [--refine L] [--set KEY=VALUE]
(--dcs: the grain diameters in mm for every part of the call, e.g. --parts b,layers_b --dcs 10 runs the 1:20 layer
against the beach's Dc = 10 mm run without the beach's other grains)
"""
import glob
import math
import os
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from common import Report, info, parse_sets, read_rows, run_case, save_figure, validation_args  # noqa: E402

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
CASES = os.path.normpath(os.path.join(HERE, "..", "..", "cases"))
NAME = "runup_permeable"
DX = 0.01
FIT_TOL, LAYER_TOL, LAYER_B_TOL, AT_REST = 0.10, 0.03, 0.05, 0.05
PARTS = {
    "a": {"case": "runup_permeable_a.yaml", "solid": "runup_flume_a.yaml", "end": 4.5, "H": 0.03423,
          "dcs": [0.25, 1.0, 2.0, 10.0, 100.0], "fit": (73.157, -0.050), "law": (0.61, -0.052),
          "toe": (2.07, 0.0), "gradient": 1 / 2.08},
    "layers": {"case": "runup_layer_a.yaml", "end": 4.5, "dcs": [2.0, 100.0]},
    "b": {"case": "runup_permeable_b.yaml", "solid": "runup_flume_b.yaml", "end": 11.0, "H": 0.0588,
          "dcs": [0.25, 1.0, 2.0, 10.0, 100.0], "fit": (41.824, -0.119), "law": (0.27, -0.120),
          "toe": (2.0, 0.0), "gradient": 1 / 20},
    "a2": {"case": "runup_permeable_a.yaml", "solid": "runup_flume_a.yaml", "end": 4.5, "H": 0.0525,
           "dcs": [1.0, 100.0], "fit": (131.46, -0.054), "law": (0.61, -0.052), "toe": (2.07, 0.0), "gradient": 1 / 2.08},
    "layers_b": {"case": "runup_layer_b.yaml", "end": 11.0, "dcs": [10.0], "beach": "b", "tol": LAYER_B_TOL},
}
# --refine L (issue 58, the permeable beaches refined at the face): a band normal to the face, REFINE_ABOVE into the
# water and (porous beaches) REFINE_BELOW into the beach, two level-0 supports at d0 (2h = 2 cm), whose elevations
# follow the waterline from 6 cm under it to 5 cm over it (the swash; docs/case-file.md, resolution), multirate
REFINE_ABOVE, REFINE_BELOW = 0.05, 0.02
REFINE = ("{{regions: [{{shape: band, {on}, above: " + str(REFINE_ABOVE) + ", z_min: 0.15, z_max: 0.40, "
          "follow: waterline, waterline_below: 0.06, waterline_above: 0.05, level: {level}}}], multirate: true}}")
MODES = {"coarse": {"parts": "a", "dcs": {"a": [1.0]}}, "fine": {"parts": "a,layers,b,layers_b,a2", "dcs": {}}}


def args():
    def extra(ap):
        ap.add_argument("--parts", default=None)
        ap.add_argument("--dcs", default=None, help="comma-separated grain diameters (mm) for every part of this call")
        ap.add_argument("--refine", type=int, default=0,
                        help="resolution level L of a band along the beach's face that follows the waterline (the "
                             "solid slope's and the porous beach's alike; dx/2^L there, multirate), issue 58")
    return validation_args(NAME, __doc__, MODES, extra=extra)


def runup(out):
    hdr, rows = read_rows(os.path.join(out, "gauges", "runup.csv"))
    t, r = rows[:, hdr.index("time")], rows[:, hdr.index("runup")]
    k = int(np.nanargmax(r))
    return float(r[k]), float(t[k]), t, r


def interior_speed(out, t_when, toe, gradient, h):
    """Mean |u| of the fluid in the beach more than 2h below its face, in the snapshot nearest t_when."""
    best, bt = None, 1e9
    for fn in glob.glob(os.path.join(out, "snapshots", "*.h5")):
        with h5py.File(fn, "r") as f:
            t = float(f.attrs["time"])
        if abs(t - t_when) < bt:
            best, bt = fn, abs(t - t_when)
    with h5py.File(best, "r") as f:
        k = f["kind"][:] == 0
        p = f["position"][:][k]
        v = f["velocity"][:][k]
    x, z = p[:, 0], p[:, -1]
    depth = ((x - toe[0]) * gradient - (z - toe[1])) / math.sqrt(1 + gradient ** 2)  # normal distance below the face
    inside = depth > 2 * h
    return float(np.mean(np.hypot(v[inside, 0], v[inside, -1]))) if np.any(inside) else float("nan")


def main():
    a = args()
    m = MODES[a.mode]
    parts = (a.parts or m["parts"]).split(",")
    rep = Report()
    res = {}

    def run(part, case, tag, sets_extra):
        out = os.path.join(a.out, part, tag if not a.refine else f"refine{a.refine}_{tag}")
        sets = {"particles.dx": DX, "time.end": PARTS[part]["end"], **sets_extra, **parse_sets(a.set)}
        if a.refine:
            on = "slope: 2, below: 0.01" if tag == "solid" else f"porous: 0, below: {REFINE_BELOW}"
            sets["resolution"] = REFINE.format(on=on, level=a.refine)
        s, wall, rc = run_case(a.sphflume, os.path.join(CASES, case), out, sets, a.threads, a.reuse)
        if s is None:
            print(f"[FAIL] {part} {tag}: run exit code = {rc}   (threshold: 0)")
            raise SystemExit(2)
        rep.metric(f"{part} {tag}: run reached t_end, fluid mass error", f"{s['simulated_time']:.3f} s, {s['mass']['relative_error']:.1e}",
                   s["simulated_time"] >= sets["time.end"] * (1 - 1e-6) and abs(s["mass"]["relative_error"]) <= 1e-12,
                   "t_end, |.| <= 1e-12", "closed flume")
        print(f"  {part} {tag}: wall {wall:.1f} s, {s['steps']} steps, {s['particles']['total']} particles, "
              f"{s['particle_steps_per_second']:.3g} particle-steps/s")
        return out, s

    def layer_runs(part, beach_part, dcs):
        """({Dc: R} of the beach run earlier in this call, {Dc: R} of the layer case at each Dc)."""
        if beach_part not in res:
            print(f"{part}: needs part {beach_part} (the beach) in the same call")
            raise SystemExit(2)
        beach = {dc: R for dc, R, _, _ in res[beach_part][1]}
        lay = {}
        for dc in dcs:
            out, _ = run(part, PARTS[part]["case"], f"dc{dc:g}", {"porous.regions.0.diameter": dc / 1000})
            lay[dc] = runup(out)[0]
        return beach, lay

    for part in parts:
        P = PARTS[part]
        dcs = [float(v) for v in a.dcs.split(",")] if a.dcs else m["dcs"].get(part, P["dcs"])
        if part in ("a", "b", "a2"):
            out, _ = run(part, P["solid"], "solid", {"particles.h_over_dx": 2.0, "motions.0.height": P["H"]})
            Rs = runup(out)[0]
            print(f"== {part}: solid slope R = {1000 * Rs:.1f} mm (dx = {parse_sets(a.set).get('particles.dx', DX)}, h = 2 dx)")
            rows = []
            for dc in dcs:
                out, _ = run(part, P["case"], f"dc{dc:g}", {"porous.regions.0.diameter": dc / 1000, "motions.0.height": P["H"]})
                R, tR, t, r = runup(out)
                fit = P["fit"][0] * dc ** P["fit"][1] / 1000
                rep.metric(f"{part} Dc = {dc:g} mm: R vs the thesis's fit", f"{1000 * R:.1f} vs {1000 * fit:.1f} mm ({100 * (R / fit - 1):+.1f} %)",
                           abs(R / fit - 1) <= FIT_TOL, "within 10 %", "issue 22, validation 6; eqs 5.4.1, 5.4.2, 6.4.1")
                rep.metric(f"{part} Dc = {dc:g} mm: R below the solid slope's", f"{1000 * R:.1f} < {1000 * Rs:.1f} mm", R < Rs,
                           "R < R_solid", "thesis §5.4, §6.4")
                law = P["law"][0] * (dc / 1000 / P["H"]) ** P["law"][1]
                rep.metric(f"{part} Dc = {dc:g} mm: R/R_solid vs the thesis's law k3 (Dc/H)^k2", f"{R / Rs:.3f} vs {law:.3f} ({100 * (R / Rs / law - 1):+.1f} %)",
                           abs(R / Rs / law - 1) <= FIT_TOL, "within 10 %",
                           "eq 5.4.6 / 6.4.3 with R_s the solid-slope run-up of the same model (as the thesis defines it)")
                if dc == 0.25:
                    h = 2 * float(parse_sets(a.set).get("particles.dx", DX))
                    us = interior_speed(out, tR, P["toe"], P["gradient"], h)
                    info(f"{part} Dc = 0.25 mm: mean |u| inside the beach (> 2h below the face) at the run-up", f"{us:.4f} m/s",
                         us < AT_REST, "< 0.05 m/s", "thesis §5.4.2: the beach acts as solid")
                rows.append((dc, R, t, r))
            Rv = [v[1] for v in rows]
            if len(Rv) > 1:
                rep.metric(f"{part}: R falls with Dc", ", ".join(f"{1000 * v:.1f}" for v in Rv) + " mm",
                           all(x > y for x, y in zip(Rv, Rv[1:])), "strictly decreasing", "thesis §5.4, §6.4")
            res[part] = (Rs, rows)
        elif part == "layers_b":
            beach, lay = layer_runs(part, P["beach"], dcs)
            for dc in dcs:
                if dc in beach:
                    q = lay[dc] / beach[dc] - 1
                    rep.metric(f"layers_b Dc = {dc:g} mm: R(0.075 m layer) vs R(1:20 beach = 0.40 m layer)",
                               f"{1000 * lay[dc]:.1f} vs {1000 * beach[dc]:.1f} mm ({100 * q:+.1f} %)", abs(q) <= P["tol"],
                               "within 5 %", "thesis §6.5: breaking, no thickness effect")
            res[part] = lay
        else:
            beach, lay = layer_runs(part, "a", dcs)
            if 2.0 in lay and 2.0 in beach:
                q = lay[2.0] / beach[2.0] - 1
                rep.metric("layers Dc = 2 mm: R(0.13 m layer) vs R(beach = 0.433 m layer)", f"{1000 * lay[2.0]:.1f} vs {1000 * beach[2.0]:.1f} mm ({100 * q:+.1f} %)",
                           abs(q) <= LAYER_TOL, "within 3 %", "thesis §5.5: no thickness effect below 30 mm")
            if 100.0 in lay and 100.0 in beach:
                rep.metric("layers Dc = 100 mm: R(beach = 0.433 m layer) < R(0.13 m layer)", f"{1000 * beach[100.0]:.1f} < {1000 * lay[100.0]:.1f} mm",
                           beach[100.0] < lay[100.0], "lower", "thesis §5.5: the thick layer lowers R for Dc >= 40 mm")
            res[part] = lay

    fig, ax = plt.subplots(1, 2, figsize=(11, 4))
    names = {"a": "1:2.08", "b": "1:20", "a2": "1:2.08, H = 0.0525 m"}
    for part, mk in (("a", "o"), ("b", "s"), ("a2", "D")):
        if part not in res:
            continue
        Rs, rows = res[part]
        P = PARTS[part]
        dd = np.logspace(np.log10(0.2), np.log10(200), 50)
        ax[0].semilogx(dd, P["fit"][0] * dd ** P["fit"][1], {"a": "k-", "b": "k--", "a2": "k-."}[part],
                       label=f"thesis fit, {names[part]}")
        ax[0].semilogx([v[0] for v in rows], [1000 * v[1] for v in rows], mk, label=f"SPHFlume, {names[part]}")
        ax[0].axhline(1000 * Rs, color={"a": "C0", "b": "C1", "a2": "C2"}[part], ls=":", lw=0.8)
        for dc, R, t, r in rows:
            ax[1].plot(t, 1000 * r, label=f"{part}, Dc = {dc:g} mm", lw=0.8)
    if "layers" in res:
        ax[0].semilogx(list(res["layers"]), [1000 * v for v in res["layers"].values()], "^", label="SPHFlume, 0.13 m layer (1:2.08)")
    if "layers_b" in res:
        ax[0].semilogx(list(res["layers_b"]), [1000 * v for v in res["layers_b"].values()], "v", label="SPHFlume, 0.075 m layer (1:20)")
    ax[0].set_xlabel("Dc [mm]")
    ax[0].set_ylabel("R [mm]")
    ax[0].set_title("run-up on permeable slopes (dotted: solid slope, same dx)")
    ax[0].legend(fontsize=7)
    ax[1].set_xlabel("t [s]")
    ax[1].set_ylabel("waterline above SWL [mm]")
    ax[1].legend(fontsize=6)
    fig.tight_layout()
    save_figure(fig, HERE, NAME, a.mode, a.out)
    rep.finish(NAME, a.mode)
    return 0


if __name__ == "__main__":
    sys.exit(main())
