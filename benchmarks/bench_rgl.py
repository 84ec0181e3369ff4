#!/usr/bin/python3
"""bench rgl: a real RGL material (FILE.bsdf) through icobrdf: values, reciprocity, white furnace, fits.

    /usr/bin/python3 benchmarks/bench_rgl.py build/cli/icobrdf MATERIAL.bsdf [OUT_DIR]

The material is not stored in the repository: pass the path of any RGL .bsdf file (docs/readers.md says
where one can be had). Writes OUT_DIR/report.md and OUT_DIR/results.json (default benchmarks/rgl):

  * reciprocity: f(a, b) against f(b, a) at 20,000 random pairs (both directions uniform in solid angle,
    theta <= 80 deg): median per-pair asymmetry |f(a,b) - f(b,a)| / mean, and ||F - F^T|| / ||F||;
  * white furnace: directional albedo a(w_i) = integral f cos(theta_r) dOmega_r at theta_i = 0 .. 80 deg
    (Gauss-Legendre in cos(theta_r), 64 nodes, times 128 azimuths, through `icobrdf eval`);
  * fits: `icobrdf fit MATERIAL --order N --level L` for several orders (anisotropic modes and --isotropic),
    (orders 2-12 anisotropic, 4, 8, 12 isotropic, level 4), each evaluated at held-out random pairs that the fit never saw. The pairs are split in two halves: the
    order is chosen on the validation half (smallest relative L2 error), and the error of that choice is
    reported on the test half. Relative L2 over the pairs, per channel: ||f_fit - f|| / ||f||.
Timings are wall-clock seconds of this machine.
"""
import json
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ORDERS = [2, 4, 6, 8, 10, 12]
LEVEL = 4
PAIRS = 20000
MAX_THETA_DEG = 80.0


