#!/usr/bin/python3
"""Multi-angle observations of a surface whose BRF is a named Ross-Li kernel model, with noise.

Writes a CSV in the remote-sensing layout `sza,vza,raa,brf` (degrees; raa = 0 on the sun's side, where the hot
spot lies) that `icobrdf fit FILE.csv` reads as it is. The kernels are written here from their published closed
forms (Lucht, Schaaf & Strahler 2000, IEEE TGRS 38(2), eqs. 38-46; Ross-Thick and Li-Sparse-R with MODIS's crown
shape h/b = 2, b/r = 1), independently of the library:

    BRF = iso + vol K_vol(sza, vza, raa) + geo K_geo(sza, vza, raa)

The white-sky albedo of the truth is iso + vol 0.189184 + geo (-1.377622), the kernels' bihemispherical integrals
of the MODIS BRDF/albedo ATBD (Strahler et al. 1999, Table 1); the script prints it.

Geometry: solar zenith uniform in [SZA_MIN, SZA_MAX] (15..70 deg by default: a season's range at mid latitudes),
view zenith uniform in [0, VZA_MAX] (70 deg, MISR's outermost cameras), relative azimuth uniform in [0, 360); noise: each BRF times (1 + NOISE * N(0, 1)), a relative error of NOISE (1% by default). A fixed seed
gives the same file on every machine (numpy's PCG64).

Usage: make_observations.py [-n 200] [--seed 7] [--iso 0.25 --vol 0.12 --geo 0.04] [--noise 0.01] -o obs.csv
"""
import argparse

import numpy as np

ROSS_THICK_WHITE_SKY = 0.189184   # MODIS BRDF/albedo ATBD, Table 1
LI_SPARSE_WHITE_SKY = -1.377622


def phase_cosine(sza, vza, raa):
    return np.cos(sza) * np.cos(vza) + np.sin(sza) * np.sin(vza) * np.cos(raa)


def ross_thick(sza, vza, raa):
    c = np.clip(phase_cosine(sza, vza, raa), -1.0, 1.0)
    xi = np.arccos(c)
    return ((np.pi / 2 - xi) * c + np.sin(xi)) / (np.cos(sza) + np.cos(vza)) - np.pi / 4


def li_sparse(sza, vza, raa, hb=2.0, br=1.0):
    ti, tv = np.arctan(br * np.tan(sza)), np.arctan(br * np.tan(vza))
    d2 = np.tan(ti) ** 2 + np.tan(tv) ** 2 - 2 * np.tan(ti) * np.tan(tv) * np.cos(raa)
    sec = 1 / np.cos(ti) + 1 / np.cos(tv)
    cost = np.clip(hb * np.sqrt(d2 + (np.tan(ti) * np.tan(tv) * np.sin(raa)) ** 2) / sec, -1.0, 1.0)
    t = np.arccos(cost)
    overlap = (t - np.sin(t) * cost) * sec / np.pi
    return overlap - sec + 0.5 * (1 + phase_cosine(ti, tv, raa)) / np.cos(ti) / np.cos(tv)


def brf(iso, vol, geo, sza, vza, raa):
    """BRF of the Ross-Thick + Li-Sparse-R model; angles in radians."""
    return iso + vol * ross_thick(sza, vza, raa) + geo * li_sparse(sza, vza, raa)


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument('-n', type=int, default=200, help='observations (default 200)')
    p.add_argument('--seed', type=int, default=7)
    p.add_argument('--iso', type=float, default=0.25)
    p.add_argument('--vol', type=float, default=0.12)
    p.add_argument('--geo', type=float, default=0.04)
    p.add_argument('--noise', type=float, default=0.01, help='relative noise (default 0.01)')
    p.add_argument('--sza', type=float, nargs=2, default=(15.0, 70.0), metavar=('MIN', 'MAX'))
    p.add_argument('--vza-max', type=float, default=70.0)
    p.add_argument('-o', '--output', required=True)
    a = p.parse_args()
    rng = np.random.default_rng(a.seed)
    sza = rng.uniform(a.sza[0], a.sza[1], a.n)
    vza = rng.uniform(0.0, a.vza_max, a.n)
    raa = rng.uniform(0.0, 360.0, a.n)
    truth = brf(a.iso, a.vol, a.geo, *np.radians([sza, vza, raa]))
    noisy = truth * (1 + a.noise * rng.standard_normal(a.n))
    with open(a.output, 'w') as f:
        f.write(f'# Ross-Thick + Li-Sparse-R iso={a.iso} vol={a.vol} geo={a.geo}, relative noise {a.noise}, seed {a.seed}\n')
        f.write('# written by examples/remote-sensing/make_observations.py\n')
        f.write('sza,vza,raa,brf\n')
        for row in zip(sza, vza, raa, noisy):
            f.write('{:.4f},{:.4f},{:.4f},{:.6f}\n'.format(*row))
    white = a.iso + a.vol * ROSS_THICK_WHITE_SKY + a.geo * LI_SPARSE_WHITE_SKY
    print(f'{a.output}: {a.n} observations; truth white-sky albedo {white:.6f}')


if __name__ == '__main__':
    main()
