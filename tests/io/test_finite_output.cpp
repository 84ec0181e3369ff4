// Non-finite output is refused by every file writer before anything is written (issue #19, class 3):
// banks, spectrum and LUT files (write_bank for every dataset of a material, the basis arrays and the
// figures) and SCATMECH exports. Each case writes over an existing file, which must stay byte-identical,
// and must leave no temporary behind; the error is one line naming the file, the material and the dataset.
#include <gtest/gtest.h>

#include <dirent.h>

#include <cmath>
#include <functional>
#include <limits>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/support/finite_values.hpp"
#include "icobrdf/core/basis/isotropic_modes.hpp"
#include "icobrdf/io/bank_file.hpp"
#include "icobrdf/io/scatmech_coefficients.hpp"
#include "icobrdf/io/spectrum_file.hpp"
#include "io_test_support.hpp"
#include "tests/support/unity_id.hpp"

namespace ICOBRDF_UNITY_ID {

using namespace icobrdf;

constexpr double kInf = std::numeric_limits<double>::infinity();

int entries_in(const std::string& dir) {
  int n = 0;
  DIR* d = ::opendir(dir.c_str());
  while (const dirent* e = ::readdir(d)) n += std::string(e->d_name) != "." && std::string(e->d_name) != "..";
  ::closedir(d);
  return n;
}

MaterialRecord valid_record() {
  MaterialRecord m;
  m.name = "paint";
  m.spectrum = test::synthetic_spectrum(2, 1);
  m.ibsss = Eigen::MatrixXd::Constant(1, 1, 0.25);
  m.ibsss_indices = RowMatrix3i::Zero(1, 3);
  m.lut = {Eigen::MatrixXd::Constant(4, 4, 0.125)};
  return m;
}

// Writes `c` over an existing bank: the error names path, material and `dataset`, is one line, and
// leaves the old file and the folder as they were.
void expect_refused(const BankContents& c, const std::string& dataset) {
  test::ScratchDir dir;
  const std::string path = dir / "bank.h5";
  BankContents old;
  old.materials = {valid_record()};
  write_bank(path, old);
  const std::string before = test::read_bytes(path);
  try {
    write_bank(path, c);
    ADD_FAILURE() << dataset << ": written";
  } catch (const UnsupportedError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(path), std::string::npos) << msg;
    EXPECT_NE(msg.find(dataset), std::string::npos) << msg;
    EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
    EXPECT_NE(msg.find("nothing written"), std::string::npos) << msg;
  }
  EXPECT_EQ(test::read_bytes(path), before) << dataset;
  EXPECT_EQ(entries_in(dir.path()), 1) << dataset << ": a temporary was left";
}

TEST(FiniteOutput, EveryDatasetOfABankIsCheckedBeforeTheFileIsTouched) {
  {
    BankContents ok;
    ok.materials = {valid_record()};
    ok.materials[0].spectrum.reciprocity_violation = std::nan("");  // NaN figure = not measured: accepted
    test::ScratchDir dir;
    EXPECT_NO_THROW(write_bank(dir / "ok.h5", ok));
  }
  const std::vector<std::pair<std::string, std::function<void(MaterialRecord&)>>> cases = {
      {"material 'paint' dataset C channel 0", [](MaterialRecord& m) { m.spectrum.channels[0](1, 2) = kInf; }},
      {"material 'paint' dataset C channel 0", [](MaterialRecord& m) { m.spectrum.channels[0](0, 0) = std::nan(""); }},
      {"material 'paint' dataset ibsss", [](MaterialRecord& m) { m.ibsss(0, 0) = -kInf; }},
      {"material 'paint' dataset lut channel 0", [](MaterialRecord& m) { m.lut[0](3, 1) = kInf; }},
      {"material 'paint' attribute max_albedo", [](MaterialRecord& m) { m.spectrum.max_albedo = kInf; }},
      {"material 'paint' attribute gram_error", [](MaterialRecord& m) { m.spectrum.gram_error = -kInf; }},
  };
  for (const auto& [dataset, spoil] : cases) {
    BankContents c;
    c.materials = {valid_record(), valid_record()};
    c.materials[0].name = "first";  // a later material spoils the whole write, not only its own group
    spoil(c.materials[1]);
    expect_refused(c, dataset);
  }
  BankContents c;
  c.materials = {valid_record()};
  c.basis.push_back(BasisArray::matrix("4/B", Eigen::MatrixXd::Constant(2, 2, kInf), "1", "overflowed"));
  expect_refused(c, "basis array '4/B'");
}

TEST(FiniteOutput, RequireFiniteNamesTheStepAndTheIndex) {
  Eigen::MatrixXd m = Eigen::MatrixXd::Zero(3, 4);
  EXPECT_NO_THROW(require_finite(m, "x", "y"));
  m(2, 1) = -kInf;
  try {
    require_finite(m, "out.h5: material 'a'", "the projection");
    ADD_FAILURE();
  } catch (const UnsupportedError& e) {
    EXPECT_STREQ(e.what(), "out.h5: material 'a': the projection gave -Inf at [2, 1], expected finite values (the result leaves the "
                           "double range); nothing written");
  }
  EXPECT_THROW(require_finite(std::nan(""), "x", "y"), UnsupportedError);
  EXPECT_NO_THROW(require_finite(std::numeric_limits<double>::max(), "x", "y"));
}

// The case: a spectrum whose coefficients are all near 1e308 exported as SCATMECH coefficients wrote
// "inf" (the IBSSS conversion sums entries of C) and exited 0. The anisotropic fraction (Inf / Inf = NaN)
// passed the isotropy test unseen.
TEST(FiniteOutput, ScatmechExportOfOverflowingCoefficientsIsRefused) {
  test::ScratchDir dir;
  Spectrum s = test::synthetic_spectrum(2, 1);
  const Eigen::MatrixXd shape = s.channels[0];
  // Every entry at the largest double: a mode of two entries converts to about sqrt(2) of them, beyond it.
  s.channels[0] = Eigen::MatrixXd::Constant(6, 6, std::numeric_limits<double>::max());
  // The fraction is scale-free: finite for 1e308 entries, equal to that of the same matrix scaled down.
  EXPECT_TRUE(std::isfinite(anisotropic_energy_fraction(s.channels[0])));
  EXPECT_NEAR(anisotropic_energy_fraction(1e307 * shape), anisotropic_energy_fraction(shape), 1e-15);
  // Without --isotropic the (finite) anisotropic fraction refuses it as before: a constant C is not isotropic.
  EXPECT_THROW(write_scatmech_coefficients(dir / "a.csv", s, 0, false, "spec.h5#paint"), UnsupportedError);
  try {
    write_scatmech_coefficients(dir / "a.csv", s, 0, true, "spec.h5#paint");
    ADD_FAILURE() << "written";
  } catch (const UnsupportedError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(dir / "a.csv"), std::string::npos) << msg;
    EXPECT_NE(msg.find("material 'spec.h5#paint'"), std::string::npos) << msg;
    EXPECT_NE(msg.find("conversion of C to SCATMECH coefficients"), std::string::npos) << msg;
  }
  EXPECT_EQ(entries_in(dir.path()), 0);
  // Control: 1e300 converts within range, and icobrdf's own reader accepts what was written.
  s.channels[0] = Eigen::MatrixXd::Constant(6, 6, 1e300);
  const ScatmechExport e = write_scatmech_coefficients(dir / "b.csv", s, 0, true, "spec.h5#paint");
  EXPECT_TRUE(e.coefficients.allFinite());
  EXPECT_NO_THROW(read_scatmech_coefficients(dir / "b.csv"));
}

}  // namespace
