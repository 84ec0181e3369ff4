#!/usr/bin/python3
"""Use an icobrdf bank from numpy + h5py alone: the numpy user's path.

    /usr/bin/python3 tools/bank_numpy_example.py BANK.h5 [MATERIAL]

Reads the bank's grid and stored operators (/basis/<order>/B, P), a material's coefficient matrix C and,
when stored, its LUT F (cells x cells, rows = incident cells). Reconstructs the LUT on the bank grid as
F' = B C B^T, projects it back as C' = P^T F' P, and prints how well both round trips agree, then the
BRDF value for the first pair of cell directions. Shapes are the logical row-major shapes of
docs/file-format.md; Debian's python3-h5py and python3-numpy are all it needs.
"""
import sys

import h5py
import numpy as np


def main(path, name=None):
    with h5py.File(path, "r") as f:
        if f.attrs["format"] != "icobrdf-bank" and f.attrs["format"] != b"icobrdf-bank":
            raise SystemExit(f"{path}: not an icobrdf bank")
        if int(f.attrs["complete"]) != 1:
            raise SystemExit(f"{path}: incomplete bank")
        mats = f["materials"]
        name = name or sorted(mats.keys())[0]
        m = mats[name]
        order = int(m.attrs["order"])
        C = m["C"][...]                       # channels x M x M
        B = f[f"basis/{order}/B"][...]        # cells x M
        P = f[f"basis/{order}/P"][...]        # cells x M
        dirs = f["grid/directions"][...]      # cells x 3
        F_stored = m["lut"][...] if "lut" in m else None
    F = np.einsum("ia,cab,jb->cij", B, C, B)  # reconstruction on the bank grid
    C_back = np.einsum("ia,cij,jb->cab", P, F, P)  # projection with the stored operator
    print(f"{name}: order {order}, {C.shape[0]} channel(s), {B.shape[0]} cells, {B.shape[1]} modes")
    print(f"  max |P^T (B C B^T) P - C| = {np.abs(C_back - C).max():.3e}")
    if F_stored is not None:
        print(f"  max |B C B^T - stored LUT| = {np.abs(F - F_stored).max():.3e} (stored as {F_stored.dtype})")
    print(f"  f(cell 0 -> cell 0) = {F[0, 0, 0]:.6g} 1/sr at direction {dirs[0]}")
    return C, C_back, F, F_stored


if __name__ == "__main__":
    main(*sys.argv[1:3])
