"""icobrdf.sun_view_directions and icobrdf.kernel_fit on numpy arrays: the geometry convention (raa = 0 on the
sun's side, the hot spot at vza = sza), exact recovery of noiseless Ross-Li weights computed by the numpy kernels
of examples/remote-sensing/make_observations.py (written from the published formulas), and one-line errors."""
import os
import sys

import numpy as np
import pytest

import icobrdf

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "..", "examples", "remote-sensing"))
from make_observations import brf  # noqa: E402

# Noiseless data in the span of the kernels: rounding only (condition ~ 10).
EXACT = 1e-10


def test_hot_spot_and_forward_directions():
    wi, wr = icobrdf.sun_view_directions([30, 30, 30], [30, 30, -30], [0, 180, 0])
    assert np.allclose(wi[0], wr[0], atol=1e-15)                          # raa = 0, vza = sza: the hot spot
    assert np.allclose(wr[1], [-wi[1, 0], -wi[1, 1], wi[1, 2]], atol=1e-15)  # raa = 180: the specular direction
    assert np.allclose(wr[2], wr[1], atol=1e-15)                          # a signed vza turns the azimuth by 180


def test_noiseless_weights_are_recovered():
    rng = np.random.default_rng(3)
    sza, vza, raa = rng.uniform(20, 60, 50), rng.uniform(0, 65, 50), rng.uniform(0, 360, 50)
    values = brf(0.25, 0.12, 0.04, *np.radians([sza, vza, raa]))
    k = icobrdf.kernel_fit(sza, vza, raa, values)
    assert k["determined"]
    assert np.allclose(k["weights"], [0.25, 0.12, 0.04], atol=EXACT)
    assert k["cv_rms"] < EXACT
    ws = k["white_sky_albedo"]
    assert ws["value"] == pytest.approx(0.25 + 0.12 * 0.189184 - 0.04 * 1.377622, abs=1e-4)  # the ATBD's integrals
    assert ws["inflation"] == pytest.approx(ws["u"] @ k["inverse_gram"] @ ws["u"], rel=1e-12)
    assert k["model"].startswith("model:ross-li:iso=")


def test_errors_are_value_errors():
    with pytest.raises(ValueError, match="one length"):
        icobrdf.kernel_fit([30], [20, 10], [0], [0.1])
    with pytest.raises(ValueError, match="zenith"):
        icobrdf.kernel_fit([95], [20], [0], [0.1])
    with pytest.raises(ValueError, match="volume"):
        icobrdf.kernel_fit([30], [20], [0], [0.1], volume="fat")
