# Brute-force check: build real first-order fields (J evanescent modes), form the
# second-order forcing by direct products + FFT in time, and get the free-wave-cancelling
# paddle amplitude via Green's identity with numerical x-quadrature.
import numpy as np
from schaffer import *
h = 0.4; w0 = 2*np.pi*0.1
import sys; nn, mm = 10, 10; w0 = 2*np.pi/15.0
wn, wm = nn*w0, mm*w0
import sys
J = int(sys.argv[1])
Xn = 0.02/0.9456*np.exp(0.3j); Xm = 0.0
Nt = 128
t = np.arange(Nt)*(2*np.pi/w0)/Nt
modes = []
for (w, X) in [(wn, Xn), (wm, Xm)]:
    ks = k_modes(w, h, J); cs = c_of(ks, h)
    for k, c in zip(ks, cs):
        modes.append((w, k, -g*c*X/w))   # P = -g c X / w
def fields_surface(x):
    # real fields at z=0 on (t) for scalar x: u, w, phi_t, D = d/dz(phi_tt + g phi_z)
    u = np.zeros(Nt); wz = np.zeros(Nt); pt = np.zeros(Nt); D = np.zeros(Nt)
    for (w, k, P) in modes:
        e = np.exp(1j*(w*t - k*x))
        Cz = k*np.tanh(k*h); Czz = k*k
        u += np.real(-1j*k*P*e); wz += np.real(P*Cz*e); pt += np.real(1j*w*P*e)
        D += np.real(P*(-w*w*Cz + g*Czz)*e)
    return u, wz, pt, D
def Qhat(x, ws_idx):
    u, wz, pt, D = fields_surface(x)
    E = u*u + wz*wz
    Et = np.real(np.fft.ifft(1j*np.fft.fftfreq(Nt, 1.0/Nt)*w0*np.fft.fft(E)))  # spectral d/dt
    Q = -Et + pt*D/g
    Qf = np.fft.fft(Q)/Nt
    return 2*Qf[ws_idx]          # Q = Re[Qhat e^{i ws t}]
def What(z, ws_idx):
    X1 = np.real(Xn*np.exp(1j*wn*t) + Xm*np.exp(1j*wm*t))
    pxx = np.zeros(Nt)
    for (w, k, P) in modes:
        pxx += np.real(-k*k*P*np.cosh(k*(z+h))/np.cosh(k*h)*np.exp(1j*w*t))
    return 2*(np.fft.fft(X1*pxx)/Nt)[ws_idx]
def gl_panels(a, b, npan, nq=24, log=True):
    if log: edges = np.concatenate([[a], np.geomspace(1e-7, b, npan)])
    else: edges = np.linspace(a, b, npan+1)
    xq, wq = np.polynomial.legendre.leggauss(nq)
    X = []; W = []
    for lo, hi in zip(edges[:-1], edges[1:]):
        X.append(0.5*(hi-lo)*xq + 0.5*(hi+lo)); W.append(0.5*(hi-lo)*wq)
    return np.concatenate(X), np.concatenate(W)
for sign, idx in [(+1, nn+mm)]:
    ws = wn + sign*wm; K = k_prog(ws, h)
    k0n = k_prog(wn, h); k0m = k_prog(wm, h); kap00 = k0n + sign*k0m
    L0 = 40*h
    xs, wx = gl_panels(0.0, L0, 80)
    Qx = np.array([Qhat(x, idx) for x in xs])
    # tail: pure progressive-progressive exponential; fit amplitude at large x
    xt = np.linspace(L0, L0+2*np.pi/abs(kap00), 7)
    Q00 = np.mean([Qhat(x, idx)*np.exp(1j*kap00*x) for x in xt])
    I = np.sum(wx*np.cos(K*xs)*(Qx - Q00*np.exp(-1j*kap00*xs))) + Q00*(-1j*kap00/(kap00**2-K**2))
    zs, wzq = gl_panels(-h, 0.0, 40, log=False)
    Wz = np.array([What(z, idx) for z in zs])
    IW = np.sum(wzq*np.cosh(K*(zs+h))*Wz)
    X2 = (np.cosh(K*h)/g*I + IW)/(1j*ws*np.sinh(K*h)/K)
    F = F_pm(wn, wm, h, J, sign)
    X2f = 0.5*F*Xn*Xn
    print('sign', sign, 'brute', X2, 'formula', X2f, 'rel.err', abs(X2-X2f)/abs(X2f))
