// A half-angle lobe through a bank file (icobrdf/io/half_angle_file.hpp) in every storage: factors per channel
// or shared with channel scales, float64 / float32 / int16 / int8. What is read is what was written and what
// the in-memory (quantized) lobe evaluates; a float64 lobe with a factor set per channel is written as format
// 3.0 wrote it (readers of 3.0 read it), a compact one as 4.0; out-of-range integers are refused. A compact lobe
// is dequantized once, when it is quantized or read: its LUT is that of float64 factors holding the same values.
#include <gtest/gtest.h>

#include <hdf5.h>

#include <random>

#include "icobrdf/core/fit/half_angle_fit.hpp"
#include "icobrdf/core/models/function_model.hpp"
#include "icobrdf/core/projection/lut.hpp"
#include "icobrdf/core/support/error.hpp"
#include "icobrdf/io/bank_file.hpp"
#include "icobrdf/io/h5_file.hpp"
#include "icobrdf/io/half_angle_file.hpp"
#include "icobrdf/mesh/tessellation.hpp"
#include "io_test_support.hpp"
#include "tests/support/unity_id.hpp"

namespace ICOBRDF_UNITY_ID {

using icobrdf::FactorPrecision;
using icobrdf::HalfAngleFactors;
using icobrdf::RowMatrixXd;

constexpr FactorPrecision kPrecisions[] = {FactorPrecision::Float64, FactorPrecision::Float32, FactorPrecision::Int16,
                                           FactorPrecision::Int8};

// A 3-channel isotropic lobe of random factors (signed: integers must keep the sign), 6 x 1 h and 4 x 4 d
// nodes, rank 2, in the given storage and rounded to it.
HalfAngleFactors random_lobe(bool shared, FactorPrecision p) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> val(-1.0, 2.0);
  HalfAngleFactors f;
  f.quantity = icobrdf::HalfAngleQuantity::MeanCosine;
  f.n_t = 6, f.n_theta_d = 4, f.n_phi_d = 4, f.rank = 2;
  const int sets = shared ? 1 : 3;
  for (int c = 0; c < sets; ++c) {
    f.u.emplace_back(RowMatrixXd::NullaryExpr(6, 2, [&] { return val(rng); }));
    f.v.emplace_back(RowMatrixXd::NullaryExpr(16, 2, [&] { return val(rng); }));
  }
  if (shared) f.channel_scales = RowMatrixXd::NullaryExpr(3, 2, [&] { return val(rng); });
  f.precision = p;
  f.quantize();
  return f;
}

std::string write_lobe_bank(const icobrdf::test::ScratchDir& dir, const HalfAngleFactors& lobe) {
  icobrdf::MaterialRecord m;
  m.name = "lobe";
  m.spectrum = icobrdf::test::synthetic_spectrum(0, 3);
  for (auto& c : m.spectrum.channels) c.setZero();
  m.lobe = lobe;
  icobrdf::BankContents b;
  b.materials = {m};
  const std::string path = dir / "lobe.h5";
  icobrdf::write_bank(path, b);
  return path;
}

TEST(HalfAngleFile, EveryStorageReadsBackAsStoredAndEvaluatesTheSame) {
  icobrdf::RowMatrix3d wi, wr;
  icobrdf::uniform_pairs(2000, 5, wi, wr);
  for (const bool shared : {false, true})
    for (const FactorPrecision p : kPrecisions) {
      const std::string what = std::string(shared ? "shared " : "") + icobrdf::factor_precision_name(p);
      const icobrdf::test::ScratchDir dir;
      const HalfAngleFactors lobe = random_lobe(shared, p);
      const std::string path = write_lobe_bank(dir, lobe);
      const icobrdf::BankContents back = icobrdf::read_bank(path);
      ASSERT_TRUE(back.materials.at(0).lobe.has_value()) << what;
      const HalfAngleFactors& got = *back.materials[0].lobe;
      EXPECT_EQ(got.precision, p) << what;
      EXPECT_EQ(got.shared(), shared) << what;
      ASSERT_EQ(got.u.size(), lobe.u.size()) << what;
      for (size_t s = 0; s < lobe.u.size(); ++s) {
        EXPECT_EQ(got.u[s], lobe.u[s]) << what;  // bitwise: the quantized values are what the file holds
        EXPECT_EQ(got.v[s], lobe.v[s]) << what;
      }
      EXPECT_EQ(got.channel_scales, lobe.channel_scales) << what;
      EXPECT_EQ(got.bytes(), lobe.bytes()) << what;
      EXPECT_EQ(got.eval(wi, wr), lobe.eval(wi, wr)) << what;
      // The dataset's element type is the precision's; the version 4.0 exactly when the storage is new.
      const icobrdf::h5::ReadFile file = icobrdf::h5::ReadFile::open(path);
      const icobrdf::h5::Group g = file.root().open_group("materials").open_group("lobe").open_group("half_angle");
      const icobrdf::h5::Type want = p == FactorPrecision::Float64   ? icobrdf::h5::Type::float64
                                     : p == FactorPrecision::Float32 ? icobrdf::h5::Type::float32
                                     : p == FactorPrecision::Int16   ? icobrdf::h5::Type::int16
                                                                     : icobrdf::h5::Type::int8;
      EXPECT_EQ(g.dataset_type("u", {}), want) << what;
      const bool compact = shared || p != FactorPrecision::Float64;
      EXPECT_EQ(file.root().attr_string("format_version"), compact ? "4.0" : "3.0") << what;
      // A 3.0 lobe: none of the 4.0 attributes.
      EXPECT_EQ(g.has_attr("precision"), p != FactorPrecision::Float64) << what;
      EXPECT_EQ(g.has_attr("factor_sets"), shared) << what;
    }
}

