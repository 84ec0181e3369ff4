#!/usr/bin/python3
"""`icobrdf export SOURCE --format rgl` read by an independent RGL evaluator written here in numpy from the
format's description (Dupuy & Jakob 2018; the evaluation of Mitsuba 3's `measured` BSDF), against
`icobrdf eval` of the source: a glossy bank material (half-angle lobe of GGX alpha 0.2) built from a
one-material scene.

Run as: /usr/bin/python3 tests/python/test_rgl_export_numpy.py <path to icobrdf>
Exits 77 (skipped) without numpy; prints the figures and exits non-zero on failure.
"""
import math
import os
import struct
import subprocess
import sys
import tempfile

try:
    import numpy as np
except ImportError:
    print("numpy is not available: skipped")
    sys.exit(77)

# The export's acceptance figure: cosine-weighted relative L2 against the source.
AGREEMENT = 0.03
# The same file through icobrdf's RGL reader and through this evaluator: the same definitions in float64,
# different arithmetic (and the tables' float32 values are read the same): rounding, relative to the norm.
SAME_FILE_TOL = 1e-9
PAIRS = 4000

SCENE = """
[bank]
level = 2
levels = [2]
order_max = 4
target = 0.02
metric = "cosine"
sampling = "centre"
holdout_pairs = 2048
representations = ["half-angle"]

[[material]]
name = "lobe"
source = "model:ggx:alpha=0.2,f0=0.04"
"""

DTYPES = {1: "u1", 2: "i1", 3: "<u2", 4: "<i2", 5: "<u4", 6: "<i4", 7: "<u8", 8: "<i8", 9: "<f2", 10: "<f4", 11: "<f8"}


def read_tensor_file(path):
    """{name: ndarray} of a tensor file: magic, version 1.0, field count, then per field name, ndim, dtype,
    offset and shape; data in C order at the offset."""
    buf = open(path, "rb").read()
    assert buf[:12] == b"tensor_file\0" and buf[12:14] == b"\x01\x00", path
    (count,) = struct.unpack_from("<I", buf, 14)
    pos, fields = 18, {}
    for _ in range(count):
        (n,) = struct.unpack_from("<H", buf, pos)
        name = buf[pos + 2:pos + 2 + n].decode()
        pos += 2 + n
        ndim, dtype, offset = struct.unpack_from("<HBQ", buf, pos)
        pos += 11
        shape = struct.unpack_from("<%dQ" % ndim, buf, pos)
        pos += 8 * ndim
        fields[name] = np.frombuffer(buf, DTYPES[dtype], int(np.prod(shape)), offset).reshape(shape).astype(np.float64)
    return fields


def axis_weights(nodes, x):
    """Linear interpolation on an increasing axis, ends held: (index of the lower node, weight of the upper)."""
    if len(nodes) == 1:
        return np.zeros(len(x), int), np.zeros(len(x))
    i = np.clip(np.searchsorted(nodes, x, side="left") - 1, 0, len(nodes) - 2)
    t = np.clip((x - nodes[i]) / (nodes[i + 1] - nodes[i]), 0.0, 1.0)
    return i, t


def bilinear(table, x, y):
    """table [..., H, W] per pair (leading axis = pairs), x along W, y along H, both in [0, 1]."""
    h, w = table.shape[-2:]
    ix = np.minimum((x * (w - 1)).astype(int), w - 2)
    iy = np.minimum((y * (h - 1)).astype(int), h - 2)
    fx, fy = x * (w - 1) - ix, y * (h - 1) - iy
    p = np.arange(len(x))
    c0 = (1 - fx) * table[p, iy, ix] + fx * table[p, iy, ix + 1]
    c1 = (1 - fx) * table[p, iy + 1, ix] + fx * table[p, iy + 1, ix + 1]
    return (1 - fy) * c0 + fy * c1


class Warp:
    """The continuous marginal-conditional warp of a bilinear density on the unit square, one table per
    slice: the normalized density, the cumulative integrals along each row, and the marginal over rows."""

    def __init__(self, density):  # [S, H, W]
        s, h, w = density.shape
        cond = np.zeros_like(density)
        cond[..., 1:] = np.cumsum(0.5 * (density[..., 1:] + density[..., :-1]), axis=-1) / (w - 1)
        rows = cond[..., -1]
        marg = np.zeros((s, h))
        marg[:, 1:] = np.cumsum(0.5 * (rows[:, 1:] + rows[:, :-1]), axis=-1) / (h - 1)
        norm = 1.0 / marg[:, -1]
        self.density, self.cond, self.marg = density * norm[:, None, None], cond * norm[:, None, None], marg * norm[:, None]

    def invert(self, x, y, slices, weights):
        """Point -> sample, tables blended over (slice, weight) lists per pair."""
        def blend(t):
            return sum(wt[(...,) + (None,) * (t.ndim - 1)] * t[sl] for sl, wt in zip(slices, weights))
        d, c, m = blend(self.density), blend(self.cond), blend(self.marg)
        h, w = d.shape[-2:]
        ix = np.minimum((x * (w - 1)).astype(int), w - 2)
        iy = np.minimum((y * (h - 1)).astype(int), h - 2)
        fx, fy = x * (w - 1) - ix, y * (h - 1) - iy
        p = np.arange(len(x))
        c0 = (1 - fy) * d[p, iy, ix] + fy * d[p, iy + 1, ix]
        c1 = (1 - fy) * d[p, iy, ix + 1] + fy * d[p, iy + 1, ix + 1]
        sx = fx * (c0 + 0.5 * fx * (c1 - c0)) / (w - 1) + (1 - fy) * c[p, iy, ix] + fy * c[p, iy + 1, ix]
        r0, r1 = c[p, iy, w - 1], c[p, iy + 1, w - 1]
        sx = np.minimum(sx / ((1 - fy) * r0 + fy * r1), 1.0)
        sy = fy * (r0 + 0.5 * fy * (r1 - r0)) / (h - 1) + m[p, iy]
        return sx, sy


