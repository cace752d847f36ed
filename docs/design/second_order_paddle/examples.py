import numpy as np
from wm2 import *
def G(pad, wn, wm, J, sgn):
    kn, km = k_prog(wn, pad.h), k_prog(wm, pad.h)
    cn = pad.c(np.array([kn+0j]))[0].real; cm = pad.c(np.array([km+0j]))[0].real
    F = F2(pad, wn, wm, J, sgn)
    return (-F if sgn > 0 else F)/(cn*cm)
h = 0.4; pis = Paddle(h)
print('=== regular: h=0.4 T=1.5 H=0.04 ===')
w = 2*np.pi/1.5; k = k_prog(w, h); c0 = 4*np.sinh(k*h)**2/(np.sinh(2*k*h) + 2*k*h); A = 0.02
print('k=%.6f kh=%.6f c0=%.6f X1amp=A/c0=%.6f mm' % (k, k*h, c0, A/c0*1e3))
mad = 0.04**2/(32*h)*(3*np.cosh(k*h)/np.sinh(k*h)**3 - 2/c0)
print('Madsen amplitude (coefficient of sin 2wt): %.6f mm' % (mad*1e3))
vals = {}
for J in [0, 10, 20, 50, 100, 200, 400, 800]:
    Gv = G(pis, w, w, J, +1); amp = 0.5*A*A*Gv; vals[J] = amp
    print('J=%4d  G+=%s  X2 = Re[%s e^{2iwt}]  |X2|=%.6f mm  phase=%.4f rad  (sin-coef %.6f mm, cos-coef %.6f mm)' % (J, np.round(Gv, 6), np.round(amp*1e3, 6), abs(amp)*1e3, np.angle(amp), -amp.imag*1e3, amp.real*1e3))
rich = 2*vals[800] - vals[400]
print('Richardson (1/J) J->inf: X2 = Re[%s mm e^{2iwt}] |X2|=%.6f mm' % (np.round(rich*1e3, 6), abs(rich)*1e3))
print('=== bichromatic: h=0.4 f1=0.6 f2=0.7 A1=A2=0.01 theta=0 ===')
w1, w2 = 2*np.pi*0.6, 2*np.pi*0.7; A1 = A2 = 0.01
for nm, (wa, wb, s, fac) in {'2w1': (w1, w1, 1, 0.5), '2w2': (w2, w2, 1, 0.5), 'w1+w2': (w2, w1, 1, 1.0), 'w2-w1': (w2, w1, -1, 1.0)}.items():
    out = []
    for J in [0, 20, 100, 400, 800]:
        Gv = G(pis, wa, wb, J, s); out.append((J, Gv, fac*A1*A2*Gv))
    r = 2*out[-1][2] - out[-2][2]
    print(nm, 'freq %.4f Hz' % ((wa + s*wb)/(2*np.pi)))
    for J, Gv, amp in out:
        print('   J=%4d G=%s  complex amp=%s mm  |amp|=%.6f mm' % (J, np.round(Gv, 6), np.round(amp*1e3, 6), abs(amp)*1e3))
    print('   J->inf (Richardson) amp=%s mm |amp|=%.6f mm' % (np.round(r*1e3, 6), abs(r)*1e3))
