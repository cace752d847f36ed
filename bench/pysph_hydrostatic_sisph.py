#!/usr/bin/python3
"""PySPH's hydrostatic tank run with its SISPH scheme (for bench/isph_vs_pysph.py).

The geometry, spacing, kernel, smoothing length, gravity history and end time are those of PySPH's own
pysph/examples/hydrostatic_tank.py (Adami, Hu & Adams 2012, section 6; that example runs a WCSPH
formulation only): still water H = 0.9 m deep in a tank Lx = 2 m wide and Ly = 1 m high, gravity
gy = -1.0 m/s^2 switched on over tdamp = 1 s with the example's ramp 0.5 (sin((t/tdamp - 0.5) pi) + 1),
dx = Lx/100 = 0.02 m on the same lattice (wall faces at x = 0, Lx and y = 0, particles dx/2 from them,
6 wall layers), QuinticSpline at h = 1.2 dx, tf = 2 s. The particles start at rest at rho0, p = 0.

The scheme is PySPH's SISPHScheme (Muta, Ramachandran & Negi 2020, pysph/sph/isph/sisph.py), set up as
PySPH's dam_break_2d.py sets it up for a free-surface flow: nu = 0, artificial viscosity alpha = 0.05,
pref = rho0 c0^2, GTVF, symmetric pressure gradient, hydrostatic wall correction, tolerance 0.05 of the
Jacobi pressure iterations, fixed dt = 0.125 h / vref with vref = sqrt(2 g H). The one change to the
scheme's equations is the ramp: its body force (MomentumEquationBodyForce) and the gravity term of its
wall pressure (SetPressureSolid) use g(t) instead of the constant g. `--tdamp 0` applies gravity in full
from t = 0: the warm-started Jacobi pressure then builds up over many steps and the column bounces
(bottom pressure between 0.25 and 1.9 rho g H, undamped to t = 2 s; measured with PySPH 1.0b1).

Any PySPH Application option works (-d DIR, --tf, --pfreq, --openmp, --max-steps, -z, --tol ...).
Usage: /usr/bin/python3 bench/pysph_hydrostatic_sisph.py -d OUTDIR [--tf 2.0] [--pfreq 10] [--tdamp 1.0]
"""
from math import sin, pi as M_PI  # noqa: F401 (the names the kernels use; compiled by Cython)

import numpy as np

from pysph.base.kernels import QuinticSpline
from pysph.base.utils import get_particle_array
from pysph.solver.application import Application
from pysph.sph.isph.sisph import SISPHScheme, MomentumEquationBodyForce, SetPressureSolid

# pysph/examples/hydrostatic_tank.py
Lx = 2.0
Ly = 1.0
H = 0.9
gy = -1.0
Vmax = np.sqrt(abs(gy) * H)
c0 = 10 * Vmax
rho0 = 1000.0
nx = 100
dx = Lx / nx
ghost_extent = 5.5 * dx
hdx = 1.2
tdamp = 1.0
tf = 2.0

# pysph/examples/dam_break_2d.py's SISPH time step: dt = 0.125 h / vref, vref = sqrt(2 g H)
vref = np.sqrt(2 * abs(gy) * H)
dt = 0.125 * hdx * dx / vref


class RampedBodyForce(MomentumEquationBodyForce):
    """SISPH's body force times the example's ramp (MomentumEquationPressureGradient's tdamp)."""
    def __init__(self, dest, sources, gx=0.0, gy=0.0, gz=0.0, tdamp=0.0):
        self.tdamp = tdamp
        super(RampedBodyForce, self).__init__(dest, sources, gx, gy, gz)

    def post_loop(self, d_idx, d_au, d_av, d_aw, t):
        damping_factor = 1.0
        if t < self.tdamp:
            damping_factor = 0.5 * (sin((-0.5 + t / self.tdamp) * M_PI) + 1.0)
        d_au[d_idx] += self.gx * damping_factor
        d_av[d_idx] += self.gy * damping_factor
        d_aw[d_idx] += self.gz * damping_factor


