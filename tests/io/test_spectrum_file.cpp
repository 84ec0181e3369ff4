// Materials <-> /materials/<name>, and whole banks: exact round trips of spectra with 1 and 3 channels,
// IBSSS tables, float32 LUTs with their rounding error, basis arrays, root attributes, name validation.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/io/bank_file.hpp"
#include "icobrdf/io/bank_format.hpp"
#include "icobrdf/io/spectrum_file.hpp"
#include "io_test_support.hpp"
#include "tests/support/unity_id.hpp"

namespace ICOBRDF_UNITY_ID {

using icobrdf::BankContents;
using icobrdf::MaterialRecord;
using icobrdf::Spectrum;

void expect_same_figure(double a, double b) {
  if (std::isnan(a))
    EXPECT_TRUE(std::isnan(b));
  else
    EXPECT_EQ(a, b);
}

void expect_identical(const Spectrum& a, const Spectrum& b) {
  EXPECT_EQ(a.order, b.order);
  EXPECT_EQ(a.isotropic, b.isotropic);
  EXPECT_EQ(a.cosine, b.cosine);
  EXPECT_EQ(a.source, b.source);
  EXPECT_EQ(a.filter, b.filter);
  EXPECT_EQ(a.level, b.level);
  EXPECT_EQ(a.grid_kind, b.grid_kind);
  expect_same_figure(a.gram_error, b.gram_error);
  expect_same_figure(a.reciprocity_violation, b.reciprocity_violation);
  expect_same_figure(a.anisotropy_fraction, b.anisotropy_fraction);
  expect_same_figure(a.max_albedo, b.max_albedo);
  EXPECT_EQ(a.channel_names, b.channel_names);
  ASSERT_EQ(a.channel_count(), b.channel_count());
  for (int c = 0; c < a.channel_count(); ++c) EXPECT_TRUE(a.channels[c] == b.channels[c]) << "channel " << c;
}

// The IBSSS index table up to order 2: n >= m >= l >= 0, n - l and m - l even (SPEC-NOTES: 5 entries).
icobrdf::RowMatrix3i ibsss_indices_order2() {
  icobrdf::RowMatrix3i t(5, 3);
  t << 0, 0, 0, 1, 1, 1, 2, 0, 0, 2, 2, 0, 2, 2, 2;
  return t;
}

TEST(SpectrumFile, OneChannelRoundTripsExactly) {
  icobrdf::test::ScratchDir dir;
  const Spectrum s = icobrdf::test::synthetic_spectrum(4, 1);
  icobrdf::write_spectrum_file(dir / "s.h5", s);
  expect_identical(s, icobrdf::read_spectrum_file(dir / "s.h5"));
  expect_identical(s, icobrdf::read_spectrum_file(dir / "s.h5", "spectrum"));
}

TEST(SpectrumFile, ThreeChannelCosineRoundTripsExactly) {
  icobrdf::test::ScratchDir dir;
  Spectrum s = icobrdf::test::synthetic_spectrum(2, 3);
  s.cosine = true;
  s.isotropic = true;
  s.filter = "hann";
  s.anisotropy_fraction = 0.0;
  const icobrdf::Grid g = icobrdf::test::synthetic_grid();
  icobrdf::write_spectrum_file(dir / "s.h5", s, &g, "red_paint");
  expect_identical(s, icobrdf::read_spectrum_file(dir / "s.h5", "red_paint"));
}

TEST(SpectrumFile, ChannelNamesRoundTripAndAreChecked) {
  icobrdf::test::ScratchDir dir;
  Spectrum s = icobrdf::test::synthetic_spectrum(2, 3);
  s.channel_names = {"450nm", "550nm", "650nm"};
  icobrdf::write_spectrum_file(dir / "s.h5", s);
  expect_identical(s, icobrdf::read_spectrum_file(dir / "s.h5"));
  s.channel_names = {"r", "g"};  // one name short
  EXPECT_THROW(icobrdf::write_spectrum_file(dir / "t.h5", s), icobrdf::ArgumentError);
  s.channel_names = {"r", "g,b", "x"};  // a comma would split the list
  EXPECT_THROW(icobrdf::write_spectrum_file(dir / "t.h5", s), icobrdf::ArgumentError);
}

// The record of a sample fit (format 1.1): every figure and the standard errors round-trip exactly, NaN
// included; a record that does not describe the spectrum (modes of another order) is not written, and the
// file stays 1.0.
TEST(SpectrumFile, SampleFitRecordRoundTripsAndBumpsTheMinorVersion) {
  icobrdf::test::ScratchDir dir;
  Spectrum s = icobrdf::test::synthetic_spectrum(2, 3);  // general modes of order 2: 21 unknowns
  const icobrdf::SampleFitRecord f = icobrdf::test::synthetic_sample_fit();
  s.sample_fit = f;
  icobrdf::write_spectrum_file(dir / "s.h5", s);
  EXPECT_EQ(icobrdf::read_bank(dir / "s.h5").format_version, "1.1");
  const Spectrum r = icobrdf::read_spectrum_file(dir / "s.h5");
  expect_identical(s, r);
  ASSERT_TRUE(r.sample_fit.has_value());
  const auto& g = *r.sample_fit;
  EXPECT_EQ(g.samples, 1234);
  EXPECT_EQ(g.unknowns, 21);
  EXPECT_EQ(g.effective_rank, 20);
  EXPECT_EQ(g.condition, 12.5);
  EXPECT_EQ(g.residual_rms, f.residual_rms);
  EXPECT_EQ(g.noise_sigma[0], 0.11);
  EXPECT_TRUE(std::isnan(g.noise_sigma[1]));
  EXPECT_EQ(g.cv_rms, 0.25);
  EXPECT_EQ(g.cv_folds, 5);
  EXPECT_EQ(g.tikhonov, 1e-3);
  EXPECT_EQ(g.order_choice, f.order_choice);
  EXPECT_EQ(g.tikhonov_choice, f.tikhonov_choice);
  EXPECT_EQ(g.fallback, f.fallback);
  EXPECT_EQ(g.solver, "QR");
  ASSERT_EQ(g.standard_error.rows(), 3);
  ASSERT_EQ(g.standard_error.cols(), 21);
  EXPECT_TRUE(std::isnan(g.standard_error(1, 7)));
  EXPECT_EQ(g.standard_error(2, 20), 0.01);

  s.sample_fit->unknowns = 6;  // the record of another fit
  icobrdf::write_spectrum_file(dir / "t.h5", s);
  EXPECT_EQ(icobrdf::read_bank(dir / "t.h5").format_version, "1.0");
  EXPECT_FALSE(icobrdf::read_spectrum_file(dir / "t.h5").sample_fit.has_value());
}

TEST(SpectrumFile, UnknownMaterialIsAnInputError) {
  icobrdf::test::ScratchDir dir;
  icobrdf::write_spectrum_file(dir / "s.h5", icobrdf::test::synthetic_spectrum(1, 1));
  try {
    icobrdf::read_spectrum_file(dir / "s.h5", "other");
    FAIL() << "no error";
  } catch (const icobrdf::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/materials/other"), std::string::npos) << e.what();
  }
}

TEST(SpectrumFile, BankWithGridIbsssLutAndBasisRoundTrips) {
  icobrdf::test::ScratchDir dir;
  BankContents b;
  b.grid = icobrdf::test::synthetic_grid();
  const int cells = b.grid->cells();

  MaterialRecord iso;  // isotropic, with its IBSSS vector and a float64 LUT
  iso.name = "matte";
  iso.spectrum = icobrdf::test::synthetic_spectrum(2, 3);
  iso.spectrum.isotropic = true;
  iso.ibsss_indices = ibsss_indices_order2();
  iso.ibsss.resize(3, 5);
  for (int c = 0; c < 3; ++c)
    for (int k = 0; k < 5; ++k) iso.ibsss(c, k) = 0.1 * c - 0.03 * k + 1.0 / 7.0;
  for (int c = 0; c < 3; ++c) {
    Eigen::MatrixXd f(cells, cells);
    for (int i = 0; i < cells; ++i)
      for (int r = 0; r < cells; ++r) f(i, r) = (c + 1) * 0.1 + i * 0.01 + r * 0.001 + 1e-17 * i * r;
    iso.lut.push_back(f);
  }

  MaterialRecord f32;  // float32 LUT whose rounding is known from the IEEE rules
  f32.name = "shiny-2";
  f32.spectrum = icobrdf::test::synthetic_spectrum(3, 1);
  Eigen::MatrixXd f(cells, cells);
  // Entries k + (k mod 3) 2^-30 with integer 1 <= k < 2^20: the offset is below half an ulp of k in
  // float32 (ulp >= 2^-23), so each rounds to k with error (k mod 3) 2^-30 <= 2^-29.
  for (int i = 0; i < cells; ++i)
    for (int r = 0; r < cells; ++r) {
      const int k = 1 + i * cells + r;
      f(i, r) = k + (k % 3) * std::ldexp(1.0, -30);
    }
  // One tie: 1 + 3 2^-24 lies halfway between 1 + 2^-23 (odd last bit) and 1 + 2^-22 (even), so round-half-
  // even gives 1 + 2^-22 with error 2^-24, the largest in the table.
  f(3, 5) = 1.0 + 3.0 * std::ldexp(1.0, -24);
  f32.lut = {f};
  f32.lut_float32 = true;

  b.materials = {iso, f32};
  Eigen::MatrixXd bm(4, 3);
  bm << 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12.5;
  b.basis.push_back(icobrdf::BasisArray::matrix("2/B", bm, "sr^-1/2", "cell averages of K_j"));
  icobrdf::BasisArray idx;
  idx.path = "2/indices";
  idx.shape = {3, 2};
  idx.indices = {0, 0, 1, -1, 1, 1};
  idx.unit = "index";
  b.basis.push_back(idx);

  icobrdf::write_bank(dir / "bank.h5", b);
  const BankContents r = icobrdf::read_bank(dir / "bank.h5");

  ASSERT_TRUE(r.grid.has_value());
  EXPECT_EQ(r.grid->cells(), cells);
  ASSERT_EQ(r.materials.size(), 2u);
  // Read back in name order: "matte" < "shiny-2".
  const MaterialRecord& a = r.materials[0];
  EXPECT_EQ(a.name, "matte");
  expect_identical(iso.spectrum, a.spectrum);
  EXPECT_TRUE(a.ibsss == iso.ibsss);
  EXPECT_TRUE(a.ibsss_indices == iso.ibsss_indices);
  ASSERT_EQ(a.lut.size(), 3u);
  for (int c = 0; c < 3; ++c) EXPECT_TRUE(a.lut[c] == iso.lut[c]);
  EXPECT_FALSE(a.lut_float32);
  EXPECT_EQ(a.lut_max_rounding_error, 0.0);

  const MaterialRecord& s = r.materials[1];
  EXPECT_EQ(s.name, "shiny-2");
  EXPECT_TRUE(s.lut_float32);
  EXPECT_EQ(s.lut_max_rounding_error, std::ldexp(1.0, -24));
  ASSERT_EQ(s.lut.size(), 1u);
  EXPECT_EQ(s.lut[0](3, 5), 1.0 + std::ldexp(1.0, -22));
  for (int i = 0; i < cells; ++i)
    for (int c = 0; c < cells; ++c)
      if (!(i == 3 && c == 5)) {
        EXPECT_EQ(s.lut[0](i, c), 1 + i * cells + c);
      }

  ASSERT_EQ(r.basis.size(), 2u);
  EXPECT_EQ(r.basis[0].path, "2/B");
  EXPECT_EQ(r.basis[0].shape, (icobrdf::h5::Shape{4, 3}));
  EXPECT_EQ(r.basis[0].values, (std::vector<double>{1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12.5}));
  EXPECT_EQ(r.basis[0].unit, "sr^-1/2");
  EXPECT_EQ(r.basis[0].description, "cell averages of K_j");
  EXPECT_EQ(r.basis[1].path, "2/indices");
  EXPECT_EQ(r.basis[1].indices, idx.indices);

  // Skipping LUTs still validates them but loads none.
  icobrdf::ReadOptions o;
  o.read_luts = false;
  const auto light = icobrdf::read_bank(dir / "bank.h5", o);
  EXPECT_TRUE(light.materials[0].lut.empty());
  EXPECT_TRUE(light.materials[1].lut_float32);
}

TEST(SpectrumFile, RootAttributesAndReproducibleBytes) {
  icobrdf::test::ScratchDir dir;
  ::setenv("SOURCE_DATE_EPOCH", "0", 1);
  BankContents b;
  b.grid = icobrdf::test::synthetic_grid();
  MaterialRecord m;
  m.name = "m";
  m.spectrum = icobrdf::test::synthetic_spectrum(2, 1);
  b.materials = {m};
  icobrdf::write_bank(dir / "a.h5", b);
  icobrdf::write_bank(dir / "b.h5", b);
  ::unsetenv("SOURCE_DATE_EPOCH");
  // No object timestamps are stored, so equal contents and creation time give equal bytes.
  EXPECT_EQ(icobrdf::test::read_bytes(dir / "a.h5"), icobrdf::test::read_bytes(dir / "b.h5"));

  const auto r = icobrdf::read_bank(dir / "a.h5");
  EXPECT_EQ(r.created, "1970-01-01T00:00:00Z");  // SOURCE_DATE_EPOCH = 0 is the epoch itself
  EXPECT_EQ(r.creator, std::string("icobrdf ") + ICOBRDF_VERSION);
  EXPECT_EQ(r.format_version, "1.0");
  const auto f = icobrdf::h5::ReadFile::open(dir / "a.h5");
  const auto root = f.root();
  EXPECT_EQ(root.attr_string("format"), "icobrdf-bank");
  EXPECT_EQ(root.attr_string("axis_order"), "row-major, logical shapes as documented");
  EXPECT_NE(root.attr_string("conventions").find("Nicodemus"), std::string::npos);
  EXPECT_TRUE(root.attr_bool("complete"));
  const auto mat = root.open_group("materials").open_group("m");
  EXPECT_EQ(mat.attr_string("function"), "f");
  EXPECT_EQ(mat.attributes_of("C").attr_string("unit"), "1");
  EXPECT_EQ(root.open_group("grid").attributes_of("solid_angles").attr_string("unit"), "sr");
}

TEST(SpectrumFile, CreatedIsCurrentUtcTime) {
  icobrdf::test::ScratchDir dir;
  const long long before = static_cast<long long>(std::time(nullptr));
  icobrdf::write_spectrum_file(dir / "s.h5", icobrdf::test::synthetic_spectrum(0, 1));
  const long long after = static_cast<long long>(std::time(nullptr));
  const std::string created = icobrdf::read_bank(dir / "s.h5").created;
  EXPECT_TRUE(created == icobrdf::iso8601_utc(before) || created == icobrdf::iso8601_utc(after)) << created;
  EXPECT_EQ(created.size(), 20u);
  EXPECT_EQ(created.back(), 'Z');
}

TEST(SpectrumFile, LargeDatasetsAreChunkedCompressedAndChecksummed) {
  icobrdf::test::ScratchDir dir;
  BankContents b;
  MaterialRecord m;
  m.name = "m";
  // C of order 12, 3 channels: 3 x 91 x 91 float64 = 198,744 bytes, above h5::kCompressMinBytes; of order
  // 8, 1 channel: 45 x 45 x 8 = 16,200 bytes, below it.
  static_assert(3 * 91 * 91 * 8 >= icobrdf::h5::kCompressMinBytes && 45 * 45 * 8 < icobrdf::h5::kCompressMinBytes);
  m.spectrum = icobrdf::test::synthetic_spectrum(12, 3);
  MaterialRecord small;
  small.name = "small";
  small.spectrum = icobrdf::test::synthetic_spectrum(8, 1);
  b.materials = {m, small};
  icobrdf::write_bank(dir / "b.h5", b);
  const hid_t f = H5Fopen((dir / "b.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  const auto filters_of = [f](const char* path) {
    const hid_t d = H5Dopen2(f, path, H5P_DEFAULT);
    const hid_t p = H5Dget_create_plist(d);
    EXPECT_EQ(H5Pget_layout(p), H5D_CHUNKED) << path;
    std::vector<H5Z_filter_t> filters;
    for (int i = 0; i < H5Pget_nfilters(p); ++i) {
      unsigned flags, cd[8], cfg;
      size_t n = 8;
      char name[32];
      filters.push_back(H5Pget_filter2(p, static_cast<unsigned>(i), &flags, &n, cd, sizeof name, name, &cfg));
    }
    H5Pclose(p);
    H5Dclose(d);
    return filters;
  };
  EXPECT_EQ(filters_of("/materials/m/C"), (std::vector<H5Z_filter_t>{H5Z_FILTER_SHUFFLE, H5Z_FILTER_DEFLATE, H5Z_FILTER_FLETCHER32}));
  EXPECT_EQ(filters_of("/materials/small/C"), (std::vector<H5Z_filter_t>{H5Z_FILTER_FLETCHER32}));
  H5Fclose(f);
  // Read back, both are what was written.
  const auto back = icobrdf::read_bank(dir / "b.h5");
  EXPECT_EQ(back.materials.at(0).spectrum.channels.at(2), m.spectrum.channels.at(2));
  EXPECT_EQ(back.materials.at(1).spectrum.channels.at(0), small.spectrum.channels.at(0));
}

TEST(SpectrumFile, InvalidNamesAreArgumentErrors) {
  icobrdf::test::ScratchDir dir;
  for (const std::string& bad : {std::string(""), std::string("a/b"), std::string("a.b"), std::string("tab\there"),
                                std::string("caf\xc3\xa9"), std::string(300, 'x')}) {
    EXPECT_THROW(icobrdf::write_spectrum_file(dir / "s.h5", icobrdf::test::synthetic_spectrum(1, 1), nullptr, bad),
                 icobrdf::ArgumentError)
        << bad;
  }
  EXPECT_TRUE(dir.entries().empty());  // nothing written, no temporary left
  EXPECT_NO_THROW(icobrdf::validate_material_name("Paint 01_(red)-x"));
}

TEST(SpectrumFile, InconsistentRecordsAreArgumentErrors) {
  icobrdf::test::ScratchDir dir;
  auto attempt = [&](const MaterialRecord& m) {
    BankContents b;
    b.materials = {m};
    icobrdf::write_bank(dir / "s.h5", b);
  };
  MaterialRecord m;
  m.name = "m";
  m.spectrum = icobrdf::test::synthetic_spectrum(2, 1);
  auto bad = m;
  bad.spectrum.order = 3;  // C is 6 x 6, order 3 needs 10 x 10
  EXPECT_THROW(attempt(bad), icobrdf::ArgumentError);
  bad = m;
  bad.spectrum.channels[0](1, 2) = std::nan("");
  EXPECT_THROW(attempt(bad), icobrdf::UnsupportedError);  // non-finite output (tests/io/test_finite_output.cpp)
  bad = m;
  bad.spectrum.channels.push_back(bad.spectrum.channels[0]);  // 2 channels
  EXPECT_THROW(attempt(bad), icobrdf::ArgumentError);
  bad = m;
  bad.ibsss_indices = ibsss_indices_order2();
  bad.ibsss_indices(1, 2) = 0;  // (1, 1, 0): n - l odd
  bad.ibsss = Eigen::MatrixXd::Zero(1, 5);
  EXPECT_THROW(attempt(bad), icobrdf::ArgumentError);
  bad = m;
  bad.lut = {Eigen::MatrixXd::Ones(8, 7)};  // not square
  EXPECT_THROW(attempt(bad), icobrdf::ArgumentError);
  bad = m;
  bad.spectrum.grid_kind = "equal-area";
  bad.spectrum.level = 1;
  bad.lut = {Eigen::MatrixXd::Ones(8, 8)};  // level 1 equal-area has 10 * 4 + 4 = 44 cells
  EXPECT_THROW(attempt(bad), icobrdf::ArgumentError);
  bad = m;
  bad.lut = {Eigen::MatrixXd::Constant(8, 8, 1e39)};  // beyond float32's 3.4e38
  bad.lut_float32 = true;
  EXPECT_THROW(attempt(bad), icobrdf::ArgumentError);
  BankContents twice;
  twice.materials = {m, m};
  EXPECT_THROW(icobrdf::write_bank(dir / "s.h5", twice), icobrdf::ArgumentError);
  EXPECT_TRUE(dir.entries().empty());
}

TEST(SpectrumFile, MaterialNamesAndSingleMaterialReads) {
  icobrdf::test::ScratchDir dir;
  BankContents b;
  for (const char* n : {"zinc", "Alu", "brass"}) {  // name order is byte order: "Alu" < "brass" < "zinc"
    MaterialRecord m;
    m.name = n;
    m.spectrum = icobrdf::test::synthetic_spectrum(1, 1);
    m.spectrum.source = std::string("model:") + n;
    b.materials.push_back(m);
  }
  icobrdf::write_bank(dir / "b.h5", b);
  EXPECT_EQ(icobrdf::bank_material_names(dir / "b.h5"), (std::vector<std::string>{"Alu", "brass", "zinc"}));
  EXPECT_EQ(icobrdf::read_bank_material(dir / "b.h5", "").name, "Alu");
  EXPECT_EQ(icobrdf::read_bank_material(dir / "b.h5", "zinc").spectrum.source, "model:zinc");
  EXPECT_EQ(icobrdf::read_spectrum_file(dir / "b.h5").source, "model:Alu");
  // An empty bank has no first material.
  icobrdf::write_bank(dir / "empty.h5", BankContents{});
  EXPECT_TRUE(icobrdf::bank_material_names(dir / "empty.h5").empty());
  EXPECT_THROW(icobrdf::read_spectrum_file(dir / "empty.h5"), icobrdf::InputError);
}

TEST(SpectrumFile, OverwritesAnyExistingFile) {
  icobrdf::test::ScratchDir dir;
  icobrdf::test::write_bytes(dir / "s.h5", "not a bank");
  icobrdf::write_spectrum_file(dir / "s.h5", icobrdf::test::synthetic_spectrum(1, 1));
  EXPECT_EQ(icobrdf::read_spectrum_file(dir / "s.h5").order, 1);
}

// Issue #19: a 40,000-term SOURCE failed deep in HDF5 ("object header message is too large"). The writer
// stores up to kMaxSourceLength bytes and refuses a longer source before creating the file.
TEST(SpectrumFile, SourceUpToTheLimitIsStoredAndLongerIsRefused) {
  icobrdf::test::ScratchDir dir;
  Spectrum s = icobrdf::test::synthetic_spectrum(2, 1);
  s.source = std::string(icobrdf::kMaxSourceLength, 's');
  icobrdf::write_spectrum_file(dir / "at.h5", s);
  EXPECT_EQ(icobrdf::read_spectrum_file(dir / "at.h5").source, s.source);
  s.source += "s";
  try {
    icobrdf::write_spectrum_file(dir / "over.h5", s);
    ADD_FAILURE() << "a source of kMaxSourceLength + 1 bytes was written";
  } catch (const icobrdf::ArgumentError& e) {
    EXPECT_NE(std::string(e.what()).find(std::to_string(icobrdf::kMaxSourceLength)), std::string::npos) << e.what();
  }
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"at.h5"});
}

}  // namespace ICOBRDF_UNITY_ID
