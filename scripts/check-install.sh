#!/usr/bin/env bash
# The installed package as a consumer sees it (issue #15, docs/api.md): installs BUILD into a prefix, moves the
# prefix elsewhere (the package must be relocatable), then builds the C++ examples (examples/cpp) against it
# twice and runs them: with -march=native under AddressSanitizer + UBSan, and for the baseline x86-64 ISA
# without sanitizers (ASan's allocator hides the failure an alignment mismatch causes: with the pin removed,
# the uninstrumented baseline build aborts with "double free or corruption", status 134, while a baseline ASan
# build passes, which is why that third build, once here, was left out: it cost a third of the test's 59 s,
# which runs alone). A library built with one set of ISA flags must work from programs built with another: Eigen's
# alignment is pinned in the exported interface (icobrdf/core/CMakeLists.txt). The examples declare CXX alone
# (project(... LANGUAGES CXX)): the package finds HDF5 without a C compiler. Also checks that the program is in the
# prefix's bin/ and runs from there, that a consumer of icobrdf::core alone configures with every other dependency
# hidden, that one of icobrdf::io (declaring C and CXX: HDF5 through CMake's FindHDF5) configures, builds and runs
# with BLAS and LAPACK hidden, and that one of the optional component blas installs its kernels and runs the
# program through the imported executable icobrdf::program.
#   scripts/check-install.sh [BUILD_DIR] [WORK_DIR]     (CTest runs it as the test install_package)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=$(cd "${1:-$root/build}" && pwd)
work=${2:-$build/check-install}
rm -rf "$work"
mkdir -p "$work"
jobs=${JOBS:-2}

step() { echo "--- check-install: $*"; }

step "install into $work/staging, then move it to $work/prefix"
cmake --install "$build" --prefix "$work/staging" >"$work/install.log"
mv "$work/staging" "$work/prefix"
prefix="$work/prefix"
for f in bin/icobrdf lib/cmake/icobrdf/icobrdfConfig.cmake lib/cmake/icobrdf/icobrdfConfigVersion.cmake include/icobrdf/icobrdf.hpp \
  include/icobrdf/core/grid/grid.hpp include/icobrdf/blas/blas_dense_kernels.hpp lib/libicobrdf_core.a lib/libicobrdf_blas.a \
  lib/libicobrdf_pipeline.a; do
  [ -e "$prefix/$f" ] || { echo "check-install: the package lacks $f" >&2; exit 1; }
done
if grep -rq "$root" "$prefix/lib/cmake/icobrdf"; then
  echo "check-install: the package config names the source tree ($root): not relocatable" >&2
  exit 1
fi
step "the installed program runs from the relocated prefix"
# Into a file first: grep -q leaving a pipe early would end the program with SIGPIPE, a failure under pipefail.
"$prefix/bin/icobrdf" models >"$work/models.txt" && grep -q "^lambert" "$work/models.txt" ||
  { echo "check-install: $prefix/bin/icobrdf models did not list lambert" >&2; exit 1; }

export ASAN_OPTIONS="halt_on_error=1:detect_leaks=1"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"
export LSAN_OPTIONS="suppressions=$root/scripts/lsan-suppressions.txt:print_suppressions=0"
sanitize="-O1 -g -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=all"
for variant in native-asan baseline-plain; do
  case $variant in
    native-asan) flags="-march=native $sanitize" link="-fsanitize=address,undefined" ;;
    baseline-plain) flags="-march=x86-64 -mtune=generic" link="" ;;
  esac
  out="$work/examples-$variant"
  step "examples built with $flags against the installed package"
  cmake -S "$root/examples/cpp" -B "$out" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_PREFIX_PATH="$prefix" \
    -DCMAKE_CXX_FLAGS="$flags" -DCMAKE_EXE_LINKER_FLAGS="$link" >"$out.configure.log"
  cmake --build "$out" -j"$jobs" >"$out.build.log" 2>&1 || { tail -n 30 "$out.build.log" >&2; exit 1; }
  (cd "$out" && ./example_fit_smooth_eval ggx.h5 && ./example_bank_eval ggx.h5 && ./example_lut_operators) >"$out.run.log" 2>&1 ||
    { echo "check-install: an example built with $flags failed:" >&2; tail -n 30 "$out.run.log" >&2; exit 1; }
done

if [ -n "$(ls "$prefix"/lib/python3/dist-packages/icobrdf*.so 2>/dev/null)" ]; then
  step "the installed Python module imports from the relocated prefix"
  PYTHONPATH="$prefix/lib/python3/dist-packages" /usr/bin/python3 -c \
    'import icobrdf, sys; g = icobrdf.Grid.equal_area(2); sys.exit(0 if g.cells == 10 * 4**2 + 2**3 else 1)' ||
    { echo "check-install: the installed Python module failed" >&2; exit 1; }
fi