class RampedSetPressureSolid(SetPressureSolid):
    """SISPH's wall pressure with the ramped gravity in its hydrostatic term."""
    def __init__(self, dest, sources, gx=0.0, gy=0.0, gz=0.0, hg_correction=True, tdamp=0.0):
        self.tdamp = tdamp
        super(RampedSetPressureSolid, self).__init__(dest, sources, gx, gy, gz, hg_correction)

    def loop(self, d_idx, s_idx, d_p, s_p, s_rho, d_au, d_av, d_aw, WIJ, XIJ, t):
        damping_factor = 1.0
        if t < self.tdamp:
            damping_factor = 0.5 * (sin((-0.5 + t / self.tdamp) * M_PI) + 1.0)
        gdotxij = (self.gx * damping_factor - d_au[d_idx]) * XIJ[0] + \
            (self.gy * damping_factor - d_av[d_idx]) * XIJ[1] + \
            (self.gz * damping_factor - d_aw[d_idx]) * XIJ[2]
        d_p[d_idx] += s_p[s_idx] * WIJ + s_rho[s_idx] * gdotxij * WIJ


class HydrostaticTankSISPH(Application):
    def add_user_options(self, group):
        group.add_argument(
            '--tdamp', action='store', type=float, dest='tdamp', default=tdamp,
            help='Gravity ramp time (the example\'s tdamp); 0: full gravity from t = 0.')

    def create_particles(self):
        # the example's lattice and its split into fluid and an open tank
        _x = np.arange(-ghost_extent, Lx + ghost_extent, dx)
        _y = np.arange(-ghost_extent, Ly, dx)
        x, y = np.meshgrid(_x, _y)
        x, y = x.ravel(), y.ravel()
        inside = (x > 0.0) & (x < Lx) & (y > 0.0) & (y < H)
        lid = ~inside & (y > 0.9) & (x > 0.0) & (x < Lx)
        wall = ~inside & ~lid
        m = rho0 * dx * dx
        h = hdx * dx
        fluid = get_particle_array(name='fluid', x=x[inside], y=y[inside], m=m, h=h, rho=rho0)
        solid = get_particle_array(name='solid', x=x[wall], y=y[wall], m=m, h=h, rho=rho0)
        self.scheme.setup_properties([fluid, solid])
        print("Hydrostatic tank (SISPH) :: nfluid = %d, nsolid = %d, dt = %g, tdamp = %g" % (
            fluid.get_number_of_particles(), solid.get_number_of_particles(), dt, self.options.tdamp))
        return [fluid, solid]

    def create_scheme(self):
        return SISPHScheme(
            fluids=['fluid'], solids=['solid'], dim=2, nu=0.0, c0=c0, rho0=rho0,
            alpha=0.05, gy=gy, pref=rho0 * c0**2, internal_flow=False,
            hg_correction=True, gtvf=True, symmetric=True
        )

    def configure_scheme(self):
        self.scheme.configure_solver(
            kernel=QuinticSpline(dim=2), dt=dt, tf=tf, adaptive_timestep=False, pfreq=10
        )

    def create_equations(self):
        eqns = self.scheme.get_equations()
        td = self.options.tdamp
        if td > 0.0:
            for stage in eqns.groups:
                for group in stage:
                    for i, eq in enumerate(group.equations):
                        if type(eq) is MomentumEquationBodyForce:
                            group.equations[i] = RampedBodyForce(
                                eq.dest, eq.sources, eq.gx, eq.gy, eq.gz, tdamp=td)
                        elif type(eq) is SetPressureSolid:
                            group.equations[i] = RampedSetPressureSolid(
                                eq.dest, eq.sources, eq.gx, eq.gy, eq.gz, eq.hg_correction, tdamp=td)
        return eqns


if __name__ == '__main__':
    app = HydrostaticTankSISPH(fname='hydrostatic_sisph')
    app.run()
