import numpy as np
from wm2 import *
from final import c0, Gfun
h = 0.4
def fmt(z): return '%+.5f%+.5fi' % (z.real, z.imag)
w1, w2 = 2*np.pi*0.6, 2*np.pi*0.7
comps = [('2f1=1.2Hz', w1, w1, 1, 0.5), ('2f2=1.4Hz', w2, w2, 1, 0.5), ('f1+f2=1.3Hz', w2, w1, 1, 1.0), ('f2-f1=0.1Hz', w2, w1, -1, 1.0)]
for name, a, b, s, fac in comps:
    row = []
    for J in [0, 10, 100]:
        row.append(fmt(fac*1e-4*Gfun(a, b, J, s)*1e3))
    r = 2*Gfun(a, b, 800, s) - Gfun(a, b, 400, s)
    row.append(fmt(fac*1e-4*r*1e3))
    print(name, ' | '.join(row), '  G(J=100)=', fmt(Gfun(a, b, 100, s)))
w = 2*np.pi/1.5; A = 0.02
for J in [0, 10, 100]:
    print('regular J=%d G=%s  C=%s mm' % (J, fmt(Gfun(w, w, J, 1)), fmt(0.5*A*A*Gfun(w, w, J, 1)*1e3)))
k = k_prog(w, h); K = k_prog(2*w, h); c = c0(w)
sc = 3*A*A*g*K*K*k*k/(16*c*w**3)*(w/(k*k - K*K) - 2*g*k*c/(w*np.cosh(k*h)**2*(4*k*k - K*K)))
print('closed form J=0 sin-coef %.6f mm' % (sc*1e3), 'K=%.6f' % K)
# flap, bottom hinged (l=0) and hinge 0.1 m above bottom
for l in [0.0, -0.1]:
    pad = Paddle(h, l); kk = k_prog(w, h); cf = pad.c(np.array([kk+0j]))[0].real
    for J in [0, 10, 100]:
        F = F2(pad, w, w, J, 1); G = -F/cf**2
        print('flap l=%g c0=%.6f J=%d G=%s C=%s mm' % (l, cf, J, fmt(G), fmt(0.5*A*A*G*1e3)))
    F = F2(pad, w2, w1, 100, -1); cA = pad.c(np.array([k_prog(w2,h)+0j]))[0].real; cB = pad.c(np.array([k_prog(w1,h)+0j]))[0].real
    print('   flap l=%g sub 0.7/0.6 J=100 G-=%s' % (l, fmt(F/(cA*cB))))
