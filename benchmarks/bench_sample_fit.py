#!/usr/bin/env python3
"""Fits of scattered samples (issue #16): speed of the 20,000-sample order-10 fit, the in-plane case that used
to fail silently, and the automatic order. Samples are values of `model:oren-nayar:sigma=20` computed by
`icobrdf eval`; held-out errors are relative L2 against the model at 2,000 pairs uniform over the domain.

usage: bench_sample_fit.py ICOBRDF [WORKDIR]
"""
import json
import math
import os
import random
import subprocess
import sys
import tempfile
import time

MODEL = "model:oren-nayar:sigma=20"


def pairs(n, seed, in_plane):
    r = random.Random(seed)
    out = []
    for _ in range(n):
        if in_plane:  # phi_r = phi_i or phi_i + 180, the plane's azimuth random
            pi = r.uniform(0, 360)
            out.append((r.uniform(0, 89), pi, r.uniform(0, 89), (pi + r.choice([0.0, 180.0])) % 360))
        else:  # uniform over the hemisphere x hemisphere
            out.append((math.degrees(math.acos(r.random())), r.uniform(0, 360),
                        math.degrees(math.acos(r.random())), r.uniform(0, 360)))
    return out


def write_pairs(path, rows):
    with open(path, "w") as f:
        f.write("theta_i,phi_i,theta_r,phi_r\n")
        for t in rows:
            f.write("%.12g,%.12g,%.12g,%.12g\n" % t)


def evaluate(exe, source, pairs_csv):
    out = subprocess.run([exe, "eval", source, "--at", pairs_csv], capture_output=True, text=True, check=True).stdout
    return [float(line.split(",")[-1]) for line in out.strip().split("\n")[1:]]


def samples(exe, work, name, rows):
    write_pairs(os.path.join(work, name + ".pairs.csv"), rows)
    values = evaluate(exe, MODEL, os.path.join(work, name + ".pairs.csv"))
    path = os.path.join(work, name + ".csv")
    with open(path, "w") as f:
        f.write("theta_i,phi_i,theta_r,phi_r,value\n")
        for t, v in zip(rows, values):
            f.write("%.12g,%.12g,%.12g,%.12g,%.17g\n" % (t + (v,)))
    return path


def held_out(exe, spectrum, held):
    ref = evaluate(exe, MODEL, held)
    fit = evaluate(exe, spectrum, held)
    return math.sqrt(sum((a - b) ** 2 for a, b in zip(fit, ref)) / sum(b * b for b in ref))


def fit(exe, args):
    t0 = time.time()
    r = subprocess.run([exe, "fit"] + args + ["-q"], capture_output=True, text=True)
    return time.time() - t0, r


def main():
    exe = os.path.abspath(sys.argv[1])
    work = sys.argv[2] if len(sys.argv) > 2 else tempfile.mkdtemp(prefix="bench_sample_fit_")
    os.makedirs(work, exist_ok=True)
    held = os.path.join(work, "held.csv")
    write_pairs(held, pairs(2000, 2, False))
    full = samples(exe, work, "full20k", pairs(20000, 3, False))
    plane = samples(exe, work, "plane", pairs(2000, 7, True))
    cases = [
        ("20,000 samples, general modes, order 10", [full, "--order", "10", "--level", "5"]),
        ("20,000 samples, isotropic modes, order 10", [full, "--order", "10", "--isotropic", "--level", "5"]),
        ("20,000 samples, no order (CV + GCV), general", [full]),
        ("20,000 samples, no order (CV + GCV), isotropic", [full, "--isotropic"]),
        ("2,000 in-plane samples, general modes, order 8", [plane, "--order", "8"]),
        ("2,000 in-plane samples, isotropic modes, order 8", [plane, "--order", "8", "--isotropic"]),
    ]
    print("| case | exit | wall s | order | CV RMS 1/sr | held-out rel. L2 | fallback |")
    print("|---|---|---|---|---|---|---|")
    for i, (label, args) in enumerate(cases):
        out = os.path.join(work, "fit%d.h5" % i)
        seconds, r = fit(exe, args + ["-o", out, "--json"])
        if r.returncode != 0:
            print("| %s | %d | %.2f | | | | %s |" % (label, r.returncode, seconds, r.stderr.strip()))
            continue
        j = json.loads(r.stdout)
        sf = j.get("sample_fit", {})
        print("| %s | 0 | %.2f | %d (%s) | %.3g | %.3g | %s |" % (
            label, seconds, j["order"], sf.get("order_choice", ""), sf.get("cv_rms") if sf.get("cv_rms") is not None else float("nan"),
            held_out(exe, out, held), "yes" if sf.get("fallback") else "no"))


if __name__ == "__main__":
    main()
