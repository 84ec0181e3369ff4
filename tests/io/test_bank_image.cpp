// Banks made and read in memory (bank_image / read_bank_image, what the MPI bank build sends between ranks):
// the image is the bank file itself, and what it carries is what a file on disk carries.
#include <gtest/gtest.h>

#include <cmath>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/io/bank_file.hpp"
#include "io_test_support.hpp"
#include "tests/support/unity_id.hpp"

namespace ICOBRDF_UNITY_ID {

using icobrdf::test::ScratchDir;

// A bank with everything a material record can hold short of a lobe: three channels, a float32 LUT, figures
// and labels, a fixed creation time.
icobrdf::BankContents sample_bank() {
  icobrdf::BankContents b;
  icobrdf::MaterialRecord m;
  m.name = "m";
  m.spectrum = icobrdf::test::synthetic_spectrum(2, 3);
  m.spectrum.grid_kind = "test-cells";
  Eigen::MatrixXd lut(12, 12);
  for (int i = 0; i < 12; ++i)
    for (int r = 0; r < 12; ++r) lut(i, r) = 1.0 / (3.0 + i + 0.1 * r);
  m.lut = {lut, 2.0 * lut, 3.0 * lut};
  m.lut_float32 = true;
  m.figures = {{"seconds", 0.125}, {"error_l2", 1e-3}};
  m.labels = {{"key", "0123abcd"}};
  b.materials = {m};
  b.created = "2026-11-25T00:00:00Z";
  return b;
}

TEST(BankImage, RoundTripsLikeAFileAndIsTheFileItself) {
  ScratchDir dir;
  const icobrdf::BankContents b = sample_bank();
  const std::string image = icobrdf::bank_image(b, "record");
  // The image read from memory and the same bytes read as a file give the same contents: written again
  // (to disk, the ordinary writer), the two files are byte-identical.
  icobrdf::test::write_bytes(dir / "image.h5", image);
  const auto from_memory = icobrdf::read_bank_image(image, "record");
  const auto from_file = icobrdf::read_bank(dir / "image.h5");
  icobrdf::write_bank(dir / "a.h5", from_memory);
  icobrdf::write_bank(dir / "b.h5", from_file);
  EXPECT_EQ(icobrdf::test::read_bytes(dir / "a.h5"), icobrdf::test::read_bytes(dir / "b.h5"));
  // And the values are the ones written.
  const auto& m = from_memory.materials.at(0);
  EXPECT_EQ(m.name, "m");
  EXPECT_EQ(m.figures.at("seconds"), 0.125);
  EXPECT_EQ(m.labels.at("key"), "0123abcd");
  EXPECT_TRUE(m.lut_float32);
  ASSERT_EQ(m.lut.size(), 3u);
  EXPECT_EQ(m.lut[1](3, 4), static_cast<double>(static_cast<float>(2.0 / (3.0 + 3 + 0.4))));
  EXPECT_EQ(m.spectrum.channels.at(1), b.materials[0].spectrum.channels.at(1));
}

TEST(BankImage, TruncatedOrForeignBytesAreAnInputErrorNamingTheImage) {
  const std::string image = icobrdf::bank_image(sample_bank(), "record");
  EXPECT_THROW(icobrdf::read_bank_image("not an HDF5 file", "record from rank 1"), icobrdf::InputError);
  try {
    icobrdf::read_bank_image(image.substr(0, image.size() / 2), "record from rank 1");
    FAIL() << "a truncated image was read";
  } catch (const icobrdf::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("record from rank 1"), std::string::npos) << e.what();
  }
}

}  // namespace
