import numpy as np
from schaffer import *
h = 0.4
def surf(w, k, P):   # surface coefficients of one mode: u, w, phi_t, d/dz(phi_tt+g phi_z), phi_zt
    Wv = P*k*np.tanh(k*h)
    return dict(U=-1j*k*P, W=Wv, T=1j*w*P, D=P*(g*k*k - w**4/g), Wt=1j*w*Wv)
def eta2(w1, a1, w2, a2, sign):
    k1, k2 = k_prog(w1, h), k_prog(w2, h)
    A = surf(w1, k1, 1j*g*a1/w1); Bm = surf(w2, k2, 1j*g*a2/w2)
    if sign < 0: Bm = {q: np.conj(v) for q, v in Bm.items()}
    ws = w1 + sign*w2; kap = k1 + sign*k2
    sq = A['U']*Bm['U'] + A['W']*Bm['W']
    Q = -1j*ws*sq + 0.5*(A['T']*Bm['D'] + Bm['T']*A['D'])/g
    B = Q/(g*kap*np.tanh(kap*h) - ws*ws)
    return -(1/g)*(1j*ws*B + 0.5*sq - 0.5*(A['T']*Bm['Wt'] + Bm['T']*A['Wt'])/g)
# regular: self-interaction = 1/2 of distinct-pair formula
for T in [1.0, 1.5, 3.0]:
    w = 2*np.pi/T; k = k_prog(w, h); A = 0.02
    e = 0.5*eta2(w, A, w, A, +1)
    st = k*A*A/4*np.cosh(k*h)*(2+np.cosh(2*k*h))/np.sinh(k*h)**3
    print('T', T, 'eta22 from Q', e, ' Stokes', st)
# subharmonic vs Hasselmann-type closed form (as quoted on fengyanshi.github.io, IG theory page)
w1, w2 = 2*np.pi*0.7, 2*np.pi*0.6
k1, k2 = k_prog(w1, h), k_prog(w2, h); kij = k1-k2
C = (w1-w2)*(w1*w1*w2*w2/g**2 + k1*k2) - 0.5*(w1*k2**2/np.cosh(k2*h)**2 - w2*k1**2/np.cosh(k1*h)**2)
Dij = -g*k1*k2/(2*w1*w2) + (w1*w1 - w1*w2 + w2*w2)/(2*g) - C*g*(w1-w2)/(w1*w2*(g*kij*np.tanh(kij*h) - (w1-w2)**2))
print('sub: eta2-/(a1 a2) from Q', eta2(w1, 1.0, w2, 1.0, -1), ' Hasselmann-type D', Dij)
sup_ref = None
