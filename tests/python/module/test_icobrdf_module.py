"""The Python module `icobrdf` (python/module.cpp), with values derived independently here.

Run by CTest as `python3 -m pytest` with PYTHONPATH=<build>/python.
"""
import math
import os
import tempfile

import numpy as np
import pytest

import icobrdf

# Tolerances, each with its reason.
EXACT = 1e-12          # closed forms evaluated in double precision (a few roundings)
QUADRATURE = 1e-9      # a 96 x 192 Gauss-Legendre x trapezoid rule on smooth integrands over the hemisphere
GRID_PROJECTION = 1e-6 # a level-3 grid's cell cubature of a constant: the solid angles are exact, the basis
                       # averages carry the Gram error of order 2 at level 3 (below 1e-3) only on modes a
                       # constant does not excite


def unit(theta, phi):
    return np.stack([np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi), np.cos(theta)], axis=-1)


def random_pairs(n, seed=7):
    rng = np.random.default_rng(seed)
    # uniform on the hemisphere: cos(theta) uniform in [0, 1]
    def draw():
        z = rng.uniform(0, 1, n)
        phi = rng.uniform(0, 2 * math.pi, n)
        r = np.sqrt(1 - z * z)
        return np.stack([r * np.cos(phi), r * np.sin(phi), z], axis=1)
    return draw(), draw()


def test_lambert_is_albedo_over_pi():
    wi, wr = random_pairs(1000)
    f = icobrdf.Source("model:lambert:albedo=0.6").eval(wi, wr)
    assert f.shape == (1000, 1)
    assert np.max(np.abs(f - 0.6 / math.pi)) < EXACT


def test_hemisphere_basis_is_orthonormal_by_independent_quadrature():
    # Gauss-Legendre in cos(theta) on [0, 1] (dOmega = dcos dphi), trapezoid in phi (periodic: exact for
    # trigonometric polynomials of degree < 192).
    x, w = np.polynomial.legendre.leggauss(96)
    mu, wmu = 0.5 * (x + 1), 0.5 * w
    nphi = 192
    phi = 2 * math.pi * np.arange(nphi) / nphi
    MU, PHI = np.meshgrid(mu, phi, indexing="ij")
    dirs = unit(np.arccos(MU), PHI).reshape(-1, 3)
    weights = (wmu[:, None] * np.full(nphi, 2 * math.pi / nphi)[None, :]).reshape(-1)
    order = 6
    K = icobrdf.hemisphere_basis(order, dirs)
    assert K.shape == (dirs.shape[0], icobrdf.basis_count(order)) == (dirs.shape[0], 28)
    G = K.T @ (weights[:, None] * K)
    assert np.max(np.abs(G - np.eye(28))) < QUADRATURE


def test_fit_of_lambert_has_one_coefficient_two_albedo():
    # f = a / pi; K_0 = 1 / sqrt(2 pi); C_00 = (a/pi) (integral K_0 dOmega)^2 = (a/pi) 2 pi = 2a, all else 0.
    a = 0.8
    s = icobrdf.fit(icobrdf.Source(f"model:lambert:albedo={a}"), level=3, order=4)
    assert s.order == 4 and s.level == 3 and not s.cosine
    (c,) = s.coefficients
    assert c.shape == (15, 15)
    assert abs(c[0, 0] - 2 * a) < GRID_PROJECTION
    c[0, 0] = 0
    assert np.max(np.abs(c)) < GRID_PROJECTION
    wi, wr = random_pairs(50)
    assert np.max(np.abs(s.eval(wi, wr) - a / math.pi)) < GRID_PROJECTION


def test_lut_projection_and_reconstruction_of_a_constant():
    a = 0.5
    grid = icobrdf.Grid.equal_area(3)
    assert grid.cells == 10 * 4**3 + 2**4
    assert abs(grid.solid_angles.sum() - 2 * math.pi) < EXACT
    (F,) = icobrdf.lut(f"model:lambert:albedo={a}", grid)
    assert F.shape == (grid.cells, grid.cells)
    assert np.max(np.abs(F - a / math.pi)) < EXACT
    basis = icobrdf.DiscreteBasis(grid, 4)
    basis.check_supported()
    P = icobrdf.Projection(basis)
    C = icobrdf.project(P, F)
    assert abs(C[0, 0] - 2 * a) < GRID_PROJECTION
    R = icobrdf.reconstruct(basis, C)
    assert np.max(np.abs(R - a / math.pi)) < GRID_PROJECTION
    S = icobrdf.smooth(basis, P, F)
    assert np.max(np.abs(S - a / math.pi)) < GRID_PROJECTION


def test_reciprocity_of_helmholtz_modes():
    wi, wr = random_pairs(200)
    m1 = icobrdf.helmholtz_modes(4, wi, wr)
    m2 = icobrdf.helmholtz_modes(4, wr, wi)
    assert np.max(np.abs(m1 - m2)) < EXACT  # symmetrized products: reciprocal by construction


def test_spectrum_file_round_trip_and_bank_listing():
    s = icobrdf.fit(icobrdf.Source("model:ggx:alpha=0.4"), level=3, order=6)
    with tempfile.TemporaryDirectory() as d:
        path = os.path.join(d, "g.h5")
        icobrdf.write_spectrum(path, s, "glossy")
        assert icobrdf.bank_materials(path) == ["glossy"]
        back = icobrdf.read_spectrum(path, "glossy")
        assert back.order == 6
        assert np.array_equal(back.coefficients[0], s.coefficients[0])
        src = icobrdf.Source(path + "#glossy")
        wi, wr = random_pairs(20)
        assert np.max(np.abs(src.eval(wi, wr) - s.eval(wi, wr))) < EXACT


def test_errors_are_python_exceptions():
    with pytest.raises(ValueError, match="must be in"):
        icobrdf.Source("model:ggx:alpha=-1")
    with pytest.raises(ValueError, match=r"expected an \(n, 3\) array"):
        icobrdf.Source("model:lambert").eval(np.zeros((4, 2)), np.zeros((4, 2)))
    with pytest.raises(ValueError, match="rows"):
        icobrdf.Source("model:lambert").eval(np.array([[0, 0, 1.0]]), np.array([[0, 0, 1.0], [0, 0, 1.0]]))
    with pytest.raises((OSError, RuntimeError)):
        icobrdf.read_spectrum("/nonexistent/x.h5")
    with pytest.raises(RuntimeError, match="largest supported order"):
        icobrdf.fit(icobrdf.Source("model:lambert"), level=1, order=8)
