// A material record through its binary wire form (icobrdf/io/record_wire.hpp), which the MPI bank build sends
// between ranks: what is read is what was written, checked by the bank file itself (every stored field ends
// up in the bank image, so equal images mean nothing was lost), and malformed bytes are one-line errors.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/io/bank_file.hpp"
#include "icobrdf/io/record_wire.hpp"
#include "io_test_support.hpp"
#include "tests/support/unity_id.hpp"

namespace ICOBRDF_UNITY_ID {

// A record with every part a bank can store: three named channels, IBSSS coefficients, an anisotropic lobe
// (a hybrid), a float32 LUT, a sample-fit record with NaN entries, figures and labels, and a spectrum figure
// left NaN (anisotropy_fraction: not measured).
icobrdf::MaterialRecord full_record() {
  icobrdf::MaterialRecord m;
  m.name = "wire";
  m.spectrum = icobrdf::test::synthetic_spectrum(2, 3);
  m.spectrum.grid_kind = "test-cells";
  m.spectrum.channel_names = {"r", "g", "b"};
  m.spectrum.reciprocity_violation = 0.03125;
  icobrdf::SampleFitRecord f = icobrdf::test::synthetic_sample_fit();  // 21 modes: order 2
  f.tikhonov_power = 2.0;
  m.spectrum.sample_fit = f;
  m.ibsss = Eigen::MatrixXd(3, 2);
  m.ibsss << 1, 2, 3, 4, 5, 6.5;
  m.ibsss_indices.resize(2, 3);
  m.ibsss_indices << 0, 0, 0, 2, 2, 0;
  icobrdf::HalfAngleFactors lobe;
  lobe.quantity = icobrdf::HalfAngleQuantity::MeanCosine;
  lobe.corners = icobrdf::HorizonCorners::All;
  lobe.isotropic = false;
  lobe.centred = true;
  lobe.h_warp = 1.5;
  lobe.h_axis = 0.5, lobe.h_scale_1 = 2.0, lobe.h_scale_2 = 0.75;
  lobe.n_t = 4, lobe.n_phi_h = 4, lobe.n_theta_d = 4, lobe.n_phi_d = 2, lobe.rank = 2;
  for (int c = 0; c < 3; ++c) {
    lobe.u.emplace_back(icobrdf::RowMatrixXd::Constant(16, 2, 0.5 + c));
    lobe.v.emplace_back(icobrdf::RowMatrixXd::Constant(8, 2, 2.0 - 0.25 * c));
    lobe.u.back()(3, 1) = 1.0 / 3.0;
  }
  m.lobe = lobe;
  Eigen::MatrixXd lut(12, 12);
  for (int i = 0; i < 12; ++i)
    for (int r = 0; r < 12; ++r) lut(i, r) = 1.0 / (3.0 + i + 0.1 * r);
  m.lut = {lut, 2.0 * lut, 3.0 * lut};
  m.lut_float32 = true;
  m.figures = {{"seconds", 0.125}, {"error_l2", 1e-3}, {"total_coefficients", 36}};
  m.labels = {{"key", "0123abcd"}, {"error_measured", "yes"}};
  return m;
}

std::string image_of(const icobrdf::MaterialRecord& m) {
  icobrdf::BankContents b;
  b.materials = {m};
  b.created = "2026-11-26T00:00:00Z";
  return icobrdf::bank_image(b, "record");
}

TEST(RecordWire, WhatIsReadIsWhatWasWrittenAsTheBankStoresIt) {
  const icobrdf::MaterialRecord m = full_record();
  const icobrdf::MaterialRecord back = icobrdf::read_record_wire(icobrdf::record_wire(m), "record from rank 1");
  // Every stored field is in the image: equal images, equal records as far as any bank can tell.
  EXPECT_EQ(image_of(back), image_of(m));
  // And the parts a bank does not store as given travel too: the LUT in double precision (the image holds
  // it rounded to float32) and the writer's rounding figure.
  ASSERT_EQ(back.lut.size(), 3u);
  EXPECT_EQ(back.lut[2], m.lut[2]);
  EXPECT_TRUE(std::isnan(back.lut_max_rounding_error));
  ASSERT_TRUE(back.spectrum.sample_fit.has_value());
  EXPECT_TRUE(std::isnan(back.spectrum.sample_fit->noise_sigma[1]));
  EXPECT_EQ(back.spectrum.sample_fit->fallback, m.spectrum.sample_fit->fallback);
  ASSERT_TRUE(back.lobe.has_value());
  EXPECT_EQ(back.lobe->u[0], m.lobe->u[0]);
  EXPECT_EQ(back.lobe->corners, icobrdf::HorizonCorners::All);
}

TEST(RecordWire, ALobeOfSharedIntegerFactorsKeepsItsStorage) {
  icobrdf::MaterialRecord m = full_record();
  icobrdf::HalfAngleFactors& lobe = *m.lobe;
  lobe.u.resize(1), lobe.v.resize(1);
  lobe.channel_scales = icobrdf::RowMatrixXd::Constant(3, 2, 0.25);
  lobe.channel_scales(2, 1) = -1.5;
  lobe.precision = icobrdf::FactorPrecision::Int8;
  lobe.quantize();
  const icobrdf::MaterialRecord back = icobrdf::read_record_wire(icobrdf::record_wire(m), "record");
  EXPECT_EQ(image_of(back), image_of(m));
  ASSERT_TRUE(back.lobe.has_value());
  EXPECT_EQ(back.lobe->precision, icobrdf::FactorPrecision::Int8);
  EXPECT_EQ(back.lobe->channel_scales, lobe.channel_scales);
  EXPECT_EQ(back.lobe->bytes(), lobe.bytes());
}

TEST(RecordWire, APlainRecordWithoutOptionalPartsRoundTrips) {
  icobrdf::MaterialRecord m;
  m.name = "plain";
  m.spectrum = icobrdf::test::synthetic_spectrum(3, 1);
  const icobrdf::MaterialRecord back = icobrdf::read_record_wire(icobrdf::record_wire(m), "record");
  EXPECT_EQ(image_of(back), image_of(m));
  EXPECT_FALSE(back.lobe.has_value());
  EXPECT_FALSE(back.spectrum.sample_fit.has_value());
  EXPECT_TRUE(back.lut.empty());
}

// Every strict prefix of a record's bytes is refused with one line naming the record and a byte offset.
TEST(RecordWire, TruncatedForeignOrPaddedBytesAreOneLineInputErrors) {
  const std::string wire = icobrdf::record_wire(full_record());
  for (std::size_t n = 0; n < wire.size(); ++n) {
    try {
      icobrdf::read_record_wire(wire.substr(0, n), "record of material 'wire' from rank 1");
      FAIL() << "a record cut to " << n << " of " << wire.size() << " bytes was read";
    } catch (const icobrdf::InputError& e) {
      const std::string what = e.what();
      EXPECT_EQ(what.rfind("record of material 'wire' from rank 1: byte ", 0), 0u) << what;
      EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    }
  }
  EXPECT_THROW(icobrdf::read_record_wire(wire + "x", "record"), icobrdf::InputError);
  EXPECT_THROW(icobrdf::read_record_wire("\x89HDF\r\n\x1a\n", "record"), icobrdf::InputError);
  // A length field that claims more than the bytes left (the name's, right after tag and version).
  const std::size_t tag = std::string("icobrdf-record-wire").size();  // the layout's first field
  std::string bad = wire;
  const std::int64_t huge = std::int64_t{1} << 40;
  std::memcpy(bad.data() + tag + sizeof(std::uint32_t), &huge, 8);
  EXPECT_THROW(icobrdf::read_record_wire(bad, "record"), icobrdf::InputError);
  // Another version.
  bad = wire;
  bad[tag] = static_cast<char>(icobrdf::kRecordWireVersion + 1);
  try {
    icobrdf::read_record_wire(bad, "record");
    FAIL();
  } catch (const icobrdf::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("expected record version " + std::to_string(icobrdf::kRecordWireVersion)), std::string::npos) << e.what();
  }
}

}  // namespace
