# Second-order wavemaker transfer functions (piston / flap), own derivation, Schaffer (1996) structure.
import numpy as np
from scipy.optimize import brentq
g = 9.81
def k_prog(w, h):
    return brentq(lambda k: g*k*np.tanh(k*h) - w*w, 1e-12, w*w/g + w/np.sqrt(g*h) + 10/h)
def k_modes(w, h, J):
    ks = [k_prog(w, h) + 0j]
    for j in range(1, J+1):
        ks.append(-1j*brentq(lambda q: w*w + g*q*np.tan(q*h), (j-0.5+1e-7)*np.pi/h, j*np.pi/h, xtol=1e-14))
    return np.array(ks)
# elementary integrals over s in [a,b] (s = z+h), complex r, with r->0 limits
def Ic(r, a, b):   # int cosh(r s)
    r = np.asarray(r, complex); out = np.empty_like(r); sm = np.abs(r) < 1e-9
    out[~sm] = (np.sinh(r[~sm]*b) - np.sinh(r[~sm]*a))/r[~sm]; out[sm] = b - a; return out
def Is(r, a, b):   # int sinh(r s)
    r = np.asarray(r, complex); out = np.empty_like(r); sm = np.abs(r) < 1e-9
    out[~sm] = (np.cosh(r[~sm]*b) - np.cosh(r[~sm]*a))/r[~sm]; out[sm] = r[sm]*(b*b-a*a)/2; return out
def Isc(r, a, b):  # int s cosh(r s)
    r = np.asarray(r, complex); out = np.empty_like(r); sm = np.abs(r) < 1e-9
    rr = r[~sm]
    out[~sm] = (b*np.sinh(rr*b) - a*np.sinh(rr*a))/rr - (np.cosh(rr*b) - np.cosh(rr*a))/rr**2
    out[sm] = (b*b - a*a)/2; return out
class Paddle:
    """l = distance of hinge below the bottom (l=np.inf: piston; l=0: bottom-hinged flap;
       -h<l<0: hinge at height d=-l above the bottom). f(z) = (z+h+l)/(h+l) on z+h>=d, 0 below."""
    def __init__(self, h, l=np.inf):
        self.h, self.l = h, l; self.d = max(0.0, -l) if np.isfinite(l) else 0.0
    def Lam(self, k):   # int f(z) cosh k(z+h) dz
        h, l, d = self.h, self.l, self.d
        if not np.isfinite(l): return Ic(k, 0, h)
        return (Isc(k, d, h) + l*Ic(k, d, h))/(h+l)
    def c(self, k):     # first-order transfer eta/X (X = paddle displacement at SWL), per mode
        h = self.h; N = (np.sinh(2*k*h) + 2*k*h)/(4*k)
        return np.sinh(k*h)*self.Lam(k)/N
    def Pi(self, k, w, K):  # int cosh K(z+h) [k^2 f C + f' dC/dz] dz, C = cosh k(z+h)/cosh kh
        h, l, d = self.h, self.l, self.d
        if not np.isfinite(l):
            return k*k*np.cosh(K*h)*(w*w - (g*K*np.tanh(K*h)))/(g*(k*k - K*K))
        p, m = k + K, k - K
        fcc = (0.5*(Isc(p, d, h) + Isc(m, d, h)) + l*0.5*(Ic(p, d, h) + Ic(m, d, h)))/(h+l)
        fsc = 0.5*(Is(p, d, h) + Is(m, d, h))/(h+l)      # int sinh k s cosh K s over hinge..SWL, times f'
        return (k*k*fcc + k*fsc)/np.cosh(k*h)
def Hpm(wn, wm, kj, kl, sgn):
    wmm = sgn*wm; klt = sgn*kl          # H- = H+ with wm -> -wm, kl -> -conj(kl) (conj applied by caller)
    ws = wn + wmm
    return ws*(wn*wmm - g*g*kj*klt/(wn*wmm)) + 0.5*(wn**3 + wmm**3) - 0.5*g*g*(kj**2/wn + klt**2/wmm)
def F2(pad, wn, wm, J=100, sgn=+1):
    """Complex transfer F: X2 = Re[ 1/2 sum_n sum_m F Xn Xm e^{i(wn+wm)t} ]   (sgn=+1)
                          X2 = Re[ 1/2 sum_n sum_m F Xn conj(Xm) e^{i(wn-wm)t} ] (sgn=-1, n != m)
       with X1 = Re[ sum_n Xn e^{i wn t} ] the SWL paddle displacement."""
    h = pad.h
    kn = k_modes(wn, h, J); km = k_modes(wm, h, J)
    cn = pad.c(kn); cm = pad.c(km)
    if sgn < 0: km, cm = np.conj(km), np.conj(cm)
    ws = wn + sgn*wm; K = k_prog(abs(ws), h)
    A1 = np.sum(cn*pad.Pi(kn, wn, K)); A2 = np.sum(cm*pad.Pi(km, wm, K))
    KJ, KL = np.meshgrid(kn, km, indexing='ij'); CJ, CL = np.meshgrid(cn, cm, indexing='ij')
    kap = KJ + sgn*KL
    S3 = np.sum(CJ*CL*kap*Hpm(wn, wm, KJ, KL, sgn)/(kap**2 - K*K))
    return (g/(2*wn)*A1 + g/(2*wm)*A2 - sgn*np.cosh(K*h)/g*S3)/(1j*ws*pad.Lam(K))
