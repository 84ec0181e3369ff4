#!/usr/bin/env bash
# The main job: install what is missing, build, and run icobrdf on the shipped default.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh
exec scripts/run-default.sh
