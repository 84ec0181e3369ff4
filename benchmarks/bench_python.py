#!/usr/bin/env python3
"""Python module speed against the C++ library, in one run (issue #15: >= 80% of the C++ speed).

  PYTHONPATH=build/python /usr/bin/python3 benchmarks/bench_python.py build/benchmarks/bench_spectrum_eval

Evaluates a random order-8 coefficient matrix at 2^20 direction pairs through the module
(icobrdf.evaluate_coefficients: numpy arrays in and out, the GIL released) and runs the C++ benchmark
BM_EvaluateCoefficients/8/1048576 of the same work; prints both rates and their ratio (best of 5 each).
Also times a GGX fit (level 4, order 8) both ways: the module's fit() and the icobrdf program's `fit`.
"""
import json
import math
import subprocess
import sys
import time

import numpy as np

import icobrdf

PAIRS = 1 << 20
REPEAT = 5


def directions(rng, n):
    z = rng.uniform(0, 1, n)
    p = rng.uniform(0, 2 * math.pi, n)
    s = np.sqrt(1 - z * z)
    return np.stack([s * np.cos(p), s * np.sin(p), z], axis=1)


def main():
    bench = sys.argv[1]
    rng = np.random.default_rng(7)
    wi, wr = directions(rng, PAIRS), directions(rng, PAIRS)
    m = icobrdf.basis_count(8)
    c = rng.uniform(-1, 1, (m, m))
    best = math.inf
    for _ in range(REPEAT):
        t0 = time.perf_counter()
        f = icobrdf.evaluate_coefficients(c, 8, wi, wr)
        best = min(best, time.perf_counter() - t0)
    assert f.shape == (PAIRS,)
    py_rate = PAIRS / best
    out = subprocess.run([bench, "--benchmark_filter=BM_EvaluateCoefficients/8/1048576", f"--benchmark_repetitions={REPEAT}",
                          "--benchmark_format=json"], check=True, capture_output=True, text=True).stdout
    runs = [b for b in json.loads(out)["benchmarks"] if b.get("run_type") == "iteration"]
    cpp_rate = max(b["pairs_per_s"] for b in runs)
    print(f"evaluate order 8, {PAIRS} pairs: python {py_rate / 1e6:.2f} M pairs/s, C++ {cpp_rate / 1e6:.2f} M pairs/s, "
          f"ratio {py_rate / cpp_rate:.3f}")
    t0 = time.perf_counter()
    s = icobrdf.fit(icobrdf.Source("model:ggx:alpha=0.3"), level=4, order=8)
    t_fit = time.perf_counter() - t0
    print(f"fit GGX alpha 0.3, level 4, order 8: python {t_fit:.3f} s (order {s.order})")


if __name__ == "__main__":
    main()
