"""Every stored representation through the Python objects that consume a stored material.

Three small banks are built here from one glossy model (its lobe too narrow for modes of order 4 to meet
the target, so that "hybrid" is chosen where allowed), each allowed one representation (modes, a half-angle
lobe alone, the hybrid of the two). Source, Sampler and the albedo functions take every representation and
agree with Source.eval; read_spectrum returns a Spectrum (modes alone) and therefore refuses a material with
a lobe in one line naming its representation, so that neither an f = 0 object nor a hybrid's modes part is
ever handed out (or written back by write_spectrum) as the material. The CLI's consumers are enumerated in
tests/cli/test_representations.cpp.
"""
import math
import os
import tempfile

import numpy as np
import pytest

import icobrdf

# Means of Monte Carlo weights are compared within 5 standard errors (a false failure: probability 6e-7).
STANDARD_ERRORS = 5.0
# Source.eval and a Spectrum of the same modes run the same evaluation: rounding only.
EXACT = 1e-12
# black_sky_albedo's product Gauss rule (48 x 64 nodes) on a lobe that is piecewise linear in its nodes:
# well below 1e-3 of the albedo, beside the sampler's noise.
ALBEDO_RULE = 1e-3

REPRESENTATIONS = {"modes": "modes", "half-angle": "a half-angle lobe \\(no modes\\)",
                   "hybrid": "a hybrid of modes and a half-angle lobe"}


@pytest.fixture(scope="module")
def banks():
    with tempfile.TemporaryDirectory() as d:
        out = {}
        for rep in REPRESENTATIONS:
            scene = os.path.join(d, rep + ".toml")
            with open(scene, "w") as f:
                target = 0.5 if rep == "modes" else 0.05  # modes of order 4 meet 0.5 only
                f.write(f'[bank]\nlevel = 2\nlevels = [2]\norder_max = 4\ntarget = {target}\nholdout_pairs = 512\n'
                        f'representations = ["{rep}"]\non_miss = "keep-best"\n\n'
                        '[[material]]\nname = "glossy"\nsource = "model:0.6*lambert+0.4*ggx:alpha=0.1"\n')
            bank = os.path.join(d, rep + ".h5")
            report = icobrdf.build_bank(scene, bank)
            assert report["materials"][0]["representation"] == rep
            out[rep] = bank + "#glossy"
        yield out


def pairs(n, seed=5):
    rng = np.random.default_rng(seed)
    ti, tr = rng.uniform(0, 1.2, n), rng.uniform(0, 1.2, n)
    pi, pr = rng.uniform(-math.pi, math.pi, n), rng.uniform(-math.pi, math.pi, n)
    wi = np.stack([np.sin(ti) * np.cos(pi), np.sin(ti) * np.sin(pi), np.cos(ti)], axis=1)
    wr = np.stack([np.sin(tr) * np.cos(pr), np.sin(tr) * np.sin(pr), np.cos(tr)], axis=1)
    return wi, wr


@pytest.mark.parametrize("rep", list(REPRESENTATIONS))
def test_source_sampler_and_albedo_take_every_representation(banks, rep):
    src = icobrdf.Source(banks[rep])
    wi, wr = pairs(200)
    f = src.eval(wi, wr)
    assert np.all(np.isfinite(f)) and np.max(f) > 0.1  # the glossy model's f reaches well above 0.1 here
    # The sampler's mean weight estimates the black-sky albedo without bias.
    sza = 30.0
    a = icobrdf.black_sky_albedo(src, [sza])
    a = float(np.ravel(a)[0])
    theta = math.radians(sza)
    w = icobrdf.Sampler(src, level=4).sample(np.array([math.sin(theta), 0, math.cos(theta)]),
                                             *np.random.default_rng(2).random((2, 20000)))[2]
    mean, se = w.mean(), w.std() / math.sqrt(w.size)
    assert abs(mean - a) < STANDARD_ERRORS * se + ALBEDO_RULE * a, (rep, mean, a, se)


@pytest.mark.parametrize("rep", list(REPRESENTATIONS))
def test_read_spectrum_takes_modes_and_refuses_a_lobe(banks, rep):
    path, name = banks[rep].split("#")
    if rep == "modes":
        s = icobrdf.read_spectrum(path, name)
        wi, wr = pairs(50)
        assert np.max(np.abs(s.eval(wi, wr) - icobrdf.Source(banks[rep]).eval(wi, wr))) < EXACT
        return
    with pytest.raises(RuntimeError, match="is " + REPRESENTATIONS[rep] + ".*icobrdf.Source") as e:
        icobrdf.read_spectrum(path, name)
    assert "\n" not in str(e.value)


def test_array_arguments_must_be_finite():
    grid = icobrdf.Grid.equal_area(1)
    basis = icobrdf.DiscreteBasis(grid, 2)
    lut = np.ones((grid.cells, grid.cells))
    lut[3, 4] = np.nan
    with pytest.raises(ValueError, match="lut: expected finite values, found nan at row 3, column 4"):
        icobrdf.project(icobrdf.Projection(basis), lut)
    c = np.zeros((6, 6))
    c[0, 1] = np.inf
    with pytest.raises(ValueError, match="coefficients: expected finite values"):
        icobrdf.reconstruct(basis, c)
    with pytest.raises(ValueError, match="coefficients: expected finite values"):
        icobrdf.evaluate_coefficients(c, 2, np.array([0, 0, 1.0]), np.array([0, 0, 1.0]))
