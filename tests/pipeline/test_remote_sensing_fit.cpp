// End to end, as `icobrdf fit FILE.csv` runs with no options: 200 observations in the remote-sensing layout
// sza,vza,raa,brf of a Ross-Li surface with 1% noise (tests/data/remote-sensing/README.md) are read without
// conversion, fitted by the Koenderink-van Doorn modes (order and class by cross-validation) and by the kernels;
// the white-sky albedo of both is the truth's within 0.5%, and the fitted hot spot lies where the data put it
// (the kernel fit's exactly, the modes' within their angular resolution).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include "icobrdf/core/basis/direction.hpp"
#include "icobrdf/core/grid/gauss_legendre.hpp"
#include "icobrdf/core/models/kernel_models.hpp"
#include "icobrdf/core/spectrum/spectrum_ops.hpp"
#include "icobrdf/io/brdf_source.hpp"
#include "icobrdf/io/measured_sources.hpp"
#include "icobrdf/pipeline/fit_source.hpp"
#include "tests/support/unity_id.hpp"

namespace icobrdf {
namespace ICOBRDF_UNITY_ID {

const std::string kFixture = std::string(ICOBRDF_SOURCE_DIR) + "/tests/data/remote-sensing/ross-li-200.csv";
// The truth's white-sky albedo: iso + vol H_vol + geo H_geo with the MODIS ATBD's integrals (Table 1).
constexpr double kTruthWhiteSky = 0.25 + 0.12 * 0.189184 + 0.04 * -1.377622;
// The acceptance bound of the task: 0.5% of the truth.
constexpr double kWhiteSkyRelTol = 0.005;
// Quadrature of the fitted modes' white-sky albedo: Gauss-Legendre in cos(theta) for each direction and midpoints
// in the azimuths. The modes of order N are (1 - mu)^(|l|/2) times polynomials of degree <= N/2 in mu, times
// cos(l phi): after the azimuth sums (exact for |l| < 32 with 32 midpoints) only l = 0 remains, a polynomial
// that 16 nodes integrate exactly up to order 60.
constexpr int kMuNodes = 16, kPhiNodes = 32;
// Hot spot. The truth's principal-plane maximum on the sun's side is the Li-Sparse-R kink at vza = sza (0.2947 at
// sza = vza = 40 deg, 0.2944 at vza = 45: a plateau). The kernel fit, the one the held-out samples support, has
// the truth's form: its maximum over vza 0..70 deg (the data's range, step 0.25 deg) must be at vza = sza to the
// step. The modes round the kink off over their angular resolution, 90 deg / N at order N: their maximum must lie
// on the sun's side (above the forward side's), within 90/N of vza = sza.
constexpr double kScanStepDeg = 0.25;
constexpr double kModesResolutionDeg = 90.0;

Eigen::Vector3d dir(double theta_deg, double phi_deg) { return direction_from_angles(theta_deg * M_PI / 180, phi_deg * M_PI / 180); }

// (1/pi) integral integral f mu_i mu_r dOmega_i dOmega_r of the spectrum's channel 0.
double white_sky_of(const Spectrum& s) {
  const QuadratureRule mu = gauss_legendre(kMuNodes, 0.0, 1.0);
  const int per = kMuNodes * kPhiNodes;
  RowMatrix3d d(per, 3);
  Eigen::VectorXd w(per);
  for (int a = 0; a < kMuNodes; ++a)
    for (int b = 0; b < kPhiNodes; ++b) {
      const double phi = (b + 0.5) * 2 * M_PI / kPhiNodes;
      d.row(a * kPhiNodes + b) = direction_from_angles(std::acos(mu.nodes(a)), phi).transpose();
      w(a * kPhiNodes + b) = mu.weights(a) * mu.nodes(a) * 2 * M_PI / kPhiNodes;  // mu dOmega = mu dmu dphi
    }
  RowMatrix3d wi(per * per, 3), wr(per * per, 3);
  Eigen::VectorXd ww(per * per);
  for (int i = 0; i < per; ++i)
    for (int r = 0; r < per; ++r) {
      wi.row(i * per + r) = d.row(i);
      wr.row(i * per + r) = d.row(r);
      ww(i * per + r) = w(i) * w(r);
    }
  return evaluate_coefficients(s.channels[0], s.order, wi, wr).dot(ww) / M_PI;
}

class RemoteSensingFit : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    source_ = open_source(kFixture).release();
    FitRequest r;
    r.level = 1;  // the grid serves only the albedo figure of sample fits
    r.order = kChooseOrder;
    fit_ = new FitResult(fit_source(*source_, r));
  }
  static void TearDownTestSuite() {
    delete fit_;
    delete source_;
  }
  static BrdfSource* source_;
  static FitResult* fit_;
};
BrdfSource* RemoteSensingFit::source_ = nullptr;
FitResult* RemoteSensingFit::fit_ = nullptr;

TEST_F(RemoteSensingFit, ReadsTheFileAsItIs) {
  const BrdfSamples* s = samples_of(*source_);
  ASSERT_NE(s, nullptr);
  EXPECT_EQ(s->wi.rows(), 200);
  EXPECT_EQ(s->layout, AngleLayout::SunViewRelative);
  EXPECT_EQ(s->quantity, ValueQuantity::Brf);
  ASSERT_EQ(source_->notes().size(), 1u);
  EXPECT_NE(source_->notes()[0].find("values BRF (f = BRF/pi"), std::string::npos) << source_->notes()[0];
}

