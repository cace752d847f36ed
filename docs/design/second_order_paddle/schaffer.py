import numpy as np
from scipy.optimize import brentq
g = 9.81

def k_prog(w, h):
    # progressive root of w^2 = g k tanh(kh)
    f = lambda k: g*k*np.tanh(k*h) - w*w
    kd = w*w/g
    return brentq(f, 1e-12, max(kd, np.sqrt(w*w/(g*h)))*2 + 10/h)

def k_modes(w, h, J):
    """k_0 (real>0) and k_j = -i*kappa_j, j=1..J, kappa_j in ((j-1/2)pi/h, j pi/h)"""
    ks = [k_prog(w, h) + 0j]
    for j in range(1, J+1):
        f = lambda q: w*w + g*q*np.tan(q*h)
        a = (j-0.5)*np.pi/h + 1e-12; b = j*np.pi/h
        ks.append(-1j*brentq(f, a, b, xtol=1e-14))
    return np.array(ks)

def c_of(k, h):
    # first-order piston transfer eta/X for each mode (Biesel for j=0)
    return 2*(np.cosh(2*k*h)-1)/(np.sinh(2*k*h)+2*k*h)

def Hp(wn, wm, kj, kl):
    ws = wn+wm
    return ws*(wn*wm - g*g*kj*kl/(wn*wm)) + 0.5*(wn**3+wm**3) - 0.5*g*g*(kj**2/wn + kl**2/wm)

def Hm(wn, wm, kj, kl):  # kl already conjugated by caller
    ws = wn-wm
    return ws*(-wn*wm - g*g*kj*kl/(wn*wm)) + 0.5*(wn**3-wm**3) - 0.5*g*g*(kj**2/wn - kl**2/wm)

def F_pm(wn, wm, h, J=50, sign=+1):
    """Complex piston transfer F such that, for ordered pairs,
       X2 = Re[ 1/2 * sum_n sum_m F(n,m) Xn Xm e^{i(wn+wm)t} ]   (sign=+1)
       X2 = Re[ 1/2 * sum_n sum_m F(n,m) Xn conj(Xm) e^{i(wn-wm)t} ] (sign=-1, n!=m)
       where X1 = Re[ sum_n Xn e^{i wn t} ]."""
    kn = k_modes(wn, h, J); km = k_modes(wm, h, J)
    cn = c_of(kn, h); cm = c_of(km, h)
    if sign < 0:
        km = np.conj(km); cm = np.conj(cm)
    ws = wn + sign*wm
    K = k_prog(abs(ws), h)
    S1 = np.sum(cn*kn**2*(wn**2-ws**2)/(kn**2-K**2))
    S2 = np.sum(cm*km**2*(wm**2-ws**2)/(km**2-K**2))
    KJ, KL = np.meshgrid(kn, km, indexing='ij')
    CJ, CL = np.meshgrid(cn, cm, indexing='ij')
    kap = KJ + sign*KL
    H = Hp(wn, wm, KJ, KL) if sign > 0 else Hm(wn, wm, KJ, KL)
    S3 = np.sum(CJ*CL*kap*H/(kap**2-K**2))
    return 1j*K**2/ws**3 * (-g/(2*wn)*S1 - g/(2*wm)*S2 + sign*S3)
