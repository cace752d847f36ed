import numpy as np
from wm2 import *
h = 0.4; pad = Paddle(h)
def c0(w): k = k_prog(w, h); return 4*np.sinh(k*h)**2/(np.sinh(2*k*h) + 2*k*h)
def Gfun(wn, wm, J, s):
    F = F2(pad, wn, wm, J, s); return (-F if s > 0 else F)/(c0(wn)*c0(wm))
def X2_real(t, w, A, th, J):
    N = len(w); out = np.zeros_like(t)
    for n in range(N):
        for m in range(N):
            if n == m:
                out += 0.5*A[n]**2*np.real(Gfun(w[n], w[n], J, 1)*np.exp(1j*(2*w[n]*t + 2*th[n])))
            elif n < m:
                out += A[n]*A[m]*np.real(Gfun(w[n], w[m], J, 1)*np.exp(1j*((w[n]+w[m])*t + th[n]+th[m])))
            else:   # n > m: difference term, assumes w[n] > w[m]
                out += A[n]*A[m]*np.real(Gfun(w[n], w[m], J, -1)*np.exp(1j*((w[n]-w[m])*t + th[n]-th[m])))
    return out
def X2_complex(t, w, A, th, J):  # 1/2 sum_n sum_m F Xn Xm(*) e^{...} with Xn = -i A e^{i th}/c0
    X = [-1j*A[n]*np.exp(1j*th[n])/c0(w[n]) for n in range(len(w))]; out = np.zeros_like(t)
    for n in range(len(w)):
        for m in range(len(w)):
            out += np.real(0.5*F2(pad, w[n], w[m], J, 1)*X[n]*X[m]*np.exp(1j*(w[n]+w[m])*t))
            if n != m:
                a, b = (n, m) if w[n] > w[m] else (m, n)
                out += np.real(0.5*F2(pad, w[a], w[b], J, -1)*X[a]*np.conj(X[b])*np.exp(1j*(w[a]-w[b])*t))
    return out
w = np.array([2*np.pi*0.7, 2*np.pi*0.6]); A = np.array([0.01, 0.01]); th = np.array([0.0, 0.0])
ts = np.array([0.0, 0.5, 1.0, 2.5, 7.3])
X1 = sum(A[n]/c0(w[n])*np.sin(w[n]*ts + th[n]) for n in range(2))
print('c0(0.6Hz)=%.9f c0(0.7Hz)=%.9f k(0.6)=%.9f k(0.7)=%.9f' % (c0(w[1]), c0(w[0]), k_prog(w[1], h), k_prog(w[0], h)))
print('t =', ts); print('X1 [mm] =', np.round(X1*1e3, 6))
for J in [0, 10, 100]:
    a = X2_real(ts, w, A, th, J); b = X2_complex(ts, w, A, th, J)
    print('J=%d X2 [mm] =' % J, np.round(a*1e3, 6), ' max|real-complex| =', np.max(np.abs(a-b)))
# odd phases
th2 = np.array([0.7, -1.2]); A2 = np.array([0.008, 0.012])
a = X2_real(ts, w, A2, th2, 10); b = X2_complex(ts, w, A2, th2, 10); print('phase test diff', np.max(np.abs(a-b)))
# closed-form progressive-only regular-wave sin-coefficient
for T in [1.5, 3.0]:
    ww = 2*np.pi/T; k = k_prog(ww, h); K = k_prog(2*ww, h); c = c0(ww); Aa = 0.02
    R = 3*K*K/(8*c*c*ww**3)*(-g*ww*c*k*k/(k*k - K*K) + 2*g*g*k**3*c*c/(ww*np.cosh(k*h)**2*(4*k*k - K*K)))
    print('T', T, 'closed-form J=0 sin-coef %.9f mm' % (0.5*Aa*Aa*R*1e3), ' from F2: %.9f mm' % (-np.imag(0.5*Aa*Aa*Gfun(ww, ww, 0, 1))*1e3),
          ' Madsen %.9f mm' % ((2*Aa)**2/(32*h)*(3*np.cosh(k*h)/np.sinh(k*h)**3 - 2/c)*1e3))
