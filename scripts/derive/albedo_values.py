#!/usr/bin/python3
"""Black-sky albedo integrals of the MODIS kernels at solar zeniths 0, 10, ..., 80 degrees, by SciPy's adaptive
quadrature (QUADPACK) of the kernels' closed forms in angles (scripts/derive/kernel_values.py), independently of
icobrdf/core/models/albedo_quadrature.cpp (a fixed product Gauss-Legendre rule on direction vectors).
tests/core/models/test_albedo_quadrature.cpp checks the library against these numbers.

    h(s) = (1/pi) int_0^{2 pi} int_0^{pi/2} K(s, v, raa) cos(v) sin(v) dv draa       (f = K / pi)

The kernels are even in raa, so h = (2/pi) int_0^pi int_0^{pi/2}. The inner integral (over raa) is split at
nothing (raa = 0, the hot-spot side, is an end); the outer one (over v) at v = s, where the hot spot is. The
requested absolute error is 1e-10 per level; QUADPACK's estimates stay below 1e-8 (printed).

Usage: scripts/derive/albedo_values.py   (prints h_vol, h_geo with 12 significant digits)
"""
from math import cos, pi, radians, sin

from scipy.integrate import quad

from kernel_values import li, ross

TOL = 1e-10


def black_sky(kernel, s):
    def over_raa(v):
        val, _ = quad(lambda r: kernel(s, v, r), 0.0, pi, epsabs=TOL, epsrel=TOL, limit=400)
        return val * cos(v) * sin(v)
    pts = [s] if 0.0 < s < pi / 2 else None
    val, err = quad(over_raa, 0.0, pi / 2, points=pts, epsabs=TOL, epsrel=TOL, limit=400)
    return 2.0 * val / pi, 2.0 * err / pi


if __name__ == '__main__':
    for deg in range(0, 90, 10):
        s = radians(deg)
        hv, ev = black_sky(ross, s)
        hg, eg = black_sky(li, s)
        print(f'{{{deg}, {hv:.12g}, {hg:.12g}}},  // quadpack error estimates {ev:.1e}, {eg:.1e}')
