#!/usr/bin/python3
"""Where the shear goes in a periodic rough-bed run (issue 20, item 2: the slow-down; README.md, "slow-down").

For planes z = const above the roughness, the x-force per unit bed length that the fluid particles above the
plane receive from those below it, split into the pair pressure force (the scheme's sum form,
-m_a m_b (p_a + p_b)/(rho_a rho_b) dW/dx) and the modelled stress (m_a m_b (tau_a/rho_a + tau_b/rho_b).grad W,
tau kinematic as stored), averaged over the snapshots in [t0, t1], against the stress the uniform flow must
carry there, rho g S0 (D - z). In the continuum only the modelled stress carries shear; a share carried by
the pressure forces is a property of the particle arrangement.
Usage: /usr/bin/python3 validation/rough_bed/shear_budget.py RUN_DIR FLOW_ID t0 t1 [z1 z2 ...]
(RUN_DIR: a periodic run of check.py, e.g. $TMPDIR/sphflume-validation/rough_bed/S004H50_periodic)
"""
import glob
import os
import sys

import h5py
import numpy as np
import yaml

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import flows  # noqa: E402


def main():
    if len(sys.argv) < 5:
        sys.exit(__doc__)
    out, fid, t0, t1 = sys.argv[1], sys.argv[2], float(sys.argv[3]), float(sys.argv[4])
    with open(out + ".yaml") as f:
        case = yaml.safe_load(f)
    _, _, s0, h, _, _ = flows.flow(fid)
    depth = h + flows.rd_of(fid)
    length = case["domain"]["max"][0] - case["domain"]["min"][0]
    planes = [float(v) for v in sys.argv[5:]] or list(np.linspace(flows.rd_of(fid), depth, 6)[1:-1])
    rho0, g = 1000.0, 9.81
    acc_p, acc_s, n = np.zeros(len(planes)), np.zeros(len(planes)), 0
    for f in sorted(glob.glob(os.path.join(out, "snapshots", "snap_*.h5"))):
        with h5py.File(f, "r") as H:
            if not t0 <= H.attrs["time"] <= t1:
                continue
            fl = H["kind"][:] == 0
            x = H["position"][:][fl][:, [0, -1]]
            p, rho, m = H["pressure"][:][fl], H["density"][:][fl], H["mass"][:][fl]
            txx, txz = H["tau_xx"][:][fl], H["tau_xz"][:][fl]
        dxv = x[:, None, 0] - x[None, :, 0]
        dxv -= length * np.round(dxv / length)
        dz = x[:, None, 1] - x[None, :, 1]
        r = np.hypot(dxv, dz)
        hk = case["particles"]["h_over_dx"] * case["particles"]["dx"]
        q = r / hk
        al = 7.0 / (4.0 * np.pi * hk * hk)
        fr = np.where((q < 2.0) & (r > 0), al * (-5.0 * q) * (1.0 - q / 2.0) ** 3 / hk / np.where(r > 0, r, 1.0), 0.0)
        gx, gz = fr * dxv, fr * dz
        mm = m[:, None] * m[None, :]
        fp = -mm * (p[:, None] + p[None, :]) / (rho[:, None] * rho[None, :]) * gx
        fs = mm * ((txx[:, None] / rho[:, None] + txx[None, :] / rho[None, :]) * gx
                   + (txz[:, None] / rho[:, None] + txz[None, :] / rho[None, :]) * gz)
        for i, zp in enumerate(planes):
            sel = (x[:, 1] > zp)[:, None] & (x[:, 1] <= zp)[None, :]
            acc_p[i] += fp[sel].sum()
            acc_s[i] += fs[sel].sum()
        n += 1
    if n == 0:
        sys.exit(f"no snapshot in [{t0}, {t1}] s in {out}")
    print(f"{fid}: {n} snapshots in [{t0}, {t1}] s; force per bed area on the fluid above each plane, N/m2")
    for i, zp in enumerate(planes):
        need = rho0 * g * s0 * (depth - zp)
        sp, ss = -acc_p[i] / n / length, -acc_s[i] / n / length
        print(f"  z = {zp:.4f} m: pressure pairs {sp:7.4f} ({sp / need:5.2f}), modelled stress {ss:7.4f} ({ss / need:5.2f}), "
              f"needed rho g S0 (D - z) = {need:.4f}")


if __name__ == "__main__":
    main()
