"""Fits of scattered samples given as numpy arrays (icobrdf.Source.from_samples, icobrdf.fit with order=None),
directions given as one 1-D array, the refusal of non-unit directions, and a bank built from a scene.

The PTFE samples (tests/data/measured/ptfe532.csv, NIST, tests/data/measured/README.md) are read here with
numpy and turned into directions independently of the library's CSV reader; the program `icobrdf fit` fits
the file itself, and both fits must agree. Run by CTest with the module's tests (PYTHONPATH=<build>/python);
the program is <build>/cli/icobrdf beside the module (ICOBRDF_PROGRAM overrides it).
"""
import math
import os
import subprocess
import tempfile
import warnings

import numpy as np
import pytest

import icobrdf
from test_icobrdf_module import random_pairs, unit  # uniform pairs on the hemisphere; (theta, phi) -> unit vector

HERE = os.path.dirname(os.path.abspath(__file__))
PTFE = os.path.join(HERE, "..", "..", "data", "measured", "ptfe532.csv")

# Tolerances, each with its reason.
EXACT = 1e-12       # closed forms evaluated in double precision (a few roundings)
SAME_FIT = 1e-9     # numpy's and the CSV reader's sin/cos of the same angles may differ in the last bit; the PTFE
                    # fit's condition (~160) carries that to ~1e-13 of the coefficients and figures
CONSTANT_FIT = 1e-9 # least squares of a constant on 400 samples: the normal equations' rounding, cond <= ~1e3
GRID_PROJECTION = 1e-6  # a level-2 grid's cubature of a constant: exact solid angles, the basis averages' Gram
                        # error (below 1e-3) only on modes a constant does not excite


def program():
    default = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(icobrdf.__file__))), "cli", "icobrdf")
    return os.environ.get("ICOBRDF_PROGRAM", default)


def signed_direction(theta_deg, phi_deg):
    # NIST's signed polar angle: theta < 0 is the direction (|theta|, phi + 180 deg).
    phi = np.where(theta_deg < 0, phi_deg + 180.0, phi_deg)
    return unit(np.radians(np.abs(theta_deg)), np.radians(phi))


def ptfe_arrays():
    rows = np.loadtxt(PTFE, delimiter=",", comments="#", skiprows=4)
    assert rows.shape == (1824, 5)
    return signed_direction(rows[:, 0], rows[:, 1]), signed_direction(rows[:, 2], rows[:, 3]), rows[:, 4]


def relative_difference(a, b):
    a, b = np.asarray(a, float), np.asarray(b, float)
    return np.max(np.abs(a - b)) / max(np.max(np.abs(b)), 1e-300)


def test_order_choosing_fit_of_ptfe_arrays_matches_the_program():
    with tempfile.TemporaryDirectory() as d:
        out = os.path.join(d, "ptfe.h5")
        done = subprocess.run([program(), "fit", PTFE, "-o", out, "--quiet"], capture_output=True, text=True)
        assert done.returncode == 0, done.stderr
        cli = icobrdf.read_spectrum(out)
    wi, wr, f = ptfe_arrays()
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # the program warned of no fallback, so neither may this fit
        py = icobrdf.fit(icobrdf.Source.from_samples(wi, wr, f), order=None)
    # The same choices: the order and class by cross-validation, lambda by GCV.
    assert (py.order, py.isotropic) == (cli.order, cli.isotropic)
    a, b = py.sample_fit, cli.sample_fit
    assert a is not None and b is not None
    assert (a.order_choice, a.class_choice, a.tikhonov_choice) == (b.order_choice, b.class_choice, b.tikhonov_choice) == (
        "cross-validation", "cross-validation", "generalized cross-validation")
    assert (a.samples, a.unknowns, a.effective_rank, a.cv_folds, a.fallback) == (b.samples, b.unknowns, b.effective_rank, b.cv_folds, b.fallback)
    assert a.samples == 1824
    # The same coefficients and figures.
    assert relative_difference(py.coefficients[0], cli.coefficients[0]) < SAME_FIT
    for name in ("cv_rms", "condition", "tikhonov", "effective_dof", "cv_rms_isotropic", "cv_rms_general"):
        assert abs(getattr(a, name) - getattr(b, name)) <= SAME_FIT * abs(getattr(b, name)), name
    assert relative_difference(a.residual_rms, b.residual_rms) < SAME_FIT
    assert relative_difference(a.noise_sigma, b.noise_sigma) < SAME_FIT
    assert a.standard_error.shape == b.standard_error.shape == (1, a.unknowns)
    assert relative_difference(a.standard_error, b.standard_error) < SAME_FIT
    # The residual RMS is that of the samples against the fit, recomputed here from the spectrum's values.
    residual = f - py.eval(wi, wr)[:, 0]
    assert abs(np.sqrt(np.mean(residual**2)) - a.residual_rms[0]) < SAME_FIT * a.residual_rms[0]


def test_general_modes_the_samples_do_not_determine_fall_back_with_a_warning():
    wi, wr, f = ptfe_arrays()
    with pytest.warns(RuntimeWarning, match="isotropic"):
        s = icobrdf.fit(icobrdf.Source.from_samples(wi, wr, f), order=8)
    assert s.isotropic and s.order == 8
    assert "isotropic" in s.sample_fit.fallback