def rgl_eval(path, wi, wo):
    """f [1/sr] (pairs x 3) of an isotropic RGB RGL file: w_i selects the slice; Mitsuba's eval divided by
    cos theta_o."""
    t = read_tensor_file(path)
    theta_nodes, phi_nodes = t["theta_i"], t["phi_i"]
    assert len(phi_nodes) <= 2, "isotropic files only"
    elevation = lambda v: 2 * np.arcsin(np.minimum(1.0, 0.5 * np.linalg.norm(v - np.array([0, 0, 1.0]), axis=1)))
    m = wi + wo
    m /= np.linalg.norm(m, axis=1)[:, None]
    theta_i, phi_i = elevation(wi), np.arctan2(wi[:, 1], wi[:, 0])
    theta_m, phi_m = elevation(m), np.arctan2(m[:, 1], m[:, 0])
    ux = np.sqrt(theta_m * 2 / math.pi)
    uy = (phi_m - phi_i + math.pi) / (2 * math.pi)
    uy -= np.floor(uy)
    it, tt = axis_weights(theta_nodes, theta_i)
    vndf = t["vndf"][0]  # [n_t, H, W] (one phi_i node)
    sx, sy = Warp(vndf).invert(ux, uy, [it, it + 1], [1 - tt, tt])
    rgb = t["rgb"][0]  # [n_t, 3, H, W]
    n = len(wi)
    ndf = bilinear(np.broadcast_to(t["ndf"], (n,) + t["ndf"].shape), ux, uy)
    sigma = bilinear(np.broadcast_to(t["sigma"], (n,) + t["sigma"].shape), np.sqrt(theta_i * 2 / math.pi), (phi_i + math.pi) / (2 * math.pi))
    scale = ndf / (4 * sigma) if t["jacobian"][0] == 1 else np.ones(n)
    out = np.zeros((n, 3))
    for c in range(3):
        v = (1 - tt) * bilinear(rgb[it, c], sx, sy) + tt * bilinear(rgb[it + 1, c], sx, sy)
        out[:, c] = v * scale / np.maximum(wo[:, 2], 1e-6)
    return out


def run(args, **kw):
    r = subprocess.run(args, capture_output=True, text=True, **kw)
    if r.returncode != 0:
        raise SystemExit("%s failed (%d): %s" % (" ".join(args), r.returncode, r.stderr.strip()))
    return r.stdout


def uniform_pairs(n, seed):
    rng = np.random.default_rng(seed)
    def draw():
        z, phi = rng.random(n), 2 * math.pi * rng.random(n)
        s = np.sqrt(1 - z * z)
        return np.stack([s * np.cos(phi), s * np.sin(phi), z], axis=1)
    return draw(), draw()


def icobrdf_eval(exe, source, wi, wo, folder):
    csv = os.path.join(folder, "pairs.csv")
    with open(csv, "w") as f:
        f.write("theta_i,phi_i,theta_r,phi_r\n")
        for a, b in zip(wi, wo):
            f.write("%.17g,%.17g,%.17g,%.17g\n" % (math.acos(min(1.0, a[2])), math.atan2(a[1], a[0]), math.acos(min(1.0, b[2])), math.atan2(b[1], b[0])))
    lines = run([exe, "eval", source, "--at", csv, "--radians"]).strip().splitlines()[1:]
    return np.array([[float(x) for x in line.split(",")] for line in lines])


def cosine_l2(a, b, wi, wo):
    w = (wi[:, 2] * wo[:, 2])[:, None]
    b = np.broadcast_to(b, a.shape)
    return float(np.linalg.norm(w * (a - b)) / np.linalg.norm(w * b))


def main():
    exe = sys.argv[1]
    failures = 0
    with tempfile.TemporaryDirectory() as d:
        with open(os.path.join(d, "scene.toml"), "w") as f:
            f.write(SCENE)
        run([exe, "bank", "build", os.path.join(d, "scene.toml"), "-o", os.path.join(d, "bank.h5"), "--no-progress"])
        wi, wo = uniform_pairs(PAIRS, 5)
        # The bank material only (the analytic model's export is checked by the C++ tests; each case costs seconds).
        for source in [os.path.join(d, "bank.h5") + "#lobe"]:
            out = os.path.join(d, "x.bsdf")
            run([exe, "export", source, "--format", "rgl", "-o", out])
            mine = rgl_eval(out, wi, wo)
            reference = icobrdf_eval(exe, source, wi, wo, d)
            reader = icobrdf_eval(exe, out, wi, wo, d)
            agreement, same = cosine_l2(mine, reference, wi, wo), cosine_l2(mine, reader, wi, wo)
            ok = agreement <= AGREEMENT and same <= SAME_FILE_TOL
            failures += not ok
            print("%s %s: numpy evaluator vs icobrdf eval of the source %.4g (<= %g); vs icobrdf's RGL reader %.2g (<= %g)"
                  % ("ok  " if ok else "FAIL", os.path.basename(source), agreement, AGREEMENT, same, SAME_FILE_TOL))
    print("%d passed, %d failed" % (1 - failures, failures))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