TEST_F(RemoteSensingFit, WhiteSkyAlbedoOfBothFitsIsTheTruths) {
  const double modes = white_sky_of(fit_->spectrum);
  EXPECT_NEAR(modes / kTruthWhiteSky, 1.0, kWhiteSkyRelTol) << "modes " << modes << ", order " << fit_->spectrum.order;
  const KernelFit* k = last_kernel_fit(*source_);
  ASSERT_NE(k, nullptr);
  ASSERT_EQ(k->quantities[0].name, "white-sky albedo");
  EXPECT_NEAR(k->quantities[0].value(0) / kTruthWhiteSky, 1.0, kWhiteSkyRelTol);
  // The data are the kernels' own: the held-out samples cannot prefer the modes.
  const CheckedSampleFit* c = last_checked_sample_fit(*source_);
  ASSERT_NE(c, nullptr);
  EXPECT_EQ(supported_fit(k->cv_rms, c->cv_rms), "kernels") << "kernels " << k->cv_rms << ", modes " << c->cv_rms;
  std::cout << "order " << fit_->spectrum.order << (fit_->spectrum.isotropic ? " isotropic" : " general") << ", white-sky modes "
            << modes << ", kernels " << k->quantities[0].value(0) << ", truth " << kTruthWhiteSky << "; CV RMS kernels " << k->cv_rms
            << ", modes " << c->cv_rms << " 1/sr\n";
}

TEST_F(RemoteSensingFit, HotSpotLiesWhereTheDataPutIt) {
  const KernelFit* k = last_kernel_fit(*source_);
  ASSERT_NE(k, nullptr);
  const RossLiModel kernels(k->weights(0, 0), k->weights(1, 0), k->weights(2, 0));
  const int n = static_cast<int>(70.0 / kScanStepDeg) + 1;
  const double resolution = kModesResolutionDeg / std::max(fit_->spectrum.order, 1);
  // At sza = 50 deg and above Ross-Thick's rise towards grazing outgrows the hot spot within vza 70 deg (the truth's
  // sun-side maximum is then at the end of the range): the hot spot is the maximum at 30 and 40 deg.
  for (double sza : {30.0, 40.0}) {
    RowMatrix3d wi(n, 3), sun_side(n, 3), forward(n, 3);
    for (int j = 0; j < n; ++j) {
      wi.row(j) = dir(sza, 0).transpose();
      sun_side.row(j) = dir(kScanStepDeg * j, 0).transpose();    // raa = 0
      forward.row(j) = dir(kScanStepDeg * j, 180).transpose();   // raa = 180
    }
    Eigen::Index at_kernels = 0, at_modes = 0;
    Eigen::MatrixXd kernel_values(n, 1);
    kernels.eval(wi, sun_side, kernel_values);
    kernel_values.col(0).maxCoeff(&at_kernels);
    const Eigen::VectorXd modes = evaluate_coefficients(fit_->spectrum.channels[0], fit_->spectrum.order, wi, sun_side);
    const double peak = modes.maxCoeff(&at_modes);
    const double forward_peak = evaluate_coefficients(fit_->spectrum.channels[0], fit_->spectrum.order, wi, forward).maxCoeff();
    std::cout << "sza " << sza << ": principal-plane maximum of the kernel fit at vza " << kScanStepDeg * static_cast<double>(at_kernels)
              << " deg, of the modes (order " << fit_->spectrum.order << ") at " << kScanStepDeg * static_cast<double>(at_modes) << " deg\n";
    EXPECT_NEAR(kScanStepDeg * static_cast<double>(at_kernels), sza, kScanStepDeg) << "sza " << sza;
    EXPECT_NEAR(kScanStepDeg * static_cast<double>(at_modes), sza, resolution) << "sza " << sza;
    EXPECT_GT(peak, forward_peak) << "sza " << sza;
  }
}

// Sparse multi-angle data never end in a refusal: the first 1, 2, 5 and 12 observations of the fixture fit with
// no options, to a spectrum bounded by the samples (the scale check's factor), with a kernel fit beside it.
TEST(RemoteSensingSparse, FewObservationsFitWithoutRefusal) {
  std::ifstream in(kFixture);
  std::string line, header;
  std::vector<std::string> rows;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    if (header.empty()) header = line;
    else rows.push_back(line);
  }
  for (size_t n : {1u, 2u, 5u, 12u}) {
    const std::string path = ::testing::TempDir() + "/sparse-" + std::to_string(n) + ".csv";
    {
      std::ofstream out(path);
      out << header << "\n";
      for (size_t k = 0; k < n; ++k) out << rows[k] << "\n";
    }
    const auto src = open_source(path);
    FitRequest r;
    r.level = 1;
    r.order = kChooseOrder;
    FitResult fit = fit_source(*src, r);
    const CheckedSampleFit* c = last_checked_sample_fit(*src);
    ASSERT_NE(c, nullptr) << n;
    EXPECT_LE(c->max_abs_fit, kScaleGuardFactor * c->max_abs_sample) << n;
    const KernelFit* k = last_kernel_fit(*src);
    ASSERT_NE(k, nullptr) << n;
    EXPECT_EQ(k->determined, n >= 5) << n;  // 5 and 12 distinct geometries determine three weights
    std::cout << n << " observations: order " << fit.spectrum.order << (fit.spectrum.isotropic ? " isotropic" : " general")
              << ", kernels determined " << k->determined << "\n";
    std::remove(path.c_str());
  }
}

}  // namespace ICOBRDF_UNITY_ID
}  // namespace icobrdf
