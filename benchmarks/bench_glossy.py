#!/usr/bin/python3
"""bench glossy: error against bytes and build time for the representations a bank can choose.

    /usr/bin/python3 benchmarks/bench_glossy.py build/cli/icobrdf [OUT_DIR]

For the glossy scene (examples/glossy-scene.toml) and the default scene (examples/default-scene.toml), builds
the bank once per representation set -- modes alone, half-angle alone, hybrid alone, and the bank's choice
among all three -- with `icobrdf bank build --json`, and records per material the representation, the
held-out relative L2 error, the bytes and the seconds. Then, for GGX (Schlick f0 = 0.04) of decreasing
alpha, the smallest alpha whose material still meets 0.02 within 1 MiB. Writes OUT_DIR/report.md (the
tables), OUT_DIR/glossy_error_bytes.png (error against bytes) and OUT_DIR/results.json; default OUT_DIR is
benchmarks/glossy. Timings are wall-clock seconds of this machine; run it on an idle machine.
"""
import json
import os
import re
import subprocess
import sys
import tempfile
import time

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
SETS = {"modes": ["modes"], "half-angle": ["half-angle"], "hybrid": ["hybrid"], "choice": ["modes", "half-angle", "hybrid"]}
ALPHAS = [0.05, 0.03, 0.02, 0.015, 0.01, 0.007, 0.005]
MIB = 1 << 20


def scene_with(path, representations, out):
    """The scene at `path` with its [bank] representations replaced."""
    text = open(path).read()
    text = re.sub(r"(?m)^representations = .*\n", "", text)
    line = "representations = [" + ", ".join(f'"{r}"' for r in representations) + "]\n"
    text = text.replace("[bank]\n", "[bank]\n" + line, 1)
    with open(out, "w") as f:
        f.write(text)
    return out


def build(icobrdf, scene, bank):
    t0 = time.monotonic()
    r = subprocess.run([icobrdf, "bank", "build", scene, "-o", bank, "--json", "--quiet"], capture_output=True, text=True)
    wall = time.monotonic() - t0
    out = json.loads(r.stdout) if r.stdout.strip() else {"materials": []}
    return out, wall


def run_scenes(icobrdf, tmp):
    results = {}
    for scene in ("glossy-scene", "default-scene"):
        for name, reps in SETS.items():
            s = scene_with(os.path.join(ROOT, "examples", scene + ".toml"), reps, os.path.join(tmp, f"{scene}-{name}.toml"))
            out, wall = build(icobrdf, s, os.path.join(tmp, f"{scene}-{name}.h5"))
            results[f"{scene}/{name}"] = {"wall_seconds": wall, "written": out.get("written", False), "materials": out["materials"]}
            print(f"{scene:14} {name:10} {wall:7.2f} s  written {out.get('written')}", flush=True)
    return results


def smallest_alpha(icobrdf, tmp):
    rows = []
    for alpha in ALPHAS:
        scene = os.path.join(tmp, f"alpha-{alpha}.toml")
        with open(scene, "w") as f:
            f.write(f"""[bank]
level = 4
levels = [3, 4]
order_max = 12
target = 0.02
metric = "cosine"
sampling = "centre"
holdout_pairs = 20000

[[material]]
name = "ggx"
source = "model:ggx:alpha={alpha},f0=0.04"
""")
        out, wall = build(icobrdf, scene, os.path.join(tmp, f"alpha-{alpha}.h5"))
        m = out["materials"][0] if out["materials"] else {"ok": False, "error": "no output"}
        ok = m.get("ok", False) and m.get("bytes", MIB + 1) <= MIB
        rows.append({"alpha": alpha, "ok": ok, "wall_seconds": wall, **{k: m.get(k) for k in ("representation", "error_l2", "bytes", "error")}})
        print(f"alpha {alpha}: {'met' if ok else 'not met'} {m.get('bytes')} bytes {m.get('error_l2') or m.get('error')}", flush=True)
    return rows


def table(results, key):
    lines = ["| material | representation | rel L2 | bytes | seconds |", "|---|---|---|---|---|"]
    for m in results[key]["materials"]:
        if m.get("ok"):
            lines.append(f"| {m['name']} | {m['representation']} | {m['error_l2']:.3g} | {m['bytes']} | {m['seconds']:.2f} |")
        else:
            lines.append(f"| {m['name']} | failed | | | |")
    return "\n".join(lines)


def figure(results, path):
    fig, ax = plt.subplots(figsize=(7, 4.5))
    marks = {"modes": "o", "half-angle": "s", "hybrid": "^"}
    for name in ("modes", "half-angle", "hybrid"):
        pts = [(m["bytes"], m["error_l2"]) for m in results[f"glossy-scene/{name}"]["materials"] if m.get("ok")]
        if pts:
            ax.scatter(*zip(*pts), marker=marks[name], label=f"{name} alone", alpha=0.8)
    ax.axhline(0.02, color="grey", linestyle="--", linewidth=0.8, label="target 0.02")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("bytes per material")
    ax.set_ylabel("held-out relative L2 error (cosine metric)")
    ax.set_title("Glossy scene: error against bytes per representation")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def main(icobrdf, out_dir=os.path.join(HERE, "glossy")):
    os.makedirs(out_dir, exist_ok=True)
    with tempfile.TemporaryDirectory() as tmp:
        results = run_scenes(icobrdf, tmp)
        alphas = smallest_alpha(icobrdf, tmp)
    figure(results, os.path.join(out_dir, "glossy_error_bytes.png"))
    with open(os.path.join(out_dir, "results.json"), "w") as f:
        json.dump({"scenes": results, "alphas": alphas}, f, indent=1)
    lines = ["# bench glossy", "", "`/usr/bin/python3 benchmarks/bench_glossy.py build/cli/icobrdf` (wall seconds of one run).", ""]
    for key, r in results.items():
        lines += [f"## {key}: {r['wall_seconds']:.2f} s, bank {'written' if r['written'] else 'NOT written'}", "", table(results, key), ""]
    lines += ["## GGX (f0 = 0.04) of decreasing alpha, target 0.02 within 1 MiB", "", "| alpha | met | representation | rel L2 | bytes | seconds |",
              "|---|---|---|---|---|---|"]
    for a in alphas:
        lines.append(f"| {a['alpha']} | {'yes' if a['ok'] else 'no'} | {a.get('representation') or '-'} | "
                     f"{a['error_l2'] if a.get('error_l2') is not None else '-'} | {a.get('bytes') or '-'} | {a['wall_seconds']:.2f} |")
    with open(os.path.join(out_dir, "report.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    print(f"wrote {out_dir}/report.md and glossy_error_bytes.png")


if __name__ == "__main__":
    if len(sys.argv) < 2:
        raise SystemExit(__doc__)
    main(*sys.argv[1:3])
