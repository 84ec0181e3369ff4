#!/usr/bin/env bash
# scripts/gallery.sh ICOBRDF OUT_DIR [--check DOC]: one picture of each kind `icobrdf plot` draws, written to
# OUT_DIR (docs/gallery/ holds the committed copies; docs/gallery.md shows them). Analytic models, the small measured
# fixture of the tests (tests/data/measured/ptfe532.csv) and a bank of one material built here, so that the gallery
# needs neither the network nor /work/data, and small sizes (tens of KB each).
# With --check DOC it also fails when DOC does not show every picture the script writes (the CTest
# `plot_gallery` runs it so into the build tree).
set -euo pipefail
bin=$1 out=$2
root=$(cd "$(dirname "$0")/.." && pwd)
mkdir -p "$out"
plot() { "$bin" plot "$@" > /dev/null; }
plot basis --order 2 --panel 48 -o "$out/basis.png"
plot slice 'model:ggx:alpha=0.3' --theta-i 45 --order 2,4,6 --level 3 --panel 100 -o "$out/slice_orders.png"
plot slice 'model:ggx:alpha=0.3' --theta-i 45 --order 6 --level 3 --panel 100 --log -o "$out/slice_log.png"
"$bin" fit 'model:lambert+0.2*ggx' --order 6 --level 3 -o "$out/spectrum.h5" > /dev/null
plot spectrum "$out/spectrum.h5" -o "$out/spectrum.png"
rm -f "$out/spectrum.h5"
plot sphere 'model:ggx:alpha=0.2' --size 128 --sky -o "$out/sphere.png"
plot curves 'model:ggx:alpha=0.2' --theta-i 0,30,60 --log -o "$out/curves.png"
plot albedo 'model:ggx:alpha=0.2' -o "$out/albedo.png"
plot halfdiff 'model:ggx:alpha=0.2' --log -o "$out/halfdiff.png"
plot halfdiff 'model:ggx:alpha=0.2' --log --phi-d 0 -o "$out/halfdiff_phid0.png"
plot samples "$root/tests/data/measured/ptfe532.csv" -o "$out/samples.png"
printf '[bank]\nlevels = [1, 2]\norder_max = 4\nholdout_pairs = 2000\n[[material]]\nname = "ggx"\nsource = "model:ggx:alpha=0.3"\ntarget = 0.05\n' > "$out/bytes.toml"
"$bin" bank build "$out/bytes.toml" -o "$out/bytes.h5" --quiet > /dev/null
plot bytes "$out/bytes.h5#ggx" -o "$out/bytes.png"
rm -f "$out/bytes.toml" "$out/bytes.h5"
if [ "${3:-}" = "--check" ]; then
  doc=$4
  for f in "$out"/*.png; do
    grep -q "gallery/$(basename "$f")" "$doc" || { echo "gallery: $doc does not show $(basename "$f")" >&2; exit 1; }
  done
fi
