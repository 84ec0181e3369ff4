#!/usr/bin/python3
"""bench rgl-export: the agreement of `icobrdf export SOURCE --format rgl` over seeds and materials.

    /usr/bin/python3 benchmarks/bench_rgl_export.py build/cli/icobrdf [RGL_DIR] [--seeds N] [--worst K]

For each source (a glossy bank material: half-angle lobe of GGX alpha 0.2, one of GGX alpha 0.05, the
analytic model 0.8 Lambert + 0.2 GGX alpha 0.2, and two RGL files of RGL_DIR read into a level-3 bank when
RGL_DIR is given) the export is written once, then for each seed s = 1 .. N:
  * report: icobrdf's RGL reader (`icobrdf eval FILE`) against `icobrdf eval SOURCE` at 20,000 pairs uniform
    in solid angle, cosine-weighted relative L2 (the figure the export's own report prints, at other draws);
  * numpy: the independent evaluator of tests/python/test_rgl_export_numpy.py against the source at 4,000 pairs.
Prints mean and max per source, the pairs where the file gives f < 0 (a file must not), and with --worst K the K pairs carrying the most of the report's error sum
(theta_i, theta_r, phi_r - phi_i in degrees, source and file values, share of the sum).
"""
import argparse
import math
import os
import subprocess
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "tests", "python"))
import test_rgl_export_numpy as rgl  # noqa: E402  (the independent evaluator)

REPORT_PAIRS = 20000
NUMPY_PAIRS = 4000
RGL_FILES = ["paper_white_rgb.bsdf", "ilm_l3_37_metallic_rgb.bsdf"]


def bank(exe, folder, name, source, level):
    scene = os.path.join(folder, name + ".toml")
    with open(scene, "w") as f:
        f.write(rgl.SCENE.replace("level = 2\nlevels = [2]", "level = %d\nlevels = [%d]" % (level, level))
                .replace('name = "lobe"', 'name = "%s"' % name).replace('"model:ggx:alpha=0.2,f0=0.04"', '"%s"' % source))
    out = os.path.join(folder, name + ".h5")
    rgl.run([exe, "bank", "build", scene, "-o", out, "--no-progress"])
    return out + "#" + name


def per_pair(a, b, wi, wo):
    w = (wi[:, 2] * wo[:, 2])[:, None]
    b = np.broadcast_to(b, a.shape)
    return ((w * (a - b)) ** 2).sum(axis=1), float(((w * b) ** 2).sum())


def main():
    p = argparse.ArgumentParser()
    p.add_argument("exe")
    p.add_argument("rgl_dir", nargs="?")
    p.add_argument("--seeds", type=int, default=5)
    p.add_argument("--worst", type=int, default=0)
    a = p.parse_args()
    with tempfile.TemporaryDirectory() as d:
        sources = [("bank GGX a0.2", bank(a.exe, d, "lobe", "model:ggx:alpha=0.2,f0=0.04", 2)),
                   ("bank GGX a0.05", bank(a.exe, d, "sharp", "model:ggx:alpha=0.05,f0=0.04", 4)),
                   ("0.8 Lambert + 0.2 GGX a0.2", "model:0.8*lambert:albedo=0.5+0.2*ggx:alpha=0.2,f0=0.04")]
        for name in RGL_FILES if a.rgl_dir else []:
            sources.append(("bank L3 " + name, bank(a.exe, d, name.split("_rgb")[0], os.path.join(a.rgl_dir, name), 3)))
        print("| source | report mean | report max | numpy mean | numpy max | file < 0 above horizon |")
        print("|---|---|---|---|---|---|")
        for label, source in sources:
            out = os.path.join(d, "x.bsdf")
            rgl.run([a.exe, "export", source, "--format", "rgl", "-o", out])
            reports, numpys, negative = [], [], 0
            for seed in range(1, a.seeds + 1):
                wi, wo = rgl.uniform_pairs(REPORT_PAIRS, 1000 + seed)
                ref = rgl.icobrdf_eval(a.exe, source, wi, wo, d)
                mine = rgl.icobrdf_eval(a.exe, out, wi, wo, d)
                negative += int((mine < 0).any(axis=1).sum())
                err, den = per_pair(mine, ref, wi, wo)
                reports.append(math.sqrt(err.sum() / den))
                for k in np.argsort(-err)[:a.worst]:
                    dphi = math.degrees(math.atan2(wo[k, 1], wo[k, 0]) - math.atan2(wi[k, 1], wi[k, 0])) % 360
                    print("  seed %d: theta_i %.2f theta_r %.3f dphi %.1f source %s file %s share %.3f" % (
                        seed, math.degrees(math.acos(wi[k, 2])), math.degrees(math.acos(wo[k, 2])), dphi,
                        np.array2string(ref[k], precision=4), np.array2string(mine[k], precision=4), err[k] / err.sum()))
                wi, wo = rgl.uniform_pairs(NUMPY_PAIRS, 2000 + seed)
                numpys.append(rgl.cosine_l2(rgl.rgl_eval(out, wi, wo), rgl.icobrdf_eval(a.exe, source, wi, wo, d), wi, wo))
            print("| %s | %.4f | %.4f | %.4f | %.4f | %d / %d |" % (label, np.mean(reports), max(reports), np.mean(numpys), max(numpys),
                                                                    negative, a.seeds * REPORT_PAIRS))
            sys.stdout.flush()
    return 0


if __name__ == "__main__":
    sys.exit(main())