def run(args):
    r = subprocess.run(args, capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit("failed: " + " ".join(args) + "\n" + r.stderr)
    return r


def eval_at(icobrdf, source, pairs_deg, tmp):
    path = os.path.join(tmp, "pairs.csv")
    np.savetxt(path, pairs_deg, delimiter=",", header="theta_i,phi_i,theta_r,phi_r", comments="", fmt="%.17g")
    out = run([icobrdf, "eval", source, "--at", path]).stdout
    header, *lines = out.strip().split("\n")
    return header.split(","), np.array([[float(x) for x in ln.split(",")] for ln in lines])


def random_pairs(rng, n):
    cmax = np.cos(np.radians(MAX_THETA_DEG))
    ti = np.degrees(np.arccos(rng.uniform(cmax, 1, n)))
    tr = np.degrees(np.arccos(rng.uniform(cmax, 1, n)))
    return np.c_[ti, rng.uniform(0, 360, n), tr, rng.uniform(0, 360, n)]


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    icobrdf, material = sys.argv[1], sys.argv[2]
    out_dir = sys.argv[3] if len(sys.argv) > 3 else os.path.join(HERE, "rgl")
    os.makedirs(out_dir, exist_ok=True)
    rng = np.random.default_rng(20261124)
    res = {"material": os.path.basename(material), "bytes": os.path.getsize(material)}
    with tempfile.TemporaryDirectory() as tmp:
        pairs = random_pairs(rng, PAIRS)
        names, f = eval_at(icobrdf, material, pairs, tmp)
        t0 = time.time()
        _, f_swapped = eval_at(icobrdf, material, pairs[:, [2, 3, 0, 1]], tmp)
        res["eval_seconds_20000_pairs"] = time.time() - t0
        res["channels"] = names
        mean = 0.5 * (f + f_swapped)
        ok = mean > 1e-6 * mean.max()
        res["reciprocity_median_asymmetry"] = [float(np.median(np.abs(f - f_swapped)[ok[:, c], c] / mean[ok[:, c], c])) for c in range(f.shape[1])]
        res["reciprocity_rel_l2"] = [float(np.linalg.norm(f[:, c] - f_swapped[:, c]) / np.linalg.norm(f[:, c])) for c in range(f.shape[1])]

        mu, wmu = np.polynomial.legendre.leggauss(64)
        mu, wmu = 0.5 * (mu + 1), 0.5 * wmu  # cos(theta_r) in (0, 1)
        nphi = 128
        phis = (np.arange(nphi) + 0.5) * 360.0 / nphi
        furnace = []
        for ti in [0, 20, 40, 60, 70, 80]:
            tr = np.degrees(np.arccos(mu))
            grid = np.array([[ti, 0.0, a, p] for a in tr for p in phis])
            _, v = eval_at(icobrdf, material, grid, tmp)
            w = np.repeat(wmu * mu, nphi) * (2 * np.pi / nphi)
            furnace.append({"theta_i": ti, "albedo": [float(x) for x in (v * w[:, None]).sum(axis=0)]})
        res["white_furnace"] = furnace

        held = random_pairs(rng, PAIRS)
        _, ref = eval_at(icobrdf, material, held, tmp)
        half = PAIRS // 2
        fits = []
        for iso in [False, True]:
            for n in (ORDERS if not iso else ORDERS[1::2]):
                h5 = os.path.join(tmp, f"fit_{n}_{int(iso)}.h5")
                args = [icobrdf, "fit", material, "--order", str(n), "--level", str(LEVEL), "-o", h5] + (["--isotropic"] if iso else [])
                t0 = time.time()
                r = subprocess.run(args, capture_output=True, text=True)
                secs = time.time() - t0
                if r.returncode != 0:
                    fits.append({"order": n, "isotropic": iso, "refused": r.stderr.strip().splitlines()[-1]})
                    continue
                _, v = eval_at(icobrdf, h5, held, tmp)
                err = lambda sl: [float(np.linalg.norm(v[sl, c] - ref[sl, c]) / np.linalg.norm(ref[sl, c])) for c in range(ref.shape[1])]
                fits.append({"order": n, "isotropic": iso, "seconds": secs, "validation_rel_l2": err(slice(0, half)),
                             "test_rel_l2": err(slice(half, None)), "bytes": os.path.getsize(h5)})
        res["fits"] = fits
        good = [x for x in fits if "refused" not in x]
        best = min(good, key=lambda x: max(x["validation_rel_l2"]))
        res["chosen"] = {"order": best["order"], "isotropic": best["isotropic"], "test_rel_l2": best["test_rel_l2"]}

    with open(os.path.join(out_dir, "results.json"), "w") as fh:
        json.dump(res, fh, indent=1)
    lines = [f"# RGL material {res['material']} ({res['bytes']:,} bytes)", "",
             f"Channels {', '.join(res['channels'])}. {PAIRS:,} random pairs, theta <= {MAX_THETA_DEG:g} deg on both sides.", "",
             "Reciprocity, median per-pair asymmetry: " + ", ".join(f"{x:.3f}" for x in res["reciprocity_median_asymmetry"]) +
             "; ||F - F^T|| / ||F||: " + ", ".join(f"{x:.3f}" for x in res["reciprocity_rel_l2"]), "",
             "| theta_i (deg) | albedo per channel |", "|---|---|"]
    lines += [f"| {x['theta_i']} | " + ", ".join(f"{a:.4f}" for a in x["albedo"]) + " |" for x in res["white_furnace"]]
    lines += ["", f"Fits at level {LEVEL} (held-out relative L2 per channel: validation half / test half):", "",
              "| order | modes | seconds | validation | test | bytes |", "|---|---|---|---|---|---|"]
    for x in res["fits"]:
        kind = "isotropic" if x["isotropic"] else "anisotropic"
        if "refused" in x:
            lines.append(f"| {x['order']} | {kind} | refused: {x['refused']} | | | |")
        else:
            lines.append(f"| {x['order']} | {kind} | {x['seconds']:.1f} | " + ", ".join(f"{e:.4f}" for e in x["validation_rel_l2"]) + " | " +
                         ", ".join(f"{e:.4f}" for e in x["test_rel_l2"]) + f" | {x['bytes']:,} |")
    c = res["chosen"]
    lines += ["", f"Chosen on the validation half: order {c['order']} ({'isotropic' if c['isotropic'] else 'anisotropic'}), test error " +
              ", ".join(f"{e:.4f}" for e in c["test_rel_l2"])]
    with open(os.path.join(out_dir, "report.md"), "w") as fh:
        fh.write("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