# consumer NAME LANGUAGES COMPONENT [ABSENT]: writes $work/NAME/CMakeLists.txt, a project of LANGUAGES ("CXX" or
# "C CXX") with a program NAME (NAME/main.cpp) that asks the package for COMPONENT alone and links
# icobrdf::COMPONENT, refusing to configure if icobrdf::ABSENT was loaded.
consumer() {
  mkdir -p "$work/$1"
  {
    printf 'cmake_minimum_required(VERSION 3.20)\nproject(%s LANGUAGES %s)\n' "$1" "$2"
    printf 'find_package(icobrdf REQUIRED COMPONENTS %s)\n' "$3"
    [ -z "${4:-}" ] || printf 'if(TARGET icobrdf::%s)\n  message(FATAL_ERROR "icobrdf::%s was loaded although only %s was asked for")\nendif()\n' "$4" "$4" "$3"
    printf 'add_executable(%s main.cpp)\ntarget_link_libraries(%s PRIVATE icobrdf::%s)\n' "$1" "$1" "$3"
  } >"$work/$1/CMakeLists.txt"
}
# build_consumer NAME [CMAKE_ARGS...]: configures (against the relocated prefix) and builds it.
build_consumer() {
  local name=$1
  shift
  cmake -S "$work/$name" -B "$work/$name/build" -DCMAKE_PREFIX_PATH="$prefix" "$@" >"$work/$name.configure.log" 2>&1 ||
    { tail -n 30 "$work/$name.configure.log" >&2; exit 1; }
  cmake --build "$work/$name/build" >"$work/$name.build.log" 2>&1 || { tail -n 30 "$work/$name.build.log" >&2; exit 1; }
}

step "a consumer of icobrdf::core alone, with OpenMesh, HDF5, fmt, toml++, nlohmann_json and cairo hidden"
consumer core_only CXX core io
cat >"$work/core_only/main.cpp" <<'CPP'
#include <cstdio>
#include <icobrdf/core/basis/hemisphere_basis.hpp>
int main() { std::printf("%d modes up to order 8\n", icobrdf::hemisphere_basis_count(8)); }
CPP
build_consumer core_only -DCMAKE_DISABLE_FIND_PACKAGE_OpenMesh=ON -DCMAKE_DISABLE_FIND_PACKAGE_HDF5=ON \
  -DCMAKE_DISABLE_FIND_PACKAGE_fmt=ON -DCMAKE_DISABLE_FIND_PACKAGE_tomlplusplus=ON -DCMAKE_DISABLE_FIND_PACKAGE_nlohmann_json=ON \
  -DCMAKE_DISABLE_FIND_PACKAGE_PkgConfig=ON
"$work/core_only/build/core_only" | grep -q "^45 modes up to order 8$" || { echo "check-install: core_only printed the wrong count" >&2; exit 1; }

step "a consumer of icobrdf::io (C and CXX) with BLAS and LAPACK hidden: io's measured SOURCEs take core's default (Eigen's) kernels"
consumer io_only "C CXX" io blas
# A CSV of samples opened as a SOURCE links io's measured sources, whose fits take core's default dense kernels.
cat >"$work/io_only/main.cpp" <<'CPP'
#include <cstdio>
#include <fstream>
#include <icobrdf/core/fit/dense_kernels.hpp>
#include <icobrdf/io/brdf_source.hpp>
int main(int argc, char** argv) {
  if (argc != 2) return 2;
  std::ofstream(argv[1]) << "theta_i,phi_i,theta_r,phi_r,value\n10,0,20,180,0.3\n30,90,40,10,0.3\n";
  const auto source = icobrdf::open_source(argv[1]);
  std::printf("%d channel, dense kernels %s\n", source->channels(), icobrdf::default_dense_kernels().name);
}
CPP
build_consumer io_only -DCMAKE_DISABLE_FIND_PACKAGE_BLAS=ON -DCMAKE_DISABLE_FIND_PACKAGE_LAPACK=ON
"$work/io_only/build/io_only" "$work/io_only/samples.csv" | grep -q "^1 channel, dense kernels Eigen$" ||
  { echo "check-install: io_only did not open the samples with Eigen's default kernels" >&2; exit 1; }

step "a consumer of icobrdf::blas that installs its choice as core's default dense kernels and runs icobrdf::program"
consumer blas_only CXX blas
# The imported program runs at build time: its list of models, written by a custom command.
printf 'add_custom_command(OUTPUT models.txt COMMAND icobrdf::program models > models.txt)\nadd_custom_target(models ALL DEPENDS models.txt)\n' \
  >>"$work/blas_only/CMakeLists.txt"
cat >"$work/blas_only/main.cpp" <<'CPP'
#include <cstdio>
#include <icobrdf/blas/blas_dense_kernels.hpp>
int main() {
  icobrdf::set_default_dense_kernels(&icobrdf::fit_dense_kernels());
  std::printf("default %s: %s\n", icobrdf::default_dense_kernels().name, icobrdf::fit_kernel_choice().reason.c_str());
  return &icobrdf::default_dense_kernels() == icobrdf::fit_kernel_choice().kernels ? 0 : 1;
}
CPP
build_consumer blas_only
grep -q "^lambert" "$work/blas_only/build/models.txt" || { echo "check-install: icobrdf::program did not run in the consumer's build" >&2; exit 1; }
"$work/blas_only/build/blas_only" >"$work/blas_only.run.log" ||
  { echo "check-install: blas_only failed" >&2; cat "$work/blas_only.run.log" >&2; exit 1; }

echo "check-install: 3 examples (CXX only) ran clean against the relocated package (native ISA under ASan + UBSan, baseline ISA without); bin/icobrdf runs; core alone links; io (C and CXX) links without BLAS or LAPACK; blas installs its kernels and runs icobrdf::program"
