"""Albedos from Python (python/albedo_binding.cpp): of a Source, a SOURCE text, a Python function and numpy values
at the rule's nodes, against closed forms derived here and the MODIS ATBD's white-sky kernel integrals.

Run by CTest as `python3 -m pytest` with PYTHONPATH=<build>/python.
"""
import math

import numpy as np
import pytest

import icobrdf

EXACT = 1e-12         # smooth closed forms through the Gauss-Legendre panels: a few roundings of ~1e4 terms
LOG_ENDPOINT = 1e-9   # Lommel-Seeliger's white sky: the outer rule meets mu ln(mu) at grazing (measured 3e-10)
ATBD = 1e-4           # the ATBD prints 6 decimals; its Li-Sparse-R value is 3.6e-5 off the formula's integral


def lommel_seeliger(wi, wr, w=0.8):
    """f = w / (4 pi (mu_i + mu_r)), written here from its definition."""
    return w / (4 * math.pi * (wi[:, 2] + wr[:, 2]))


def test_source_methods_and_module_functions_agree_on_lambert():
    src = icobrdf.Source("model:lambert:albedo=0.45")
    a = src.black_sky_albedo([0, 30, 89.5])
    assert a.shape == (3, 1)
    np.testing.assert_allclose(a, 0.45, atol=EXACT)
    np.testing.assert_allclose(src.white_sky_albedo(), [0.45], atol=EXACT)
    np.testing.assert_allclose(icobrdf.black_sky_albedo("model:lambert:albedo=0.45", [60]), [[0.45]], atol=EXACT)


def test_a_python_function_gives_the_lommel_seeliger_closed_forms():
    # a(mu_s) = (w/2)(1 - mu_s ln(1 + 1/mu_s)); A = (2w/3)(1 - ln 2).
    w = 0.8
    s = np.array([0.0, 25.0, 70.0, 88.0])
    a = icobrdf.black_sky_albedo(lommel_seeliger, s, isotropic=True)
    mu = np.cos(np.radians(s))
    np.testing.assert_allclose(a[:, 0], 0.5 * w * (1 - mu * np.log1p(1 / mu)), atol=EXACT)
    A = icobrdf.white_sky_albedo(lommel_seeliger, isotropic=True)
    assert abs(A[0] - 2 * w / 3 * (1 - math.log(2))) < LOG_ENDPOINT


def test_numpy_values_at_the_nodes_give_the_albedos():
    wi, wr, weights = icobrdf.albedo_nodes(40.0)
    assert wi.shape == wr.shape == (weights.size, 3)
    assert abs(weights.sum() - math.pi) < EXACT
    mu = math.cos(math.radians(40.0))
    assert abs(weights @ lommel_seeliger(wi, wr) - 0.4 * (1 - mu * math.log1p(1 / mu))) < EXACT
    wi, wr, weights = icobrdf.white_sky_nodes()
    assert abs(weights @ lommel_seeliger(wi, wr) - 1.6 / 3 * (1 - math.log(2))) < LOG_ENDPOINT
    # Three channels: (n, 3) values give one albedo per column.
    rgb = np.stack([np.full(weights.size, r / math.pi) for r in (0.1, 0.2, 0.3)], axis=1)
    np.testing.assert_allclose(weights @ rgb, [0.1, 0.2, 0.3], atol=EXACT)


def test_a_multichannel_function_and_the_kernels():
    f = lambda wi, wr: np.stack([np.full(len(wi), 0.3 / math.pi), 0.7 / math.pi * np.ones(len(wi))], axis=1)
    np.testing.assert_allclose(icobrdf.white_sky_albedo(f, channels=2, sun_polar_nodes=4), [0.3, 0.7], atol=EXACT)
    assert abs(icobrdf.white_sky_albedo("model:ross-li:iso=0,vol=1,geo=0")[0] - 0.189184) < ATBD
    assert abs(icobrdf.white_sky_albedo("model:ross-li:iso=0,vol=0,geo=1")[0] - -1.377622) < ATBD


def test_bad_arguments_raise_value_error():
    with pytest.raises(ValueError, match="solar zenith"):
        icobrdf.black_sky_albedo("model:lambert", [91])
    with pytest.raises(ValueError, match="polar_nodes"):
        icobrdf.albedo_nodes(10.0, polar_nodes=0)
    with pytest.raises(ValueError, match="must return"):
        icobrdf.black_sky_albedo(lambda wi, wr: np.zeros(3), [10], isotropic=True)
    with pytest.raises(ValueError, match="expected a Source"):
        icobrdf.white_sky_albedo(3.5)
