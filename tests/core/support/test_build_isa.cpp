// The CPU-extension check of icobrdf/core/support/build_isa.hpp. Expected values come from two independent sources:
// the compiler's predefined macros in this test (built with the library's flags) and the kernel's
// /proc/cpuinfo flags for the CPU that runs it.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>

#include "icobrdf/core/support/build_isa.hpp"
#include "tests/support/unity_id.hpp"

namespace icobrdf {
namespace ICOBRDF_UNITY_ID {

bool has(const std::vector<std::string>& v, const std::string& s) { return std::find(v.begin(), v.end(), s) != v.end(); }

TEST(BuildIsa, FeaturesAreTheCompilersPredefinedOnes) {
  const std::vector<std::string> f = build_isa_features();
#ifdef __AVX2__
  EXPECT_TRUE(has(f, "avx2"));
#else
  EXPECT_FALSE(has(f, "avx2"));
#endif
#ifdef __AVX512F__
  EXPECT_TRUE(has(f, "avx512f"));
#else
  EXPECT_FALSE(has(f, "avx512f"));
#endif
#ifdef __FMA__
  EXPECT_TRUE(has(f, "fma"));
#else
  EXPECT_FALSE(has(f, "fma"));
#endif
}

TEST(BuildIsa, ACpuWithEveryExtensionHasNoProblem) {
  EXPECT_EQ(build_isa_problem([](const char*) { return true; }), "");
}

TEST(BuildIsa, AMissingExtensionIsNamedOnOneLine) {
  const std::vector<std::string> f = build_isa_features();
  if (f.empty()) GTEST_SKIP() << "baseline x86-64 build (ICOBRDF_NATIVE=OFF): nothing can be missing";
  const std::string p = build_isa_problem([](const char*) { return false; });  // a CPU with none of them
  EXPECT_EQ(p.find('\n'), std::string::npos);
  for (const std::string& x : f) EXPECT_NE(p.find(x), std::string::npos) << x;
  EXPECT_NE(p.find("-DICOBRDF_NATIVE=OFF"), std::string::npos);
  const std::string last = f.back();
  static std::string denied;
  denied = last;
  const std::string one = build_isa_problem([](const char* n) { return denied != n; });
  EXPECT_NE(one.find("(" + last + ";"), std::string::npos) << one;  // only the denied one is listed
}

// /proc/cpuinfo's names for the extensions whose kernel name differs from GCC's.
std::string kernel_name(const std::string& gcc) {
  static const std::map<std::string, std::string> m = {{"sse3", "pni"}, {"sse4.1", "sse4_1"}, {"sse4.2", "sse4_2"}, {"bmi", "bmi1"}};
  const auto it = m.find(gcc);
  return it == m.end() ? gcc : it->second;
}

TEST(BuildIsa, CpuSupportsAgreesWithTheKernelsFlags) {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  std::set<std::string> flags;
  while (std::getline(in, line))
    if (line.rfind("flags", 0) == 0) {
      std::istringstream words(line.substr(line.find(':') + 1));
      for (std::string w; words >> w;) flags.insert(w);
      break;
    }
  if (flags.empty()) GTEST_SKIP() << "no /proc/cpuinfo flags line";
  for (const char* name : {"sse3", "ssse3", "sse4.1", "sse4.2", "popcnt", "avx", "avx2", "fma", "bmi", "bmi2", "avx512f",
                           "avx512vl", "avx512bw", "avx512dq"})
    EXPECT_EQ(cpu_supports(name), flags.count(kernel_name(name)) == 1) << name;
  EXPECT_FALSE(cpu_supports("no-such-extension"));
  // This test runs, so the start-up check passed: the CPU has every extension the library was built for.
  for (const std::string& f : build_isa_features()) EXPECT_TRUE(flags.count(kernel_name(f))) << f;
}

}  // namespace
}  // namespace icobrdf
