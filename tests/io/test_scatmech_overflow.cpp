// SCATMECH import: finite coefficients whose sum (or wavelength scaling) leaves the double range are refused
// with an InputError naming the file and the mode, instead of producing an infinite spectrum (found by
// fuzz/fuzz_scatmech_coefficients.cpp).
#include <gtest/gtest.h>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/io/scatmech_coefficients.hpp"
#include "io_test_support.hpp"
#include "tests/support/unity_id.hpp"

namespace ICOBRDF_UNITY_ID {

using icobrdf::test::ScratchDir;

std::string import_error(const std::string& path, double lambda_um) {
  icobrdf::ScatmechImportOptions o;
  o.wavelength_um = lambda_um;
  try {
    icobrdf::scatmech_to_spectrum(icobrdf::read_scatmech_coefficients(path), o);
  } catch (const icobrdf::InputError& e) {
    return e.what();
  }
  return "";
}

TEST(ScatmechOverflow, SumsBeyondTheDoubleRangeAreInputErrors) {
  ScratchDir d;
  // 1e308 + 1e308 exceeds DBL_MAX (about 1.8e308).
  icobrdf::test::write_bytes(d / "sum.txt", "1,1,0,0,0,0,0,1e308\n1,1,0,0,0,0,0,1e308\n");
  const std::string m = import_error(d / "sum.txt", -1.0);
  EXPECT_EQ(m.rfind(d / "sum.txt", 0), 0u) << m;
  EXPECT_NE(m.find("mode (N, M, L) = (0, 0, 0) sum to inf"), std::string::npos) << m;
  // 1e300 x lambda^4 with lambda = 1e3 um is 1e312.
  icobrdf::test::write_bytes(d / "power.txt", "1,1,2,2,0,0,4,1e300\n");
  EXPECT_NE(import_error(d / "power.txt", 1e3).find("mode (N, M, L) = (2, 2, 0) sum to inf"), std::string::npos);
  // The same rows at lambda = 1 um are finite and imported.
  EXPECT_EQ(import_error(d / "power.txt", 1.0), "");
}

}  // namespace
