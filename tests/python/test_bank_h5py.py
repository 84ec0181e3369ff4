#!/usr/bin/python3
"""The numpy user's path, end to end: icobrdf builds a bank, tools/bank_numpy_example.py uses it with h5py.

Run as: /usr/bin/python3 tests/python/test_bank_h5py.py <path to icobrdf>
Prints 'N passed, M failed' and exits non-zero on failure.
"""
import os
import subprocess
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "tools"))
import bank_numpy_example  # noqa: E402

# P^T B C B^T P = G^-1 (B^T W B) C (B^T W B) G^-1 = C exactly; float64 products over 168 cells and 15 modes
# round to ~1e-14 of the largest coefficient.
ROUND_TRIP_TOL = 1e-10

SCENE = """
[bank]
level = 2
levels = [2]
order_max = 3
store_lut = true
lut_float32 = false

[[material]]
name = "opik"
source = "model:minnaert:k=2"
target = 1e-6

[[material]]
name = "rough"
source = "model:0.5*lambert+0.5*phong:n=2"
target = 0.3
"""


def run(icobrdf):
    """Returns (number of checks, list of failures)."""
    failures = []
    checks = 0
    with tempfile.TemporaryDirectory() as d:
        scene = os.path.join(d, "scene.toml")
        bank = os.path.join(d, "bank.h5")
        with open(scene, "w") as f:
            f.write(SCENE)
        subprocess.run([icobrdf, "bank", "build", scene, "-o", bank, "--quiet"], check=True, stdout=subprocess.DEVNULL)
        for name in ("opik", "rough"):
            C, C_back, F, F_stored = bank_numpy_example.main(bank, name)
            err = np.abs(C_back - C).max() / np.abs(C).max()
            lut_err = np.abs(F - F_stored).max() / np.abs(F).max()
            checks += 1
            if not (err < ROUND_TRIP_TOL and lut_err < ROUND_TRIP_TOL):
                failures.append(f"{name}: projection round trip {err:.3e}, LUT reconstruction {lut_err:.3e}")
            if name == "opik":
                # Minnaert k = 2, f = (3/(2 pi)) cos_i cos_r: C_00 = (3/(2 pi)) (integral cos K_0^0 dOmega)^2
                # = (3/(2 pi)) (pi / sqrt(2 pi))^2 = 3/4, recovered exactly (the BRDF is in the span).
                checks += 1
                if abs(C[0, 0, 0] - 0.75) > ROUND_TRIP_TOL:
                    failures.append(f"opik: C_00 = {C[0, 0, 0]!r}, expected 0.75")
    return checks, failures


if __name__ == "__main__":
    checks, failures = run(sys.argv[1])
    for f in failures:
        print("FAILED:", f)
    print(f"{checks - len(failures)} passed, {len(failures)} failed")
    sys.exit(1 if failures else 0)
