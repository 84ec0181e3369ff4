// CSV samples: duplicate rows whose values are finite but whose sum leaves the double range still average to
// the finite mean (found by fuzz/fuzz_sample_csv.cpp: the mean used to come out infinite).
#include <gtest/gtest.h>

#include <cfloat>

#include "icobrdf/io/sample_csv.hpp"
#include "io_test_support.hpp"
#include "tests/support/unity_id.hpp"

namespace ICOBRDF_UNITY_ID {

TEST(SampleCsvOverflow, DuplicatesNearTheDoubleRangeAverageToTheirFiniteMean) {
  icobrdf::test::ScratchDir d;
  // Mean of 1e308 and 1e308 is 1e308 (the sum, 2e308, exceeds DBL_MAX); mean of 1.5e308 and -0.5e308 is 0.5e308,
  // computed as 1.5e308/2 + (-0.5e308)/2 (exact halvings); the third sample has no duplicate.
  icobrdf::test::write_bytes(d / "big.csv",
                             "theta_i,phi_i,theta_r,phi_r,value\n10,20,30,40,1e308\n10,-340,30,40,1e308\n"
                             "20,0,0,0,1.5e308\n20,0,0,0,-0.5e308\n0,0,0,0,0.25\n");
  const icobrdf::BrdfSamples s = icobrdf::read_sample_csv(d / "big.csv");
  ASSERT_EQ(s.values.rows(), 3);
  EXPECT_EQ(s.values(0, 0), 1e308);
  EXPECT_EQ(s.values(1, 0), 1.5e308 / 2 + (-0.5e308) / 2);
  EXPECT_EQ(s.values(2, 0), 0.25);
  EXPECT_EQ(s.duplicates_merged, 2);
}

}  // namespace
