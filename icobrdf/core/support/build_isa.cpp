#include "icobrdf/core/support/build_isa.hpp"

#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace icobrdf {

namespace {

// The compiler's predefined macros name the extensions this translation unit (and, with one set of flags
// for the whole library, every other) was compiled with. Null-terminated for the start-up check, which
// must not use the library's containers (they may be compiled with the very extensions being checked).
const char* const kBuildFeatures[] = {
#ifdef __SSE3__
    "sse3",
#endif
#ifdef __SSSE3__
    "ssse3",
#endif
#ifdef __SSE4_1__
    "sse4.1",
#endif
#ifdef __SSE4_2__
    "sse4.2",
#endif
#ifdef __POPCNT__
    "popcnt",
#endif
#ifdef __AVX__
    "avx",
#endif
#ifdef __AVX2__
    "avx2",
#endif
#ifdef __FMA__
    "fma",
#endif
#ifdef __BMI__
    "bmi",
#endif
#ifdef __BMI2__
    "bmi2",
#endif
#ifdef __AVX512F__
    "avx512f",
#endif
#ifdef __AVX512VL__
    "avx512vl",
#endif
#ifdef __AVX512BW__
    "avx512bw",
#endif
#ifdef __AVX512DQ__
    "avx512dq",
#endif
    nullptr};

#if defined(__x86_64__) && defined(__GNUC__)
#define ICOBRDF_BASELINE_X86 __attribute__((target("arch=x86-64")))
#else
#define ICOBRDF_BASELINE_X86
#endif

// Appends the missing extensions to `out` (capacity `size`, always terminated); returns how many are missing.
ICOBRDF_BASELINE_X86 int missing_features(bool (*supports)(const char*), char* out, size_t size) {
  int missing = 0;
  size_t used = 0;
  out[0] = '\0';
  for (const char* const* f = kBuildFeatures; *f; ++f) {
    if (supports(*f)) continue;
    const size_t n = std::strlen(*f);
    if (used + n + 2 < size) {
      if (missing > 0) out[used++] = ' ';
      std::memcpy(out + used, *f, n);
      used += n;
      out[used] = '\0';
    }
    ++missing;
  }
  return missing;
}

constexpr const char* kRefusalStart = "icobrdf: this library was compiled for CPU extensions that this CPU lacks (";
constexpr const char* kRefusalEnd =
    "; it was built with -march=native, ICOBRDF_NATIVE=ON); rebuild icobrdf on this machine, or with "
    "-DICOBRDF_NATIVE=OFF for a portable library";

}  // namespace

std::vector<std::string> build_isa_features() {
  std::vector<std::string> v;
  for (const char* const* f = kBuildFeatures; *f; ++f) v.emplace_back(*f);
  return v;
}

std::string build_isa_problem(bool (*supports)(const char* name)) {
  char missing[256];
  if (missing_features(supports, missing, sizeof missing) == 0) return "";
  return std::string(kRefusalStart) + missing + kRefusalEnd;
}

ICOBRDF_BASELINE_X86 bool cpu_supports(const char* name) {
#if defined(__x86_64__) && defined(__GNUC__)
  __builtin_cpu_init();
  // __builtin_cpu_supports takes only string literals.
  if (!std::strcmp(name, "sse3")) return __builtin_cpu_supports("sse3");
  if (!std::strcmp(name, "ssse3")) return __builtin_cpu_supports("ssse3");
  if (!std::strcmp(name, "sse4.1")) return __builtin_cpu_supports("sse4.1");
  if (!std::strcmp(name, "sse4.2")) return __builtin_cpu_supports("sse4.2");
  if (!std::strcmp(name, "popcnt")) return __builtin_cpu_supports("popcnt");
  if (!std::strcmp(name, "avx")) return __builtin_cpu_supports("avx");
  if (!std::strcmp(name, "avx2")) return __builtin_cpu_supports("avx2");
  if (!std::strcmp(name, "fma")) return __builtin_cpu_supports("fma");
  if (!std::strcmp(name, "bmi")) return __builtin_cpu_supports("bmi");
  if (!std::strcmp(name, "bmi2")) return __builtin_cpu_supports("bmi2");
  if (!std::strcmp(name, "avx512f")) return __builtin_cpu_supports("avx512f");
  if (!std::strcmp(name, "avx512vl")) return __builtin_cpu_supports("avx512vl");
  if (!std::strcmp(name, "avx512bw")) return __builtin_cpu_supports("avx512bw");
  if (!std::strcmp(name, "avx512dq")) return __builtin_cpu_supports("avx512dq");
#else
  (void)name;
#endif
  return false;
}

ICOBRDF_BASELINE_X86 bool check_build_isa_at_startup() {
#if defined(__x86_64__)
  char missing[256];
  if (missing_features(cpu_supports, missing, sizeof missing) > 0) {
    std::fputs(kRefusalStart, stderr);
    std::fputs(missing, stderr);
    std::fputs(kRefusalEnd, stderr);
    std::fputc('\n', stderr);
    std::_Exit(4);
  }
#endif
  return true;
}

}  // namespace icobrdf
