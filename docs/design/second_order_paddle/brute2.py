import numpy as np, sys
from wm2 import *
h = 0.4; w0 = 2*np.pi*0.1; nn, mm = 7, 6; wn, wm = nn*w0, mm*w0
l = float(sys.argv[1]); J = int(sys.argv[2]); pad = Paddle(h, l)
Xn = 0.013*np.exp(0.4j); Xm = 0.009*np.exp(-1.1j)
Nt = 128; t = np.arange(Nt)*(2*np.pi/w0)/Nt
modes = []
for (w, X) in [(wn, Xn), (wm, Xm)]:
    ks = k_modes(w, h, J); cs = pad.c(ks)
    for k, c in zip(ks, cs): modes.append((w, k, -g*c*X/w))
# check first-order paddle BC numerically: sum_j -ik P C(z) == i w X f(z)
def f(z):
    if not np.isfinite(l): return 1.0, 0.0
    s = z + h; return ((s + l)/(h + l), 1.0/(h + l)) if s >= pad.d else (0.0, 0.0)
def fields_surface(x):
    u = np.zeros(Nt); wz = np.zeros(Nt); pt = np.zeros(Nt); D = np.zeros(Nt)
    for (w, k, P) in modes:
        e = np.exp(1j*(w*t - k*x)); Cz = k*np.tanh(k*h)
        u += np.real(-1j*k*P*e); wz += np.real(P*Cz*e); pt += np.real(1j*w*P*e); D += np.real(P*(-w*w*Cz + g*k*k)*e)
    return u, wz, pt, D
def Qhat(x, i):
    u, wz, pt, D = fields_surface(x); E = u*u + wz*wz
    Et = np.real(np.fft.ifft(1j*np.fft.fftfreq(Nt, 1.0/Nt)*w0*np.fft.fft(E)))
    return 2*(np.fft.fft(-Et + pt*D/g)/Nt)[i]
def What(z, i):   # f X1 phi_xx - f' X1 phi_z  at x=0
    X1 = np.real(Xn*np.exp(1j*wn*t) + Xm*np.exp(1j*wm*t)); fz, fp = f(z)
    pxx = np.zeros(Nt); pz = np.zeros(Nt)
    for (w, k, P) in modes:
        e = np.exp(1j*w*t)
        pxx += np.real(-k*k*P*np.cosh(k*(z+h))/np.cosh(k*h)*e); pz += np.real(k*P*np.sinh(k*(z+h))/np.cosh(k*h)*e)
    return 2*(np.fft.fft(X1*(fz*pxx - fp*pz))/Nt)[i]
def gl(a, b, npan, nq=24, log=False):
    edges = np.concatenate([[a], np.geomspace(1e-7, b, npan)]) if log else np.linspace(a, b, npan+1)
    xq, wq = np.polynomial.legendre.leggauss(nq); X = []; W = []
    for lo, hi in zip(edges[:-1], edges[1:]): X.append(0.5*(hi-lo)*xq + 0.5*(hi+lo)); W.append(0.5*(hi-lo)*wq)
    return np.concatenate(X), np.concatenate(W)
for sgn, idx in [(+1, nn+mm), (-1, nn-mm)]:
    ws = wn + sgn*wm; K = k_prog(ws, h); kap00 = k_prog(wn, h) + sgn*k_prog(wm, h)
    L0 = 40*h; xs, wx = gl(0.0, L0, 80, log=True)
    Qx = np.array([Qhat(x, idx) for x in xs])
    Q00 = np.mean([Qhat(x, idx)*np.exp(1j*kap00*x) for x in np.linspace(L0, L0 + 2*np.pi/abs(kap00), 7)])
    I = np.sum(wx*np.cos(K*xs)*(Qx - Q00*np.exp(-1j*kap00*xs))) + Q00*(-1j*kap00/(kap00**2 - K*K))
    zlo = -h + pad.d
    zs, wzq = gl(-h, 0.0, 60) if pad.d == 0 else (lambda a, b: (np.concatenate([a[0], b[0]]), np.concatenate([a[1], b[1]])))(gl(-h, zlo, 20), gl(zlo, 0.0, 40))
    IW = np.sum(wzq*np.cosh(K*(zs+h))*np.array([What(z, idx) for z in zs]))
    X2 = (np.cosh(K*h)/g*I + IW)/(1j*ws*pad.Lam(K))
    X2f = F2(pad, wn, wm, J, sgn)*Xn*(Xm if sgn > 0 else np.conj(Xm))
    print('l', l, 'J', J, 'sign', sgn, 'brute', X2, 'formula', X2f, 'rel.err %.2e' % (abs(X2 - X2f)/abs(X2f)))
