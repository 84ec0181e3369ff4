#!/usr/bin/python3
"""Values of the remote-sensing BRDF models at stated geometries, from their closed forms written in angles
(sza, vza, raa) as the papers print them, independently of icobrdf/core/models/kernel_models.cpp (which works
on direction vectors). tests/core/models/test_kernel_models.cpp checks the library against these numbers.

Sources: Lucht, Schaaf & Strahler 2000 (IEEE TGRS 38(2), eqs. 38-46) for the Ross and Li kernels (h/b = 2,
b/r = 1); Rahman, Pinty & Verstraete 1993 (JGR 98(D11), eqs. 4-8) for RPV with the Henyey-Greenstein phase;
Nilson & Kuusk 1989 for the reciprocal Walthall form. Angles in degrees here; the phase angle
cos(xi) = cos(sza) cos(vza) + sin(sza) sin(vza) cos(raa), raa = 0 on the sun's side (hot spot).

Usage: scripts/derive/kernel_values.py   (prints the values with 17 significant digits)
"""
from math import acos, cos, pi, radians, sin, sqrt, tan


def phase(sza, vza, raa):
    return cos(sza) * cos(vza) + sin(sza) * sin(vza) * cos(raa)


def ross(sza, vza, raa, thick=True):
    c = phase(sza, vza, raa)
    xi = acos(c)
    num = (pi / 2 - xi) * c + sin(xi)
    return num / (cos(sza) + cos(vza)) - pi / 4 if thick else num / (cos(sza) * cos(vza)) - pi / 2


def li(sza, vza, raa, sparse=True, hb=2.0, br=1.0):
    ti, tv = atan_scaled(sza, br), atan_scaled(vza, br)
    d2 = tan(ti) ** 2 + tan(tv) ** 2 - 2 * tan(ti) * tan(tv) * cos(raa)
    sec = 1 / cos(ti) + 1 / cos(tv)
    cost = max(-1.0, min(1.0, hb * sqrt(d2 + (tan(ti) * tan(tv) * sin(raa)) ** 2) / sec))
    t = acos(cost)
    o = (t - sin(t) * cost) * sec / pi
    cxi = phase(ti, tv, raa)
    if sparse:
        return o - 1 / cos(ti) - 1 / cos(tv) + 0.5 * (1 + cxi) / cos(ti) / cos(tv)
    return (1 + cxi) / cos(ti) / cos(tv) / (sec - o) - 2


def atan_scaled(theta, br):
    from math import atan
    return atan(br * tan(theta))


def rpv_brf(sza, vza, raa, rho0, k, th, rhoc):
    m = rho0 * (cos(sza) * cos(vza)) ** (k - 1) / (cos(sza) + cos(vza)) ** (1 - k)
    f = (1 - th * th) / (1 + 2 * th * phase(sza, vza, raa) + th * th) ** 1.5
    g = sqrt(tan(sza) ** 2 + tan(vza) ** 2 - 2 * tan(sza) * tan(vza) * cos(raa))
    return m * f * (1 + (1 - rhoc) / (1 + g))


def walthall_brf(sza, vza, raa, a, b, c, d):
    return a * (sza ** 2 + vza ** 2) + b * sza ** 2 * vza ** 2 + c * sza * vza * cos(raa) + d


GEOMETRIES = [(30, 45, 60), (60, 20, 170), (10, 70, 0), (45, 45, 0)]
if __name__ == '__main__':
    for g in GEOMETRIES:
        s, v, r = (radians(x) for x in g)
        print(f'{g}: thick {ross(s, v, r):.17g} thin {ross(s, v, r, False):.17g} sparse {li(s, v, r):.17g} '
              f'dense {li(s, v, r, False):.17g} rpv {rpv_brf(s, v, r, 0.1, 0.8, -0.1, 0.1):.17g} '
              f'walthall {walthall_brf(s, v, r, 0.01, 0.002, -0.01, 0.1):.17g}')
