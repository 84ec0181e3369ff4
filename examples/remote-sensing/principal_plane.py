#!/usr/bin/python3
"""Albedos and a principal-plane plot of the two fits `icobrdf fit` made of the observations.

Reads the fit's JSON report (`icobrdf fit OBS.csv --json -o FIT.h5 > FIT.json`), evaluates the Koenderink-van Doorn
fit (FIT.h5) and the kernel fit (its model SOURCE) with `icobrdf eval ... --at PAIRS.csv` in the remote-sensing
layout sza,vza,raa, and prints

- the white-sky albedo of the truth (the ATBD's kernel integrals), of the kernel fit (from the report, with its
  weight of determination) and of the modes (a Gauss-Legendre x midpoint quadrature of the fitted f:
  (1/pi) integral integral f cos(theta_i) cos(theta_r) dOmega_i dOmega_r);
- the principal-plane BRF at the solar zenith SZA: truth, both fits and the observations within 15 deg of the
  plane and 5 deg of SZA, plotted to PNG with matplotlib (Agg). The hot spot lies at vza = +SZA (raa = 0).

Usage: principal_plane.py FIT.json FIT.h5 OBS.csv --icobrdf PATH [--sza 40] [--truth iso,vol,geo] -o PLOT.png
"""
import argparse
import json
import os
import subprocess
import tempfile

import numpy as np

from make_observations import ROSS_THICK_WHITE_SKY, LI_SPARSE_WHITE_SKY, brf


def evaluate(icobrdf, source, sza, vza, raa):
    """pi f of SOURCE at the geometries (degrees): BRF."""
    with tempfile.NamedTemporaryFile('w', suffix='.csv', delete=False) as f:
        f.write('sza,vza,raa\n')
        for row in zip(sza, vza, raa):
            f.write('{:.10g},{:.10g},{:.10g}\n'.format(*row))
        path = f.name
    try:
        out = subprocess.run([icobrdf, 'eval', source, '--at', path], check=True, capture_output=True, text=True).stdout
    finally:
        os.remove(path)
    return np.pi * np.array([float(x) for x in out.split()[1:]])


def white_sky_of(icobrdf, source, n_mu=16, n_phi=32):
    """(1/pi) integral integral f mu_i mu_r: Gauss-Legendre in mu, midpoints in the azimuth (phi_i = 0 and raa;
    an isotropic fit depends on raa only, and the modes' azimuthal orders are below n_phi)."""
    x, w = np.polynomial.legendre.leggauss(n_mu)
    mu, w = 0.5 * (x + 1), 0.5 * w
    raa = (np.arange(n_phi) + 0.5) * 360.0 / n_phi
    zi, zr, r = np.meshgrid(np.degrees(np.arccos(mu)), np.degrees(np.arccos(mu)), raa, indexing='ij')
    weight = np.broadcast_to((w * mu)[:, None, None] * (w * mu)[None, :, None] * (2 * np.pi) * (2 * np.pi / n_phi), zi.shape)
    f = evaluate(icobrdf, source, zi.ravel(), zr.ravel(), r.ravel()) / np.pi
    return float((f * weight.ravel()).sum() / np.pi)


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument('report')
    p.add_argument('spectrum')
    p.add_argument('observations')
    p.add_argument('--icobrdf', required=True)
    p.add_argument('--sza', type=float, default=40.0)
    p.add_argument('--truth', default='0.25,0.12,0.04')
    p.add_argument('-o', '--output', required=True)
    a = p.parse_args()
    report = json.load(open(a.report))
    iso, vol, geo = (float(x) for x in a.truth.split(','))
    k = report['kernel_fit']
    ws = next(q for q in k['quantities'] if q['name'] == 'white-sky albedo')
    truth_ws = iso + vol * ROSS_THICK_WHITE_SKY + geo * LI_SPARSE_WHITE_SKY
    modes_ws = white_sky_of(a.icobrdf, a.spectrum)
    print(f"white-sky albedo: truth {truth_ws:.5f}, kernel fit {ws['value'][0]:.5f} +- {ws['sigma'][0]:.5f} "
          f"(1/WoD {ws['inflation']:.3g}), modes (order {report['order']}) {modes_ws:.5f}")
    print(f"CV RMS (1/sr): kernels {k['cv_rms']:.4g}, modes {report['sample_fit']['cv_rms']:.4g}: "
          f"the held-out samples support the {k['supported']}")

    vza = np.linspace(-75, 75, 301)
    sza = np.full_like(vza, a.sza)
    raa = np.zeros_like(vza)  # signed vza: negative = the forward side
    truth = brf(iso, vol, geo, np.radians(a.sza), np.radians(np.abs(vza)), np.where(vza >= 0, 0.0, np.pi))
    modes = evaluate(a.icobrdf, a.spectrum, sza, vza, raa)
    kernels = evaluate(a.icobrdf, k['weights'][0]['model'], sza, vza, raa)
    lines = [l.strip() for l in open(a.observations) if l.strip() and not l.startswith('#')]
    names = lines[0].split(',')
    table = np.array([[float(x) for x in l.split(',')] for l in lines[1:]])
    obs = {n: table[:, k] for k, n in enumerate(names)}
    rel = np.mod(obs['raa'], 360.0)
    near = (np.abs(obs['sza'] - a.sza) <= 5) & ((np.minimum(rel, 360 - rel) <= 15) | (np.abs(rel - 180) <= 15))
    signed = np.where(np.abs(rel - 180) <= 15, -obs['vza'], obs['vza'])
    peak = vza[vza >= 0][np.argmax(modes[vza >= 0][: np.searchsorted(vza[vza >= 0], 65.0)])]
    print(f"principal plane at sza {a.sza:g}: the modes' maximum over vza 0..65 (sun's side) at {peak:.1f} deg "
          f"(hot spot of the data: {a.sza:g})")

    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(7, 4.2), dpi=120)
    ax.plot(vza, truth, 'k-', lw=2, label=f'truth ross-li iso={iso} vol={vol} geo={geo}')
    ax.plot(vza, kernels, 'C1--', label='kernel fit (3 weights)')
    ax.plot(vza, modes, 'C0-', label=f"Koenderink-van Doorn modes, order {report['order']}")
    ax.plot(signed[near], obs['brf'][near], 'o', color='C2', ms=4, label='observations near the plane')
    ax.axvline(a.sza, color='grey', lw=0.8, ls=':')
    ax.text(a.sza, ax.get_ylim()[0], ' hot spot', color='grey', va='bottom')
    ax.set_xlabel('view zenith (deg): < 0 forward (raa 180), > 0 the sun\'s side (raa 0)')
    ax.set_ylabel('BRF')
    ax.set_title(f'principal plane, sza = {a.sza:g} deg')
    ax.legend(fontsize=8, loc='upper left')
    fig.tight_layout()
    fig.savefig(a.output)
    print(f'{a.output}: principal-plane BRF')


if __name__ == '__main__':
    main()
