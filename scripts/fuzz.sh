#!/usr/bin/env bash
# Builds the libFuzzer targets of fuzz/ with clang into build-check (scripts/build-check.sh, shared with
# scripts/sanitize.sh) and runs each for SECONDS (default 60)
# from a fresh copy of its seed corpus fuzz/corpus/<reader>/, JOBS targets at a time (default: the number of
# cores). Exits non-zero on any finding: a crash, an ASan / UBSan report, an exception other than
# InputError / IoError, a multi-line message, an input taking longer than TIMEOUT seconds (default 10) or
# more than 2 GB. The input that caused it is kept as build-check/fuzz-run/<reader>/findings/*.
#   scripts/fuzz.sh [SECONDS]
#   TARGETS="merl sample_csv" scripts/fuzz.sh 30     only some targets
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-60}
timeout_s=${TIMEOUT:-10}
jobs=${JOBS:-$(nproc)}
scripts/install-deps.sh
BUILD_DIR=${CHECK_BUILD_DIR:-build-check}
scripts/build-check.sh fuzzers   # up to date after scripts/sanitize.sh

targets=${TARGETS:-$(for f in fuzz/fuzz_*.cpp; do basename "$f" .cpp | sed 's/^fuzz_//'; done)}
export ASAN_OPTIONS="halt_on_error=1:detect_leaks=1${ASAN_OPTIONS:+:$ASAN_OPTIONS}"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1${UBSAN_OPTIONS:+:$UBSAN_OPTIONS}"
export LSAN_OPTIONS="suppressions=$PWD/scripts/lsan-suppressions.txt:print_suppressions=0${LSAN_OPTIONS:+:$LSAN_OPTIONS}"

run_one() {  # reader name -> libFuzzer's exit status; log in fuzz-run/<reader>/log
  local t=$1 work="$BUILD_DIR/fuzz-run/$1"
  rm -rf "$work"
  mkdir -p "$work/corpus" "$work/findings"
  cp fuzz/corpus/"$t"/* "$work/corpus/"
  "$BUILD_DIR/fuzz/fuzz_$t" -max_total_time="$seconds" -timeout="$timeout_s" -rss_limit_mb=2048 \
    -artifact_prefix="$work/findings/" -print_final_stats=1 "$work/corpus" >"$work/log" 2>&1
}

declare -A pid_of
status=0
report() {  # reader name, exit status
  local log="$BUILD_DIR/fuzz-run/$1/log"
  if [ "$2" -ne 0 ]; then
    echo "FINDING: fuzz_$1 exited with $2; input kept in $BUILD_DIR/fuzz-run/$1/findings/, log $log:"
    grep -v '^#' "$log" | tail -n 60
    status=1
  else
    echo "fuzz_$1: no finding in ${seconds} s ($(grep -m1 -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$') runs, corpus $(ls "$BUILD_DIR/fuzz-run/$1/corpus" | wc -l) inputs, $(grep -o 'cov: [0-9]*' "$log" | tail -n 1))"
  fi
}
running=()
for t in $targets; do
  run_one "$t" &
  pid_of[$t]=$!
  running+=("$t")
  if [ ${#running[@]} -ge "$jobs" ]; then
    first=${running[0]}
    running=("${running[@]:1}")
    rc=0; wait "${pid_of[$first]}" || rc=$?
    report "$first" "$rc"
  fi
done
for t in "${running[@]}"; do
  rc=0; wait "${pid_of[$t]}" || rc=$?
  report "$t" "$rc"
done
exit $status
