// Rewriting a bank that was read back (a resumed build, `bank extract`): the float32 LUT's recorded rounding
// error must stay the one measured against the original float64 values, not the zero error of re-rounding
// values that are already float32.
#include <gtest/gtest.h>

#include <cmath>

#include "icobrdf/io/bank_file.hpp"
#include "io_test_support.hpp"
#include "tests/support/unity_id.hpp"

namespace ICOBRDF_UNITY_ID {

using icobrdf::test::ScratchDir;

TEST(BankRewrite, Float32LutKeepsItsRoundingErrorWhenWrittenAgain) {
  ScratchDir dir;
  icobrdf::BankContents b;
  icobrdf::MaterialRecord m;
  m.name = "m";
  m.spectrum = icobrdf::test::synthetic_spectrum(2, 1);
  m.spectrum.grid_kind = "test-cells";
  Eigen::MatrixXd lut(12, 12);
  for (int i = 0; i < 12; ++i)
    for (int r = 0; r < 12; ++r) lut(i, r) = 1.0 / (3.0 + i + 0.1 * r);  // not float32-representable
  m.lut = {lut};
  m.lut_float32 = true;
  b.materials = {m};
  // Expected: max |float32(x) - x| over the table, computed here independently of the writer.
  double expected = 0.0;
  for (int i = 0; i < 12; ++i)
    for (int r = 0; r < 12; ++r) expected = std::max(expected, std::abs(static_cast<double>(static_cast<float>(lut(i, r))) - lut(i, r)));
  ASSERT_GT(expected, 0.0);
  icobrdf::write_bank(dir / "a.h5", b);
  const auto first = icobrdf::read_bank(dir / "a.h5");
  EXPECT_EQ(first.materials.at(0).lut_max_rounding_error, expected);
  icobrdf::write_bank(dir / "b.h5", first);
  const auto second = icobrdf::read_bank(dir / "b.h5");
  EXPECT_EQ(second.materials.at(0).lut_max_rounding_error, expected);
  EXPECT_TRUE(second.materials.at(0).lut_float32);
  EXPECT_EQ(second.materials.at(0).lut.at(0), first.materials.at(0).lut.at(0));
}

}  // namespace
