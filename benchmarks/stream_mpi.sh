#!/usr/bin/env bash
# Times the streaming projection of one material, `icobrdf fit SOURCE --level L --order N`, on one process
# against `mpirun -np R` (default 2), and compares the coefficient matrices the two wrote: the largest
# entry-wise difference relative to max|C| (the issue's "agrees with one process to rounding"), and, from a
# second distributed run, whether two distributed runs give the same bits.
#   benchmarks/stream_mpi.sh ICOBRDF SOURCE LEVEL ORDER [RANKS] [THREADS]
#     THREADS: OpenMP threads per process ("default": OMP_NUM_THREADS unset, all cores per process)
# Each process runs under /usr/bin/time -v: its wall time and peak resident memory (per rank) are printed.
# Every run is a whole `fit` (grid, operators, projection, writing); docs/cluster.md separates the parts.
# Results: benchmarks/RESULTS.md, section "Distributed streaming projection".
set -euo pipefail
ICOBRDF=$(realpath "$1")
SOURCE=$2
LEVEL=$3
ORDER=$4
RANKS=${5:-2}
THREADS=${6:-1}
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 ICOBRDF_PROGRESS_DELAY=1000000
if [ "$THREADS" = default ]; then unset OMP_NUM_THREADS; else export OMP_NUM_THREADS=$THREADS; fi
# One process of a run: /usr/bin/time -v into TAG.RANK.time (rank 0 without mpirun).
cat >"$dir/one_process.sh" <<'SH'
#!/bin/sh
tag=$1
shift
exec /usr/bin/time -v -o "$tag.${OMPI_COMM_WORLD_RANK:-0}.time" "$@"
SH
chmod +x "$dir/one_process.sh"
timed() {  # timed OUT.h5 TAG [mpirun args...]: one fit
  local out=$1 tag=$2
  shift 2
  "$@" "$dir/one_process.sh" "$dir/$tag" "$ICOBRDF" fit "$SOURCE" --level "$LEVEL" --order "$ORDER" -o "$out" --quiet >/dev/null
}
report() {  # report TAG: wall seconds and peak RSS of each process of the run
  for f in "$dir/$1".*.time; do
    awk -v f="$(basename "$f" .time)" '/Elapsed \(wall clock\)/ {w=$NF} /Maximum resident set size/ {m=$NF} /User time/ {u=$NF} /System time/ {s=$NF}
      END {n=split(w, p, ":"); sec=(n==3 ? p[1]*3600+p[2]*60+p[3] : p[1]*60+p[2]); printf "  %s: wall %.1f s, CPU %.1f s, peak RSS %.0f MB\n", f, sec, u+s, m/1024}' "$f"
  done
}
echo "fit $SOURCE level $LEVEL order $ORDER; $RANKS ranks; threads per process: $THREADS"
echo "machine: $(nproc --all) vCPU, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'); load before: $(cut -d' ' -f1-3 /proc/loadavg)"
t0=$(date +%s.%N)
timed "$dir/one.h5" one
t1=$(date +%s.%N)
timed "$dir/many.h5" many mpirun -q -np "$RANKS" --oversubscribe
t2=$(date +%s.%N)
timed "$dir/again.h5" again mpirun -q -np "$RANKS" --oversubscribe
t3=$(date +%s.%N)
echo "1 process: $(echo "$t1 - $t0" | bc) s; $RANKS ranks: $(echo "$t2 - $t1" | bc) s, again $(echo "$t3 - $t2" | bc) s (wall, mpirun included)"
report one
report many
report again
/usr/bin/python3 - "$dir/one.h5" "$dir/many.h5" "$dir/again.h5" <<'PY'
import sys, h5py, numpy as np
c = [h5py.File(f)["materials/material/C"][()] for f in sys.argv[1:]]
scale = np.abs(c[0]).max()
print(f"  C: {c[0].shape}, max|C| {scale:.6g}; max|C_R - C_1| / max|C_1| = {np.abs(c[1] - c[0]).max() / scale:.3e}; "
      f"entries that differ: {np.count_nonzero(c[1] != c[0])} of {c[0].size}; two distributed runs bitwise equal: {bool((c[1] == c[2]).all())}")
PY
echo "load after: $(cut -d' ' -f1-3 /proc/loadavg)"
