#!/usr/bin/env bash
# Times `icobrdf bank build` of a generated scene of N cheap analytic materials (default 1,000) on one process
# against `mpirun -np R` (default 2), one OpenMP thread per process, and checks that both give the same bank
# (bytes compared with each material's `seconds` figure masked, as tests/cli/bank_identity.hpp does).
#   benchmarks/bank_mpi.sh [ICOBRDF] [N] [RANKS] [REPEATS] [LEVEL]   (default build/cli/icobrdf 1000 2 1 3)
# LEVEL: the fitting level of every material (3: about 3 ms each; 4: about 20 ms each).
# Runs alternate (1 process, R ranks, 1 process, ...) so that load from elsewhere falls on both alike. Both
# runs print the --json report (the R-rank one is read for the materials per rank), so both pay for it.
# The materials: Lambert, Minnaert, Oren-Nayar, GGX, Beckmann and Phong over a range of parameters, each fitted
# at a fixed level (LEVEL, default 3) and order 6 (no level/order search), prune = false, a loose target (the fit is timed, not
# judged), 1024 held-out pairs, and no LUTs (store_lut = false: the bank holds the spectra), so that a
# material takes milliseconds and the per-material overhead of the distribution shows.
# Results: benchmarks/RESULTS.md, section "MPI bank build"; the cost model: docs/cluster.md.
set -euo pipefail
ICOBRDF=$(realpath "${1:-build/cli/icobrdf}")
N=${2:-1000}
RANKS=${3:-2}
REPEATS=${4:-1}
LEVEL=${5:-3}
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
scene=$dir/scene.toml
/usr/bin/python3 - "$N" "$LEVEL" >"$scene" <<'PY'
import sys
n, level = int(sys.argv[1]), int(sys.argv[2])
print('[bank]\nlevel = 3\nstore_lut = false\nholdout_pairs = 1024')
kinds = [
    lambda t: f"lambert:albedo={0.1 + 0.8 * t:.4f}",
    lambda t: f"minnaert:k={1.1 + 1.8 * t:.4f}",
    lambda t: f"oren-nayar:sigma={5 + 40 * t:.3f},albedo=0.7",
    lambda t: f"ggx:alpha={0.3 + 0.6 * t:.4f}",
    lambda t: f"beckmann:alpha={0.3 + 0.6 * t:.4f}",
    lambda t: f"phong:n={1 + 9 * t:.3f}",
]
for i in range(n):
    spec = kinds[i % len(kinds)]((i // len(kinds)) / max(1, n // len(kinds)))
    print(f'\n[[material]]\nname = "m{i:05d}"\nsource = "model:{spec}"\nlevel = {level}\norder = 6\ntarget = 100\nprune = false')
PY
export SOURCE_DATE_EPOCH=1700000000 OMP_NUM_THREADS=1 OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
# The bytes of a bank with every `seconds` figure (found by its 8 little-endian bytes) zeroed. With 1,000
# materials two of them can take the same time to the nanosecond, so every occurrence is zeroed: that can
# only hide a difference that happens to equal a timing of the same file (it never makes unequal banks equal
# otherwise).
masked() {
  "$ICOBRDF" bank info "$1" --json | /usr/bin/python3 -c '
import json, struct, sys
data = bytes(open(sys.argv[1], "rb").read())
timings = {m["name"]: struct.pack("<d", m["seconds"]) for m in json.load(sys.stdin)["materials"]}
missing = [name for name, le in timings.items() if le not in data]
if missing: sys.exit("seconds figure not found for " + ", ".join(missing))
for le in set(timings.values()): data = data.replace(le, bytes(8))
sys.stdout.buffer.write(data)' "$1"
}
echo "scene: $N materials; machine: $(nproc --all) vCPU, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'); load: $(cut -d' ' -f1-3 /proc/loadavg)"
for r in $(seq "$REPEATS"); do
  t0=$(date +%s.%N)
  /usr/bin/time -f "%U %S" -o "$dir/one.cpu" "$ICOBRDF" bank build "$scene" -o "$dir/one.h5" --quiet --json >"$dir/one.json" 2>/dev/null
  t1=$(date +%s.%N)
  /usr/bin/time -f "%U %S" -o "$dir/many.cpu" mpirun -q -np "$RANKS" --oversubscribe "$ICOBRDF" bank build "$scene" -o "$dir/many.h5" --quiet --json >"$dir/many.json" 2>/dev/null
  t2=$(date +%s.%N)
  masked "$dir/one.h5" >"$dir/one.masked"
  masked "$dir/many.h5" >"$dir/many.masked"
  same=$(cmp -s "$dir/one.masked" "$dir/many.masked" && echo identical || echo DIFFERENT)
  per_rank=$(/usr/bin/python3 -c '
import json, sys, collections
c = collections.Counter(m["rank"] for m in json.load(open(sys.argv[1]))["materials"])
print(" ".join(f"rank {r}: {c[r]}" for r in sorted(c)))' "$dir/many.json")
  # CPU seconds (user + system, every process of the run, mpirun's own included).
  cpu() { awk '{print $1 + $2}' "$1"; }
  /usr/bin/python3 -c 'import sys; a, b = float(sys.argv[1]), float(sys.argv[2]); print(f"run {sys.argv[3]}: 1 process {a:.2f} s (CPU {sys.argv[8]} s), {sys.argv[4]} ranks {b:.2f} s (CPU {sys.argv[9]} s), speed-up {a / b:.3f}; banks {sys.argv[5]} ({sys.argv[6]} bytes); materials per rank: {sys.argv[7]}")' \
    "$(echo "$t1 - $t0" | bc)" "$(echo "$t2 - $t1" | bc)" "$r" "$RANKS" "$same" "$(stat -c %s "$dir/one.h5")" "$per_rank" "$(cpu "$dir/one.cpu")" "$(cpu "$dir/many.cpu")"
done
echo "load after: $(cut -d' ' -f1-3 /proc/loadavg)"
