#!/usr/bin/python3
"""Values of the Hapke model at stated geometries, written in angles (i, e, psi) from the published formulas
(Hapke 2012, "Theory of Reflectance and Emittance Spectroscopy", 2nd ed., eqs. 12.46-12.55: the roughness
functions chi, E1, E2, eta, the effective cosines and the shadowing S; the shadow-hiding surge
B(g) = B0 / (1 + tan(g/2)/h)), with isotropic particles (p = 1) and Chandrasekhar's exact H function solved here
by its own Nystrom iteration, independently of icobrdf/core/models/hapke.cpp (which works on direction vectors
and tabulates H). tests/core/models/test_hapke_full.cpp checks the library against these numbers.

    f = r / cos(i),  r = w/(4 pi) mu0e/(mu0e + mue) [(1 + B) + H(mu0e) H(mue) - 1] S(i, e, psi)

psi is the azimuth between the planes of incidence and emergence (0: the sun's side, the hot spot at e = i).
H: 1/H(mu) = sqrt(1 - w) + (w/2) integral_0^1 mu' H(mu') / (mu + mu') dmu', on mu' = t^2 with 400 Gauss-Legendre
nodes in t, iterated to a fixed point (converged to 1e-15), then evaluated at mu by the same formula: accurate to
about 1e-10 for mu >= 0.05.

Usage: scripts/derive/hapke_values.py   (prints f with 12 significant digits)
"""
from math import acos, cos, exp, pi, radians, sin, sqrt, tan

import numpy as np


def h_function(w):
    x, wt = np.polynomial.legendre.leggauss(400)
    t, wt = 0.5 * (x + 1), 0.5 * wt
    mu_k, weight_k = t * t, wt * 2 * t  # dmu = 2 t dt
    h = np.ones_like(mu_k)
    for _ in range(20000):
        new = 1 / (sqrt(1 - w) + 0.5 * w * (weight_k * mu_k * h / (mu_k[:, None] + mu_k)).sum(axis=1))
        if np.max(np.abs(new - h)) < 1e-15:
            h = new
            break
        h = new
    return lambda mu: 1 / (sqrt(1 - w) + 0.5 * w * float((weight_k * mu_k * h / (mu + mu_k)).sum()))


def hapke_f(i, e, psi, w, b0, hw, theta_bar, H):
    cg = cos(i) * cos(e) + sin(i) * sin(e) * cos(psi)
    g = acos(max(-1.0, min(1.0, cg)))
    b = b0 / (1 + tan(g / 2) / hw)
    if theta_bar == 0:
        mu0e, mue, s = cos(i), cos(e), 1.0
    else:
        tb = tan(theta_bar)
        chi = 1 / sqrt(1 + pi * tb * tb)
        e1 = lambda x: exp(-2 / (pi * tb * tan(x))) if x > 0 else 0.0
        e2 = lambda x: exp(-1 / (pi * tb * tb * tan(x) ** 2)) if x > 0 else 0.0
        eta = lambda x: chi * (cos(x) + sin(x) * tb * e2(x) / (2 - e1(x)))
        f = exp(-2 * tan(psi / 2))
        s2 = sin(psi / 2) ** 2
        if i <= e:
            d = 2 - e1(e) - psi / pi * e1(i)
            mu0e = chi * (cos(i) + sin(i) * tb * (cos(psi) * e2(e) + s2 * e2(i)) / d)
            mue = chi * (cos(e) + sin(e) * tb * (e2(e) - s2 * e2(i)) / d)
            s = mue / eta(e) * cos(i) / eta(i) * chi / (1 - f + f * chi * cos(i) / eta(i))
        else:
            d = 2 - e1(i) - psi / pi * e1(e)
            mu0e = chi * (cos(i) + sin(i) * tb * (e2(i) - s2 * e2(e)) / d)
            mue = chi * (cos(e) + sin(e) * tb * (cos(psi) * e2(i) + s2 * e2(e)) / d)
            s = mue / eta(e) * cos(i) / eta(i) * chi / (1 - f + f * chi * cos(e) / eta(e))
    r = w / (4 * pi) * mu0e / (mu0e + mue) * ((1 + b) + H(mu0e) * H(mue) - 1) * s
    return r / cos(i)


# (w, b0, h, theta-bar deg) and geometries (i, e, psi) in degrees.
PARAMETERS = [(0.6, 0.8, 0.06, 20.0), (0.9, 0.0, 0.05, 35.0), (0.3, 1.0, 0.1, 0.0)]
GEOMETRIES = [(30, 30, 0), (30, 60, 0), (60, 30, 0), (45, 20, 120), (10, 70, 180), (50, 50, 90), (0, 40, 0)]
if __name__ == '__main__':
    for w, b0, hw, tbar in PARAMETERS:
        H = h_function(w)
        vals = [hapke_f(*(radians(a) for a in g), w, b0, hw, radians(tbar), H) for g in GEOMETRIES]
        print(f'w={w} b0={b0} h={hw} theta={tbar}: ' + ', '.join(f'{v:.12g}' for v in vals))
