#!/usr/bin/env bash
# The main job on the shipped default: build the LUT bank of examples/default-scene.toml into
# out/default-bank.h5 and print, per material, the level, order, isotropy, kept coefficients and errors.
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${BUILD_DIR:-build}
mkdir -p out
"$BUILD_DIR"/cli/icobrdf bank build examples/default-scene.toml -o out/default-bank.h5
"$BUILD_DIR"/cli/icobrdf bank info out/default-bank.h5
