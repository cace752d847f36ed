"""Kazemi's rough-bed flows (thesis §3.2, Table 3-1) and the case file of each.

Bed of spheres d_s = 24 mm; bulk velocity U = Fr sqrt(g H) (Table 3-1's Fr; Re = U H / nu reproduces the table).
R_d / H: the thesis's calibrated value of each flow, Table 3-2 (issue 20, decision 2; the default since
2026-11-24). The power law fitted to the calibration ("C") cases, R_d / H = 0.0054 H^-1.224 (H in m; the form
of the thesis's Fig. 3-5, which prints no coefficients; least squares on Table 3-2, max error 4.6 %), which the
runs used before, stays selectable: rd_source="law" (check.py --set rd=law).
Measured U two ways: Fr sqrt(g H) for every flow (Table 3-1), and Q / (B H) where the thesis gives the discharge Q
(S004H50 only: Q = 0.00825 m3/s, flume width B = 0.459 m, thesis §3.2.2); the two disagree by 19 % for S004H50.

Depths: H (Table 3-1) is read as the flow depth above the roughness crest, so the simulated fluid runs from the
numerical bed (z = 0, the zero-velocity plane) to z = H + R_d and the crest is at z = R_d. The thesis does not say
which it is; this reading is the one under which his model gives his stated discharge for S004H50 (q = 0.0174
against the measured 0.0180 m2/s, Table 3-2's R_d; with the fluid depth H it gives 0.0122: model_1d.py), and
under which his figures draw the numerical bed and the crest as separate levels. The measured U is compared with
the simulated velocity averaged over the depth H above the crest (what PIV above the spheres can measure).

Numerical settings (stated, not the thesis's): dx ~ H / 20 (the thesis: 2 mm for all, H / dx = 20-50), Wendland C2
with h = 1.5 dx (support 3 dx; the thesis: cubic spline, h = 1.2 dx; h = 2 dx before 2026-11-25, whose smoothing
over the drag layer and the surface set most of the SPH's error, README.md), c0 = 10 x 1.6 U (>= 10 |u|max; the thesis
16 m/s), Verlet integrator, delta-SPH (Fourtakas), Adami dummy bed (the thesis: dynamic dummies), domain L = 4 H
between the inflow and outflow zones (as the thesis), start from U0 = 0.2 m/s everywhere (the thesis tried
0.05-0.7 m/s; check.py starts the periodic runs from the 1D model's bulk velocity).
Lattice (dx_of): dx = (H + R_d) / N with N = round(n (H + R_d) / H) for the requested H / dx = n, so that the fluid
lattice's N rows fill the depth H + R_d exactly (H / dx then lies within 2.5 % of n), and the channel length is
the whole number of dx nearest 4 H (a periodic channel needs one). Before 2026-11-24 dx was H / n exactly and the
lattice held floor((H + R_d) / dx) rows: the fluid was up to 0.9 dx short of H + R_d (4.4 mm, 4.4 % of H, for
S004H100), which the 1D model (run at H + R_d) did not know. The bed's plane is filled from -8 dx (before: from
-0.05 m, so for 8 of the 12 flows, where 0.05 / dx is not whole, the top wall row sat 0.1-0.7 dx too low and the
fluid settled into the gap: up to 1.4 mm, S002H60).
"""
import math

G = 9.81
NU = 1.0e-6
DS = 0.024
# No, ID, S0, H [m], Fr, calibration (C) or validation (V)
TABLE = [
    (1, "S004H40", 0.004, 0.040, 0.433, "C"),
    (2, "S004H50", 0.004, 0.050, 0.430, "V"),
    (3, "S004H70", 0.004, 0.070, 0.564, "V"),
    (4, "S004H90", 0.004, 0.090, 0.559, "V"),
    (5, "S004H100", 0.004, 0.100, 0.603, "C"),
    (6, "S003H50", 0.003, 0.050, 0.332, "C"),
    (7, "S003H60", 0.003, 0.060, 0.424, "V"),
    (8, "S003H70", 0.003, 0.070, 0.481, "C"),
    (9, "S003H80", 0.003, 0.080, 0.453, "V"),
    (10, "S002H60", 0.002, 0.060, 0.261, "C"),
    (11, "S002H70", 0.002, 0.070, 0.339, "V"),
    (12, "S002H80", 0.002, 0.080, 0.435, "C"),
]
# the smoothing length for every flow (h / dx; 2.0 before 2026-11-25: README.md, "smoothing length")
H_OVER_DX = 1.5
# particle shifting for every flow (docs/numerics.md §7a; A = 2, DualSPHysics' default; none before 2026-11-26):
# without it the start lattice breaks up after 10-20 s and the disordered particles carry up to 40 % of the
# shear through their pressure forces (README.md, "slow-down")
SHIFTING = 2.0
# Table 3-2: the calibrated R_d / H of each flow (what the runs use; rd_source="law" gives the fitted law instead)
RD_TABLE = {"S004H40": 0.285, "S004H50": 0.206, "S004H70": 0.144, "S004H90": 0.104, "S004H100": 0.094,
            "S003H50": 0.202, "S003H60": 0.156, "S003H70": 0.135, "S003H80": 0.116, "S002H60": 0.172,
            "S002H70": 0.137, "S002H80": 0.113}