def test_samples_of_a_constant_choose_order_zero_and_give_two_albedo():
    # f = a / pi everywhere: C_00 = 2a (K_0 = 1 / sqrt(2 pi)), every other coefficient 0, residual 0; the
    # cross-validation sees no gain beyond order 0 and keeps the fewest unknowns (the isotropic constant).
    a = 0.7
    wi, wr = random_pairs(400)
    s = icobrdf.fit(icobrdf.Source.from_samples(wi, wr, np.full(400, a / math.pi)))
    assert s.order == 0 and s.isotropic
    assert abs(s.coefficients[0][0, 0] - 2 * a) < CONSTANT_FIT
    assert s.sample_fit.residual_rms[0] < CONSTANT_FIT
    assert s.sample_fit.order_choice == "cross-validation"


def test_duplicate_rows_are_merged_into_their_weighted_mean():
    # Two rows of one pair with weights 1 and 3 are one sample of weight 4 and value (v1 + 3 v2) / 4.
    wi, wr = random_pairs(60, seed=3)
    rng = np.random.default_rng(5)
    v = rng.uniform(0.1, 0.3, 60)
    v2 = rng.uniform(0.1, 0.3, 60)
    merged = icobrdf.fit(icobrdf.Source.from_samples(wi, wr, (v + 3 * v2) / 4, weights=np.full(60, 4.0), tikhonov=0), order=2, isotropic=True)
    rows = icobrdf.fit(icobrdf.Source.from_samples(np.vstack([wi, wi]), np.vstack([wr, wr]), np.concatenate([v, v2]),
                                                   weights=np.concatenate([np.ones(60), np.full(60, 3.0)]), tikhonov=0),
                       order=2, isotropic=True)
    assert rows.sample_fit.samples == merged.sample_fit.samples == 60
    assert relative_difference(rows.coefficients[0], merged.coefficients[0]) < CONSTANT_FIT


def test_one_direction_as_a_1d_array_pairs_with_every_row():
    src = icobrdf.Source("model:ggx:alpha=0.3")
    wi = unit(0.4, 0.2)
    _, wr = random_pairs(25)
    one = src.eval(wi, wr)
    many = src.eval(np.tile(wi, (25, 1)), wr)
    assert one.shape == (25, 1)
    assert np.array_equal(one, many)
    assert np.array_equal(src.eval(wr, wi), src.eval(wr, np.tile(wi, (25, 1))))
    assert icobrdf.hemisphere_basis(4, wi).shape == (1, 15)
    with pytest.raises(ValueError, match="rows"):  # only a 1-D direction pairs with every row; a (1, 3) array is one pair
        src.eval(wi[None, :], wr)
    assert np.array_equal(icobrdf.helmholtz_modes(3, wi, wr), icobrdf.helmholtz_modes(3, np.tile(wi, (25, 1)), wr))


def test_non_unit_directions_are_refused():
    src = icobrdf.Source("model:lambert")
    with pytest.raises(ValueError, match=r"wi: row 0 \(0, 0, 2\) has length 2, expected a unit vector"):
        src.eval(np.array([0, 0, 2.0]), np.array([[0, 0, 1.0]]))
    with pytest.raises(ValueError, match=r"wr: row 1 .* expected a unit vector"):
        src.eval(np.array([0, 0, 1.0]), np.array([[0, 0, 1.0], [0.5, 0, 0.5]]))
    with pytest.raises(ValueError, match="expected an \\(n, 3\\) array .* found \\(3, 1\\)"):
        src.eval(np.zeros((3, 1)) + 1, np.array([[0, 0, 1.0]]))
    wi, wr = random_pairs(10)
    with pytest.raises(ValueError, match="wr: row 4 .* has length 2"):
        bad = wr.copy()
        bad[4] *= 2
        icobrdf.Source.from_samples(wi, bad, np.ones(10))
    with pytest.raises(ValueError, match="below the horizon"):
        below = wr.copy()
        below[2, 2] = -below[2, 2]
        icobrdf.Source.from_samples(wi, below, np.ones(10))
    with pytest.raises(ValueError, match="values has 9 rows"):
        icobrdf.Source.from_samples(wi, wr, np.ones(9))
    with pytest.raises(ValueError, match="weights"):
        icobrdf.Source.from_samples(wi, wr, np.ones(10), weights=-np.ones(10))
    with pytest.raises(ValueError, match="tikhonov"):
        icobrdf.Source.from_samples(wi, wr, np.ones(10), tikhonov="gcv")
    with pytest.raises(ValueError, match="order"):
        icobrdf.fit(icobrdf.Source.from_samples(wi, wr, np.ones(10)), order=-1)


def test_bank_built_from_a_scene():
    a = 0.6
    with tempfile.TemporaryDirectory() as d:
        scene = os.path.join(d, "scene.toml")
        with open(scene, "w") as out:
            out.write('[bank]\nlevel = 2\nlevels = [2]\norder_max = 2\nholdout_pairs = 512\n\n'
                      f'[[material]]\nname = "matte"\nsource = "model:lambert:albedo={a}"\ntarget = 0.001\n')
        bank = os.path.join(d, "bank.h5")
        report = icobrdf.build_bank(scene, bank)
        assert report["written"] and not report["interrupted"]
        (m,) = report["materials"]
        assert m["name"] == "matte" and m["representation"] == "modes" and m["target_met"]
        assert icobrdf.bank_materials(bank) == ["matte"]
        s = icobrdf.read_spectrum(bank, "matte")
        assert not s.cosine and abs(s.coefficients[0][0, 0] - 2 * a) < GRID_PROJECTION
        with pytest.raises((OSError, RuntimeError)):
            icobrdf.build_bank(os.path.join(d, "missing.toml"), os.path.join(d, "other.h5"))
