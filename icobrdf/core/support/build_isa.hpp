#pragma once
// The x86-64 instruction-set extensions icobrdf was compiled for, and the check that the CPU running a
// program has them (docs/api.md, "ABI and portability").
//
// A library built with ICOBRDF_NATIVE=ON (the default: -march=native) uses the build machine's extensions
// wherever the compiler or Eigen vectorizes, so on a CPU without one of them it would die of SIGILL at the
// first such instruction. Instead, every program that includes an icobrdf header checks once, while static
// objects are initialized (before main), and on a CPU that lacks an extension prints one line naming the
// missing extensions and the remedy, and exits with status 4 (the status of UnsupportedError in the
// icobrdf program). A portable build (ICOBRDF_NATIVE=OFF: baseline x86-64; five kernels, the projection tile,
// the spectrum tile, the block basis kernel, the microfacet kernel and lab's FP64 peak loop, are dispatched at run
// time to the best of Highway's targets from SSSE3 to AVX-512 that the CPU runs, icobrdf/core/support/simd_target.hpp)
// requires no extension and runs anywhere.
// Limit: a static initializer of the program that runs earlier and uses a missing extension still faults.
// On other architectures nothing is checked.
#include <string>
#include <vector>

namespace icobrdf {

// The extensions the library's translation units were compiled with, by the names of GCC's
// __builtin_cpu_supports ("avx2", "fma", "avx512f", ...); empty for a baseline build.
std::vector<std::string> build_isa_features();

// The one-line refusal for a CPU on which `supports(name)` is false for some of build_isa_features(), or ""
// when it has them all.
std::string build_isa_problem(bool (*supports)(const char* name));

// Whether this CPU has the extension (one of the names above; false for any other name).
bool cpu_supports(const char* name);

// Prints build_isa_problem(cpu_supports) to stderr and ends the process with status 4 when it is not empty;
// returns true otherwise. Run once per program through kBuildIsaChecked.
bool check_build_isa_at_startup();

namespace detail {
inline const bool kBuildIsaChecked = check_build_isa_at_startup();
}  // namespace detail

}  // namespace icobrdf