# the measured discharges the thesis gives (m3/s; §3.2.2, S004H50 only) and the flume width (m; Nichols 2013)
Q_MEASURED = {"S004H50": 0.00825}
B_FLUME = 0.459


def measured_u(fr, h):
    return fr * math.sqrt(G * h)


def measured_u_q(fid):
    """U = Q / (B H) where the thesis gives Q, else None."""
    if fid not in Q_MEASURED:
        return None
    return Q_MEASURED[fid] / (B_FLUME * flow(fid)[3])


def rd_over_h_law(h):
    """The power law fitted to Table 3-2's calibration cases (the form of Kazemi's Fig. 3-5; least squares)."""
    return 0.0054 * h ** -1.224


def rd_over_h(fid, rd_source="table"):
    """R_d / H of flow `fid`: Table 3-2's value (default) or the fitted law (rd_source="law")."""
    if rd_source == "table":
        return RD_TABLE[fid]
    if rd_source == "law":
        return rd_over_h_law(flow(fid)[3])
    raise ValueError(f"rd_source {rd_source!r}: 'table' or 'law'")


def rd_of(fid, rd_source="table"):
    """R_d [m] of flow `fid`."""
    return rd_over_h(fid, rd_source) * flow(fid)[3]


def flow(fid):
    for row in TABLE:
        if row[1] == fid:
            return row
    raise KeyError(fid)


def dx_of(fid, dx_per_h=20, rd_source="table"):
    """The particle spacing of flow `fid`: about H / dx_per_h, a whole number of rows in the fluid depth H + R_d."""
    h = flow(fid)[3]
    depth = h + rd_of(fid, rd_source)
    return depth / max(1, round(dx_per_h * depth / h))


