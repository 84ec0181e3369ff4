"""icobrdf.Sampler (importance sampling of reflected directions, icobrdf/io/material_sampler.hpp) from numpy.

Expected values are derived here: albedos by Gauss-Legendre quadrature of Source.eval, the pdf's integral by
a midpoint rule, a chi-squared test with expected counts from a fine quadrature of Sampler.pdf. Fixed seeds.
"""
import math

import numpy as np
import pytest

import icobrdf

# Means of draws are compared within 5 standard errors: a false failure has probability 6e-7 (normal mean).
STANDARD_ERRORS = 5.0
# 128 x 256 Gauss-Legendre nodes in (cos theta, phi) integrate f cos of GGX alpha 0.3 to about 1e-9.
ALBEDO_QUADRATURE = 1e-6
# Midpoint rule, 600 x 1200 in (cos theta, phi), of a piecewise-constant pdf at level 3 (656 cells): only
# rectangles cut by cell edges err (about 4 % of them), each by at most its mass with random signs:
# about 1e-4 at one standard deviation; 2e-3 is 20 of those.
PDF_QUADRATURE = 2e-3
# The significance for the chi-squared test.
SIGNIFICANCE = 1e-3


def unit(theta, phi):
    return np.array([math.sin(theta) * math.cos(phi), math.sin(theta) * math.sin(phi), math.cos(theta)])


def uniforms(n, seed):
    rng = np.random.default_rng(seed)
    return rng.random(n), rng.random(n)


def hemisphere_rule(nz, nphi):
    """Directions and weights of Gauss-Legendre in cos(theta) on [0, 1] x Gauss-Legendre in phi on [-pi, pi]."""
    x, w = np.polynomial.legendre.leggauss(nz)
    mu, wmu = 0.5 * (x + 1), 0.5 * w
    y, v = np.polynomial.legendre.leggauss(nphi)
    phi, wphi = math.pi * y, math.pi * v
    MU, PHI = np.meshgrid(mu, phi, indexing="ij")
    st = np.sqrt(1 - MU * MU)
    dirs = np.stack([st * np.cos(PHI), st * np.sin(PHI), MU], axis=-1).reshape(-1, 3)
    return dirs, (wmu[:, None] * wphi[None, :]).reshape(-1)


def midpoint_directions(nz, nphi):
    z = (np.arange(nz) + 0.5) / nz
    phi = -math.pi + (np.arange(nphi) + 0.5) * 2 * math.pi / nphi
    Z, PHI = np.meshgrid(z, phi, indexing="ij")
    st = np.sqrt(1 - Z * Z)
    return np.stack([st * np.cos(PHI), st * np.sin(PHI), Z], axis=-1).reshape(-1, 3)


def chi_square_p_value(chi2, dof):
    """Upper tail of the chi-squared distribution by the Wilson-Hilferty cube-root normal approximation
    (relative error of a few percent in the p-value near 1e-3 for dof > 30)."""
    z = ((chi2 / dof) ** (1 / 3) - (1 - 2 / (9 * dof))) / math.sqrt(2 / (9 * dof))
    return 0.5 * math.erfc(z / math.sqrt(2))


def test_shapes_and_pdf_agree_with_draws():
    s = icobrdf.Sampler(icobrdf.Source("model:ggx:alpha=0.3"), level=3)
    u1, u2 = uniforms(1000, 1)
    wi = unit(math.radians(40), 0.3)
    wr, pdf, weight = s.sample(wi, u1, u2)
    assert wr.shape == (1000, 3) and pdf.shape == (1000,) and weight.shape == (1000, 1)
    assert np.all(np.abs(np.linalg.norm(wr, axis=1) - 1) < 1e-14)
    assert np.all(wr[:, 2] >= 0)
    assert np.array_equal(s.pdf(wi, wr), pdf)


