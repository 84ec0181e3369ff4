// The noise figure of a MERL table (the MERL SOURCE's noise_sigma_at, icobrdf/io/measured_sources.cpp): a table of
// a constant plus Gaussian noise of a known sigma at every node (a hash of the bin and channel, Box-Muller), so each
// theta_h bin's estimate is judged against that sigma within the estimator's standard error
// (icobrdf/core/tables/grid_noise.hpp), nodes below the horizon (stored 0 by write_merl) left out.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>

#include "icobrdf/core/models/function_model.hpp"
#include "icobrdf/core/support/scramble.hpp"
#include "icobrdf/io/brdf_source.hpp"
#include "icobrdf/io/merl.hpp"
#include "io_test_support.hpp"
#include "tests/support/unity_id.hpp"

namespace icobrdf {
namespace ICOBRDF_UNITY_ID {

constexpr double kLevel = 0.3, kSigma = 0.003;
// 4 standard errors of 1.67 / sqrt(N), N at least half a bin's 90 x 178 + 180 x 88 differences (the rest may be
// below the horizon at the bins judged).
const double kTol = 4 * 1.67 / std::sqrt((90.0 * 178 + 180.0 * 88) / 2);

// A standard normal draw for (bin, channel): Box-Muller of two splitmix64 uniforms.
double normal_of(std::int64_t flat, int channel) {
  const std::uint64_t key = static_cast<std::uint64_t>(flat) * 4 + static_cast<std::uint64_t>(channel);
  const double u1 = (static_cast<double>(splitmix64(2 * key) >> 11) + 0.5) / 9007199254740992.0;
  const double u2 = static_cast<double>(splitmix64(2 * key + 1) >> 11) / 9007199254740992.0;
  return std::sqrt(-2 * std::log(u1)) * std::cos(2 * M_PI * u2);
}

TEST(MerlNoise, EachThetaHalfBinEstimatesTheNoiseDrawnIntoIt) {
  test::ScratchDir d;
  const FunctionModel noisy(
      3,
      [](const RowMatrix3d& wi, const RowMatrix3d& wr, Eigen::Ref<Eigen::MatrixXd> out) {
        for (Eigen::Index k = 0; k < wi.rows(); ++k) {
          const std::int64_t flat = merl_bin(wi.row(k).transpose(), wr.row(k).transpose()).flat();
          for (int c = 0; c < 3; ++c) out(k, c) = kLevel + kSigma * normal_of(flat, c);
        }
      },
      "noisy", true, true);
  write_merl(d / "noisy.binary", noisy);
  const auto src = open_source("merl:" + d / "noisy.binary");
  const int bins[] = {0, 20, 45, 70};
  RowMatrix3d wi(4, 3), wr(4, 3);
  for (int k = 0; k < 4; ++k) {
    Eigen::Vector3d a, b;
    directions_from_half_diff(merl_node(MerlBin{bins[k], 30, 50}), a, b);
    ASSERT_GT(a.z(), 0);
    ASSERT_GT(b.z(), 0);
    wi.row(k) = a.transpose();
    wr.row(k) = b.transpose();
  }
  const std::optional<Eigen::MatrixXd> sigma = src->noise_sigma_at(wi, wr);
  ASSERT_TRUE(sigma.has_value());
  for (int k = 0; k < 4; ++k)
    for (int c = 0; c < 3; ++c) EXPECT_NEAR((*sigma)(k, c) / kSigma, 1.0, kTol) << "theta_h bin " << bins[k] << " channel " << c;
}

}  // namespace ICOBRDF_UNITY_ID
}  // namespace icobrdf
