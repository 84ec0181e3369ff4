#!/usr/bin/python3
"""Every representation a bank can hold, reconstructed with numpy + h5py alone (tools/bank_eval_numpy.py),
against `icobrdf eval` of the same stored material.

Run as: /usr/bin/python3 tests/python/test_bank_eval_numpy.py <path to icobrdf>
Prints 'N passed, M failed' and exits non-zero on failure.
"""
import math
import os
import subprocess
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "tools"))
import bank_eval_numpy  # noqa: E402

# Both sides evaluate the same stored numbers by the same definitions with different arithmetic (explicit
# Zernike sums against recurrences, numpy's trigonometry against the C++ kernels): they agree to rounding,
# amplified by 1/(cos_i cos_r) for a cosine-quantity lobe near grazing; relative to the largest value.
AGREEMENT_TOL = 1e-9

SCENE = """
[bank]
level = 2
levels = [2, 3]
order_max = 6
target = 0.05
metric = "{metric}"
sampling = "centre"
holdout_pairs = 2048
representations = ["{representation}"]

[[material]]
name = "m"
source = "{source}"
"""

# (representation, metric, source). The hybrid's body is Minnaert's (not low-rank in half-angle coordinates,
# where Lambert + GGX is a rank-2 lobe and needs no body).
CASES = [
    ("modes", "f", "model:minnaert:k=2"),
    ("half-angle", "cosine", "model:ggx:alpha=0.2,f0=0.04"),
    ("half-angle", "f", "model:blinn-phong:n=50"),
    ("half-angle", "cosine", "model:ggx-aniso:alpha_x=0.2,alpha_y=0.4"),
    ("hybrid", "cosine", "model:minnaert:k=2+0.2*ggx:alpha=0.2"),
    ("half-angle", "cosine", "merl:{merl}"),  # a lobe on the table's own (centred) nodes
]


def write_merl(path):
    """A MERL table (icobrdf/io/merl.hpp layout) of a smooth lobe over a constant, with a few missing (-1) entries."""
    i = np.arange(90)
    th = math.pi / 2 * ((i + 0.5) / 90) ** 2
    td = math.pi / 2 * (i + 0.5) / 90
    pd = math.pi * (np.arange(180) + 0.5) / 180
    TH, TD, PD = np.meshgrid(th, td, pd, indexing="ij")  # (i_h, i_d, i_p): flat index i_p + 180 (i_d + 90 i_h)
    f = 0.1 + 2.0 * np.exp(-(TH / 0.15) ** 2) * (1 + 0.2 * np.cos(2 * PD)) + 0.5 * TD ** 2
    values = np.stack([f / s for s in (1 / 1500, 1.15 / 1500, 1.66 / 1500)]).reshape(3, -1)
    values[:, 1000:1010] = -1.0
    with open(path, "wb") as out:
        np.array([90, 90, 180], dtype="<i4").tofile(out)
        values.astype("<f8").tofile(out)


def random_pairs(n, seed):
    rng = np.random.default_rng(seed)
    deg = np.degrees
    ti, tr = deg(np.arccos(rng.uniform(0, 1, n))), deg(np.arccos(rng.uniform(0, 1, n)))
    pi, pr = rng.uniform(0, 360, n), rng.uniform(0, 360, n)
    # Hard cases: normal incidence, grazing, the specular direction (h = n), w_i = w_r.
    ti[:4], pi[:4], tr[:4], pr[:4] = [0, 90, 40, 30], [0, 10, 20, 50], [0, 45, 40, 30], [0, 100, 200, 50]
    return np.stack([ti, pi, tr, pr], axis=1)


def run(icobrdf):
    failures, checks = [], 0
    with tempfile.TemporaryDirectory() as d:
        pairs = random_pairs(3000, 7)
        csv = os.path.join(d, "pairs.csv")
        np.savetxt(csv, pairs, delimiter=",", header="theta_i,phi_i,theta_r,phi_r", comments="", fmt="%.17g")
        for k, (representation, metric, source) in enumerate(CASES):
            scene, bank = os.path.join(d, f"s{k}.toml"), os.path.join(d, f"b{k}.h5")
            if "{merl}" in source:
                merl = os.path.join(d, "table.binary")
                write_merl(merl)
                source = source.format(merl=merl)
            with open(scene, "w") as f:
                f.write(SCENE.format(metric=metric, representation=representation, source=source))
            subprocess.run([icobrdf, "bank", "build", scene, "-o", bank, "--quiet"], check=True, stdout=subprocess.DEVNULL)
            out = subprocess.run([icobrdf, "eval", bank + "#m", "--at", csv], check=True, capture_output=True, text=True).stdout
            want = np.loadtxt(out.splitlines()[1:], delimiter=",", ndmin=2)
            got = bank_eval_numpy.eval_material(bank, "m", bank_eval_numpy.direction(pairs[:, 0], pairs[:, 1]),
                                                bank_eval_numpy.direction(pairs[:, 2], pairs[:, 3]))
            err = np.abs(got - want).max() / np.abs(want).max()
            checks += 1
            if not err < AGREEMENT_TOL:
                failures.append(f"{representation} {source}: numpy vs icobrdf eval {err:.3e}")
    return checks, failures


if __name__ == "__main__":
    n, failures = run(sys.argv[1])
    for f in failures:
        print("FAILED:", f)
    print(f"{n - len(failures)} passed, {len(failures)} failed")
    sys.exit(1 if failures else 0)
