"""Steady uniform solution of Kazemi's rough-bed model (MSPH-ML + drag layer) as a 1D ODE: the reference the
SPH runs are verified against (what the model itself predicts, independent of SPH).

Bed-aligned frame, numerical bed at z = 0, free surface at z = D (the fluid depth in the simulation), roughness
crest at z = R_d. Uniform flow: the shear stress tau/rho = (nu + l_m^2 |du/dz|) du/dz satisfies
    d(tau/rho)/dz = -g S0 + C_d W_d(z) / (2 d_s) u|u|,   tau(D) = 0,   u(0) = 0,
with W_d the point form sqrt(1 - ((z - z_c)/(d_s/2))^2) inside the layer (z_c = R_d - d_s/2) and
l_m = kappa z sqrt(1 - z/D) (Nezu-Rodi, Pi = 0). Solved by shooting on the surface velocity (bisection), marching
down with N steps. Returns the profile; depth_mean() averages it over [z0, D].
"""
import math


def solve(depth, s0, rd, ds=0.024, cd=1.0, nu=1.0e-6, kappa=0.41, g=9.81, n=4000):
    """(z, u) lists from the surface down to the bed."""
    centre, r = rd - 0.5 * ds, 0.5 * ds

    def drag(z):
        if z <= 0.0 or z >= rd:
            return 0.0
        y = (z - centre) / r
        return 0.5 * cd * math.sqrt(max(0.0, 1.0 - y * y)) / ds

    def lm(z):
        return kappa * z * math.sqrt(1.0 - z / depth) if 0.0 < z < depth else 0.0

    def march(us, keep=False):
        dz = depth / n
        u, tau, z = us, 0.0, depth
        zs, uu = [], []
        for _ in range(n):
            l2 = lm(z) ** 2
            up = (-nu + math.sqrt(nu * nu + 4.0 * l2 * tau)) / (2.0 * l2) if (l2 > 0.0 and tau > 0.0) else tau / nu
            if keep:
                zs.append(z)
                uu.append(u)
            u -= up * dz
            tau += dz * (g * s0 - drag(z) * u * abs(u))
            z -= dz
            if u < -10.0:
                break
        if keep:
            zs.append(0.0)
            uu.append(u)
        return u, zs, uu

    lo, hi = 0.0, 5.0
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        if march(mid)[0] > 0.0:
            hi = mid
        else:
            lo = mid
    _, zs, uu = march(0.5 * (lo + hi), keep=True)
    return zs[::-1], uu[::-1]


def depth_mean(zs, uu, z0, z1):
    """Mean of u over [z0, z1] (trapezoids on the solution's grid)."""
    tot = ln = 0.0
    for i in range(1, len(zs)):
        a, b = max(zs[i - 1], z0), min(zs[i], z1)
        if b > a:
            tot += 0.5 * (uu[i - 1] + uu[i]) * (b - a)
            ln += b - a
    return tot / ln