def test_lambert_mean_weight_is_albedo():
    rho = 0.6
    s = icobrdf.Sampler(icobrdf.Source("model:lambert:albedo=0.6"), level=4)
    for theta in (0.0, 45.0, 85.0):
        u1, u2 = uniforms(200000, 2)
        _, _, w = s.sample(unit(math.radians(theta), 0.0), u1, u2)
        w = w[:, 0]
        assert abs(w.mean() - rho) < STANDARD_ERRORS * w.std(ddof=1) / math.sqrt(w.size)


def test_white_furnace_equals_directional_albedo():
    src = icobrdf.Source("model:ggx:alpha=0.3")
    dirs, weights = hemisphere_rule(128, 256)
    for mode in ("centre", "average"):
        s = icobrdf.Sampler(src, level=4, cell_value=mode)
        for theta in (0.0, 30.0, 60.0, 80.0):
            wi = unit(math.radians(theta), 1.0)
            albedo = weights @ (src.eval(np.tile(wi, (dirs.shape[0], 1)), dirs)[:, 0] * dirs[:, 2])
            u1, u2 = uniforms(100000, 3)
            _, _, w = s.sample(wi, u1, u2)
            w = w[:, 0]
            assert np.all(np.isfinite(w))
            assert abs(w.mean() - albedo) < STANDARD_ERRORS * w.std(ddof=1) / math.sqrt(w.size) + ALBEDO_QUADRATURE


def test_pdf_integrates_to_one():
    s = icobrdf.Sampler(icobrdf.Source("model:phong:n=20"), level=3)
    dirs = midpoint_directions(600, 1200)
    for theta in (0.0, 70.0):
        total = s.pdf(unit(math.radians(theta), 0.0), dirs).mean() * 2 * math.pi
        assert abs(total - 1) < PDF_QUADRATURE


def test_chi_squared_against_pdf():
    s = icobrdf.Sampler(icobrdf.Source("model:ggx:alpha=0.3"), level=4)
    nz, nphi, sub = 20, 40, 12
    for theta in (0.0, 50.0, 80.0):
        wi = unit(math.radians(theta), 0.5)
        u1, u2 = uniforms(100000, 4)
        wr, _, _ = s.sample(wi, u1, u2)
        iz = np.minimum((wr[:, 2] * nz).astype(int), nz - 1)
        ip = np.clip(((np.arctan2(wr[:, 1], wr[:, 0]) + math.pi) / (2 * math.pi) * nphi).astype(int), 0, nphi - 1)
        observed = np.bincount(iz * nphi + ip, minlength=nz * nphi).astype(float)
        fine = s.pdf(wi, midpoint_directions(nz * sub, nphi * sub)).reshape(nz, sub, nphi, sub)
        expected = fine.sum(axis=(1, 3)).reshape(-1) * (1 / (nz * sub)) * (2 * math.pi / (nphi * sub)) * u1.size
        keep = expected >= 5  # pool the bins below 5 expected draws
        e = np.append(expected[keep], expected[~keep].sum())
        o = np.append(observed[keep], observed[~keep].sum())
        if e[-1] == 0:
            assert o[-1] == 0
            e, o = e[:-1], o[:-1]
        chi2 = ((o - e) ** 2 / e).sum()
        assert chi_square_p_value(chi2, e.size - 1) > SIGNIFICANCE, (theta, chi2, e.size - 1)


def test_refusals_are_python_exceptions():
    u1, u2 = uniforms(4, 5)
    with pytest.raises(RuntimeError, match="at every one of the 168 cell centres of level 2 .*delta part"):
        icobrdf.Sampler(icobrdf.Source("model:mirror"), level=2).sample(unit(0.3, 0.0), u1, u2)
    s = icobrdf.Sampler(icobrdf.Source("model:lambert"), level=2)
    with pytest.raises(ValueError, match="expected uniform numbers in"):
        s.sample(unit(0.3, 0.0), u1 + 1, u2)
    with pytest.raises(ValueError, match="expected a unit vector"):
        s.sample(np.array([0.0, 0.0, 2.0]), u1, u2)
    with pytest.raises(ValueError, match="cell_value"):
        icobrdf.Sampler(icobrdf.Source("model:lambert"), cell_value="corner")
