#!/usr/bin/env bash
# Runs the main job on the shipped default with an already built program.
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${BUILD_DIR:-build}
"$BUILD_DIR"/cli/icobrdf info