// The LUT (cell averages on the level-0 grid with the degree-2 rule, every channel) of a lobe as it stands.
std::vector<Eigen::MatrixXd> lobe_lut(const HalfAngleFactors& lobe, const icobrdf::Grid& g) {
  const icobrdf::FunctionModel m(
      lobe.channels(), [&lobe](const icobrdf::RowMatrix3d& wi, const icobrdf::RowMatrix3d& wr, Eigen::Ref<Eigen::MatrixXd> out) { lobe.eval(wi, wr, out); },
      "lobe", true, true);
  return icobrdf::build_lut(m, g, false).channels;
}

// Evaluation reads the factor values as doubles whatever the storage: the integers of a file are multiplied
// by their column scales once, when read (as quantize() leaves them in memory), never per evaluation. So the
// LUT of a compact lobe, in memory or read back, is bit for bit the LUT of the float64 lobe whose factors are
// those dequantized values (the same arithmetic on the same doubles), and costs the same evaluations.
TEST(HalfAngleFile, ACompactLobeSamplesTheLutOfItsDequantizedFloat64Factors) {
  const icobrdf::Grid g = icobrdf::build_equal_area_grid(0, 2);  // the cheap rule: the arithmetic is compared
  for (const bool shared : {false, true})
    for (const FactorPrecision p : {FactorPrecision::Int16, FactorPrecision::Int8}) {  // integers: scale x k
      const std::string what = std::string(shared ? "shared " : "") + icobrdf::factor_precision_name(p);
      const icobrdf::test::ScratchDir dir;
      const HalfAngleFactors lobe = random_lobe(shared, p);
      const HalfAngleFactors read = *icobrdf::read_bank(write_lobe_bank(dir, lobe)).materials.at(0).lobe;
      HalfAngleFactors plain = read;  // the dequantized values, stored as float64
      plain.precision = FactorPrecision::Float64;
      const auto want = lobe_lut(plain, g);
      EXPECT_GT(want[0].cwiseAbs().maxCoeff(), 0.0) << what;  // a LUT with values to compare
      // (The lobe in memory holds the values read, bit for bit: EveryStorageReadsBackAsStoredAndEvaluatesTheSame.)
      const auto from_file = lobe_lut(read, g);
      ASSERT_EQ(from_file.size(), want.size()) << what;
      for (size_t c = 0; c < want.size(); ++c) EXPECT_EQ(from_file[c], want[c]) << what << " channel " << c;
    }
}

TEST(HalfAngleFile, IntegersBeyondTheirLevelsAreRefused) {
  const icobrdf::test::ScratchDir dir;
  const std::string path = write_lobe_bank(dir, random_lobe(false, FactorPrecision::Int8));
  // -128 is an int8 but outside [-127, 127], the levels the scales were taken for.
  const hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  const hid_t d = H5Dopen2(f, "/materials/lobe/half_angle/v", H5P_DEFAULT);
  std::vector<std::int8_t> k(3 * 16 * 2);
  ASSERT_GE(H5Dread(d, H5T_NATIVE_INT8, H5S_ALL, H5S_ALL, H5P_DEFAULT, k.data()), 0);
  k[5] = -128;
  ASSERT_GE(H5Dwrite(d, H5T_NATIVE_INT8, H5S_ALL, H5S_ALL, H5P_DEFAULT, k.data()), 0);
  H5Dclose(d);
  H5Fclose(f);
  try {
    icobrdf::read_bank(path);
    FAIL() << "an int8 factor of -128 was read";
  } catch (const icobrdf::InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("half_angle/v"), std::string::npos) << what;
    EXPECT_NE(what.find("|k| <= 127"), std::string::npos) << what;
  }
}

}  // namespace ICOBRDF_UNITY_ID
