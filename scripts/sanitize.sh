#!/usr/bin/env bash
# Builds icobrdf with AddressSanitizer + UndefinedBehaviorSanitizer (clang -O1, scripts/build-check.sh, the
# build the fuzz stage reuses) into build-check and runs the whole CTest suite under them. Any sanitizer report ends the process that made
# it with a non-zero exit, so the test that ran it fails; the script's exit is CTest's.
#   scripts/sanitize.sh                 everything
#   scripts/sanitize.sh -R 'io_|core_'  extra arguments go to ctest (e.g. a subset)
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
BUILD_DIR=${CHECK_BUILD_DIR:-build-check}
scripts/build-check.sh
# halt_on_error: the first report ends the process (UBSan would otherwise print and go on).
# detect_leaks: LeakSanitizer checks every process at exit (it cannot run under ptrace, e.g. a debugger).
export ASAN_OPTIONS="halt_on_error=1:abort_on_error=0:detect_leaks=1:strict_string_checks=1:check_initialization_order=1${ASAN_OPTIONS:+:$ASAN_OPTIONS}"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1${UBSAN_OPTIONS:+:$UBSAN_OPTIONS}"
# Third-party caches kept until exit (fontconfig) are not leaks of ours: scripts/lsan-suppressions.txt.
export LSAN_OPTIONS="suppressions=$PWD/scripts/lsan-suppressions.txt:print_suppressions=0${LSAN_OPTIONS:+:$LSAN_OPTIONS}"
root=$PWD
cd "$BUILD_DIR"
# Without arguments every test runs except those below. Each one's instrumented code is run by another test
# here, and each one runs uninstrumented in the test stage; together they cost about 150 s of the stage's wall
# time (docs/reliability.md, "CI").
skip=(
  # build the same banks again and again to time signals (5 min each at -O1); BankKill.* and the bank tests
  # run that code here.
  'BankSignals[.]'
  # rerun the sweep CliBenchSweep.TinySweepRowsFollowTheGridDefinitions runs (about 19 s each at -O1) and
  # differ from it only in what they assert about its output.
  'CliBenchSweep[.](UnsupportedPairs|GramErrorShrinks|ErrorsMatchWhat|ParetoFront|ResultsFileAgrees|EveryReportSection)'
  # the level-8 grid (45 s): the code of levels 0-7, which the other tessellation tests build.
  'Tessellation[.]LevelEightBuildsAndValidates'
  # scalar quadrature of the Smith function (60 s): no buffer or index in it.
  'Microfacet[.]SmithLambdaSatisfiesTheVisibleAreaIdentity'
  # the full representation search of a sharp lobe (86 s): GlossyBank.* runs that search here.
  'CliBank[.]UnreachableTargetIsReportedWithTheBestAchieved'
  # chi-squared statistics over many draws (48 s together): the samplers' code runs here in
  # MaterialSampler.NarrowLobeConcentratesAroundTheMirror and the other sampler tests.
  'DirectionSampler[.]ChiSquaredAgainstPdf'
  'MaterialSampler[.]ChiSquaredFiveMaterialsFiveIncidences'
)
# And, when the uninstrumented suite has run in this clone (the test stage of .ci/run, build/), every test it
# measured at SANITIZE_SLOW_SECONDS or more (default 0.3; 1 until 2026-11-28, night: 39 more tests, about
# 190 of the instrumented suite's 510 test-seconds, measured on the merged tree; 0.5 until 2026-11-29: 47 more
# tests, about 135 instrumented test-seconds): on 2 cores CI went over its 45 minutes (58.5 min on 2026-11-28,
# 56.6 min on 2026-11-29), and these tests are about 12% of the suite but 80% of its test-seconds (tests/ sizes and repeats:
# sweeps, hard cases, white furnaces, thread and MPI comparisons, kills, budgets), which the sanitizers multiply
# several times. Their code paths stay instrumented here only where the faster tests reach them (the readers
# also under the fuzzers); each still runs uninstrumented in the test stage. The file lists each one's seconds.
slow_seconds=${SANITIZE_SLOW_SECONDS:-0.3}
costs=${RELEASE_BUILD_DIR:-$root/build}/Testing/Temporary/CTestCostData.txt
if [ $# -eq 0 ] && [ -f "$costs" ] && [ "$slow_seconds" != "0" ]; then
  mapfile -t slow < <(awk -v t="$slow_seconds" '$0 == "---" { exit } NF == 3 && $3 + 0 >= t + 0 { print $1 }' "$costs")
  # A fixture's setup test stays (ctest does not run it for the tests that need it once -E leaves it out).
  mapfile -t setups < <(ctest --show-only=json-v1 | /usr/bin/python3 -c 'import json, sys
for t in json.load(sys.stdin)["tests"]:
    if any(p["name"] == "FIXTURES_SETUP" for p in t.get("properties", [])): print(t["name"])')
  mapfile -t slow < <(printf '%s\n' "${slow[@]}" | grep -vxF -f <(printf '%s\n' "${setups[@]}"))
  echo "sanitize: leaving out ${#slow[@]} tests of ${slow_seconds} s or more in the uninstrumented run ($costs)"
  for t in "${slow[@]}"; do skip+=("$(printf '%s' "$t" | sed 's/[^A-Za-z0-9_/:-]/[&]/g')\$"); done
fi
if [ $# -eq 0 ]; then set -- -E "^($(IFS='|'; echo "${skip[*]}"))"; fi
ctest --output-on-failure -j"${JOBS:-$(nproc)}" "$@"
