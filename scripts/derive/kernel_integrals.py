#!/usr/bin/python3
"""The Ross-Thick and Li-Sparse-R kernels' albedo integrals by numpy quadrature, from the kernels' closed forms in
angles (scripts/derive/kernel_values.py), independently of icobrdf/core/fit/kernel_fit.cpp:

    black-sky  h_k(sza) = (1/pi) integral K_k(sza, vza, raa) cos(vza) dOmega_v
    white-sky  H_k = 2 integral_0^1 h_k(mu) mu dmu

and their distance from the MODIS ATBD's cubic fits h_k ~ g0 + g1 sza^2 + g2 sza^3 (Strahler et al. 1999,
Table 1) over 0..70 deg, which sets kBlackSkyPolynomialTol of tests/core/fit/test_kernel_fit.cpp. One run printed
    thick: largest |quadrature - ATBD cubic| over 0..70 deg: 0.0184
    sparse: largest |quadrature - ATBD cubic| over 0..70 deg: 0.00628
(the cubic is a fit: at sza = 0 the Ross-Thick integral is -0.02108 by a 1-D integral of its closed form, the cubic
gives -0.00757).
Quadrature: Gauss-Legendre in cos(vza) (64 nodes), midpoints in raa over [0, pi] (256; K is even in raa).

Usage: scripts/derive/kernel_integrals.py
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from kernel_values import li, ross  # noqa: E402

ATBD = {'thick': (-0.007574, -0.070987, 0.307588), 'sparse': (-1.284909, -0.166314, 0.041840)}


def black_sky(sza, kernel, n_mu=128, n_phi=1024):
    x, w = np.polynomial.legendre.leggauss(n_mu)
    mu, wmu = 0.5 * (x + 1), 0.5 * w
    phi = (np.arange(n_phi) + 0.5) * np.pi / n_phi
    total = 0.0
    for m, wm in zip(mu, wmu):
        vza = np.arccos(m)
        vals = np.array([kernel(sza, vza, p) for p in phi])
        total += wm * m * vals.sum() * np.pi / n_phi
    return 2 * total / np.pi


def main():
    kernels = {'thick': lambda s, v, r: ross(s, v, r), 'sparse': lambda s, v, r: li(s, v, r)}
    for name, k in kernels.items():
        worst = 0.0
        for deg in range(0, 71, 5):
            s = np.radians(deg)
            g0, g1, g2 = ATBD[name]
            h = black_sky(s, k, 64, 256)
            worst = max(worst, abs(h - (g0 + g1 * s * s + g2 * s ** 3)))
        print(f'{name}: largest |quadrature - ATBD cubic| over 0..70 deg: {worst:.3g}')


if __name__ == '__main__':
    main()
