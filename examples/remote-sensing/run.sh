#!/usr/bin/env bash
# Observations from a named kernel model with noise -> icobrdf fit (modes and kernels) -> albedos and a
# principal-plane plot. Usage: examples/remote-sensing/run.sh [ICOBRDF] (default: build/cli/icobrdf).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
icobrdf=${1:-$here/../../build/cli/icobrdf}
out=$here/out
mkdir -p "$out"
/usr/bin/python3 "$here/make_observations.py" -n 200 --seed 7 -o "$out/obs.csv"
"$icobrdf" fit "$out/obs.csv" -o "$out/fit.h5" -q
"$icobrdf" fit "$out/obs.csv" -o "$out/fit.h5" -q --json > "$out/fit.json" 2>/dev/null
/usr/bin/python3 "$here/principal_plane.py" "$out/fit.json" "$out/fit.h5" "$out/obs.csv" --icobrdf "$icobrdf" -o "$out/principal-plane.png"