def case_yaml(fid, dx_per_h=20, t_end=30.0, u0=0.2, turbulence="mixing_length", periodic=False, output=0.5,
              outlet="frozen", length_h=4.0, rd_source="table"):
    """The case file text of flow `fid` (in/out-flow channel, or periodic along x with periodic=True)."""
    _, _, s0, h, fr, _ = flow(fid)
    u = measured_u(fr, h)
    dx = dx_of(fid, dx_per_h, rd_source)  # N rows fill H + R_d (dx_of)
    L = round(length_h * h / dx) * dx  # the thesis: 4 H (here the nearest whole number of dx)
    zone = 4.0 * dx  # at least one kernel support (2h = 3 dx at h = 1.5 dx)
    rd = rd_of(fid, rd_source)
    depth = h + rd  # fluid from the numerical bed to the surface
    top = depth + 0.25 * dx  # the fluid box's top: the lattice (rows at (i + 1/2) dx) then holds exactly N rows
    c0 = 16.0 * u
    if turbulence == "mixing_length":
        turb = "{model: mixing_length, profile: nezu_rodi, bed: 0.0, kappa: 0.41}"
    else:
        turb = "{model: smagorinsky, cs: 0.15}"
    x0 = 0.0 if periodic else -zone
    x1 = L if periodic else L + zone
    lines = [
        f"# Kazemi ch. 3 rough-bed flow {fid}: S0 = {s0}, H = {h} m, measured U = {u:.4f} m/s,",
        f"# R_d = {rd:.5f} m (R_d/H = {rd / h:.4f}, {'Table 3-2' if rd_source == 'table' else 'the fitted law'}), spheres d_s = {DS} m; fluid depth H + R_d",
        f"# = {h + rd:.5f} m above the numerical bed (z = 0), crest at z = R_d. Generated by",
        "# validation/rough_bed/flows.py; see that file for the numerical settings.",
        f"name: rough_bed_{fid}{'_periodic' if periodic else ''}",
        "dimension: 2",
        f"slope: {s0}",
        f"particles: {{dx: {dx:.9g}, kernel: wendland_c2, h_over_dx: {H_OVER_DX}}}",
        f"fluid: {{density: 1000.0, viscosity: {NU}, sound_speed: {c0:.4g}}}",
        "scheme: {integrator: verlet, density_diffusion: fourtakas, viscosity: laminar, "
        f"shifting: {{coefficient: {SHIFTING}}}}}",
        "walls: {type: dummy, slip: no_slip}",
        f"turbulence: {turb}",
        "forces:",
        f"  - {{type: rough_bed, cd: 1.0, diameter: {DS}, bed: 0.0, thickness: {rd:.6g}}}",
        "geometry:",
        # the bed: in a periodic channel exactly one period (the images continue it), else a kernel support beyond the zones
        # and its lattice from a whole number of dx below z = 0, so that the wall rows sit at -dx/2, -3dx/2, ... (from
        # -0.05 m, as before 2026-11-24, the top row sat up to 0.7 dx lower wherever 0.05 / dx is not whole)
        f"  - {{type: plane, point: [0.0, 0.0], normal: [0.0, 1.0], min: [{x0 - (0 if periodic else 6 * dx):.12g}, {-8 * dx:.12g}], "
        f"max: [{x1 + (0 if periodic else 6 * dx):.12g}, 0.0]}}",
        f"  - {{type: box, fill: fluid, min: [{x0:.12g}, 0.0], max: [{x1:.12g}, {top:.6g}], velocity: [{u0}, 0.0]}}",
    ]
    if periodic:
        lines += [f"domain: {{min: [{x0:.12g}, -0.05], max: [{x1:.12g}, {3 * depth:.6g}], periodic: [x]}}"]
    else:
        lines += [
            "open_boundaries:",
            f"  - {{type: inflow, zone: [{-zone:.6g}, 0.0], depth: {depth:.6g}, velocity: averaged, initial_profile: true,",
            f"     profile: {{type: uniform, u: {u0}}}}}",
            # outlet: Kazemi's frozen outflow (default); outlet="extrapolated" gives the zero-gradient one (velocity
            # and density extrapolated), which at L = 4 H lets the flow stall (validation/README.md)
            f"  - {{type: outflow, zone: [{L:.6g}, {L + zone:.6g}], depth: {depth:.6g}, "
            + {"frozen": "velocity: frozen}", "extrapolated": "velocity: extrapolated, pressure: extrapolated}",
               # a tailgate: the tailwater stage H + R_d (the flume's measured depth) imposed as hydrostatic pressure,
               # velocity zero-gradient (issue 20 decision 3; long_channel.py)
               "tailwater": "velocity: extrapolated, pressure: imposed}"}[outlet],
            f"domain: {{min: [{-zone - 0.05:.6g}, -0.05], max: [{L + zone + 0.05:.6g}, {3 * depth:.6g}]}}",
        ]
    lines += [f"time: {{end: {t_end}, output_interval: {output}}}", "gauges:"]
    for name, xf in (("q_in", 0.0), ("q_mid", 0.5), ("q_out", 1.0)):
        if periodic and name != "q_mid":
            continue
        lines.append(f"  - {{name: {name}, type: flux, start: [{xf * L:.6g}, 0.0], end: [{xf * L:.6g}, {2 * h:.6g}], points: 81}}")
    for name, xf in (("u_25", 0.25), ("u_50", 0.5), ("u_75", 0.75)):
        lines.append(f"  - {{name: {name}, type: velocity_profile, start: [{xf * L:.6g}, {0.5 * dx:.6g}], "
                     f"end: [{xf * L:.6g}, {depth - 0.5 * dx:.6g}], points: {2 * dx_per_h + 1}}}")
    lines.append(f"  - {{name: u_above, type: velocity_profile, start: [{0.5 * L:.6g}, {rd:.6g}], "
                 f"end: [{0.5 * L:.6g}, {depth:.6g}], points: 41}}")
    lines.append(f"  - {{name: stress_50, type: stress_profile, start: [{0.5 * L:.6g}, {0.5 * dx:.6g}], "
                 f"end: [{0.5 * L:.6g}, {depth - 0.5 * dx:.6g}], points: {2 * dx_per_h + 1}}}")
    lines.append(f"  - {{name: depth, type: depth_profile, start: [{0.1 * L:.6g}, 0.0], end: [{0.9 * L:.6g}, 0.0], points: 9}}")
    if not periodic:
        lines.append("  - {name: volumes, type: boundary_volume}")
    return "\n".join(lines) + "\n"


if __name__ == "__main__":
    import sys
    print(case_yaml(sys.argv[1] if len(sys.argv) > 1 else "S004H50"))
