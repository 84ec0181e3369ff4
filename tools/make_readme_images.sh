#!/usr/bin/env bash
# Regenerates the pictures of the README (docs/images/*.png) with the icobrdf program:
# the basis functions, mirror and retroreflector slices (the paper's Figs. 1-2, 4-6), a spectrum overview
# (Fig. 3) and the spheres of the default scene's materials.
# Usage: tools/make_readme_images.sh [path/to/icobrdf]   (default: build/cli/icobrdf)
set -euo pipefail
cd "$(dirname "$0")/.."
ICOBRDF=$(realpath "${1:-build/cli/icobrdf}")
OUT=docs/images
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
mkdir -p "$OUT"
ROOT=$PWD

"$ICOBRDF" bank build examples/default-scene.toml -o "$TMP/default-bank.h5" >/dev/null 2>&1
(cd "$TMP" && "$ICOBRDF" plot sphere default-bank.h5 --light 45,135 --sky --exposure 1.3 --size 120 -o "$ROOT/$OUT/default-spheres.png")

"$ICOBRDF" plot basis --order 4 --panel 96 -o "$TMP"
cp "$TMP/basis.png" "$OUT/basis-order4.png"

"$ICOBRDF" plot slice "model:mirror+0.05*lambert" --theta-i 45 --order 0 1 2 4 6 8 --panel 112 -o "$OUT/mirror-slice-45.png"
"$ICOBRDF" plot slice "model:mirror+0.05*lambert" --theta-i 45 --order 8 --filter hann --panel 112 -o "$OUT/mirror-slice-45-hann.png"
"$ICOBRDF" plot slice "model:retroreflector+0.05*lambert" --theta-i 67.5 --order 2 4 8 --panel 112 -o "$OUT/retro-slice-67.png"
"$ICOBRDF" plot slice "model:ggx:alpha=0.3" --theta-i 45 --order 2 4 8 --panel 112 -o "$OUT/ggx-slice-45.png"

"$ICOBRDF" fit "model:0.5*lambert+0.5*phong:n=4,ks=0.8" --order 8 --level 4 --isotropic -o "$TMP/phong.h5" >/dev/null
(cd "$TMP" && "$ICOBRDF" plot spectrum phong.h5 -o "$ROOT/$OUT/phong-spectrum.png")

ls -l "$OUT"/*.png
