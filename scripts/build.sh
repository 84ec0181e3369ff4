#!/usr/bin/env bash
# Configures and builds icobrdf into build/ (Release). Extra arguments go to cmake's configure step.
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${BUILD_DIR:-build}
# Ninja for a new build directory when it is installed (scripts/install-deps.sh installs it): it compiles any
# target's objects as soon as their own inputs exist, where make starts a target only after the libraries it
# links are built, so one core idled behind the slowest library batch (docs/reliability.md, "CI").
gen=()
[ -f "$BUILD_DIR/CMakeCache.txt" ] || ! command -v ninja >/dev/null || gen=(-G Ninja)
cmake -S . -B "$BUILD_DIR" "${gen[@]}" -DCMAKE_BUILD_TYPE=Release "$@" >/dev/null
cmake --build "$BUILD_DIR" -j"${JOBS:-$(nproc)}"
