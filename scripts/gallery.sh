#!/usr/bin/env bash
# scripts/gallery.sh ICOBRDF OUT_DIR [--check DOC]: one picture of each kind `icobrdf plot` draws, written to
# OUT_DIR (docs/gallery/ holds the committed copies; docs/gallery.md shows them). Analytic models only, so that
# the gallery needs neither the network nor measured data, and small sizes (tens of KB each).
# With --check DOC it also fails when DOC does not show every picture the script writes (the CTest
# `plot_gallery` runs it so into the build tree).
set -euo pipefail
bin=$1 out=$2
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
if [ "${3:-}" = "--check" ]; then
  doc=$4
  for f in "$out"/*.png; do
    grep -q "gallery/$(basename "$f")" "$doc" || { echo "gallery: $doc does not show $(basename "$f")" >&2; exit 1; }
  done
fi
