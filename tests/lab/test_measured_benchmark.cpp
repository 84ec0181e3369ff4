// `bench measured` on a fixture-sized RGL file (tests/io/rgl_test_files.hpp: a coloured Lambertian material,
// 4 incidences x 9 x 9 nodes) without the bank: every budget's lobe stores at most its bytes, the budgets
// too small for any lobe are left out, the chosen storages are reported, and the lobes hold the material.
#include <gtest/gtest.h>

#include <cmath>

#include "icobrdf/core/basis/direction.hpp"
#include "icobrdf/io/tensor_file.hpp"
#include "icobrdf/lab/measured_benchmark.hpp"
#include "tests/io/io_test_support.hpp"
#include "tests/io/rgl_test_files.hpp"
#include "tests/support/unity_id.hpp"

namespace ICOBRDF_UNITY_ID {

using namespace icobrdf;

// Errors of the lobes on this fixture: measured 0.05-0.09 (the RGL reader's interpolation between 4
// incidences of 9 x 9 nodes is Lambert at the nodes only, and the lobes are small); a lobe that lost the
// material (all zero, a channel swapped or dropped) is at 0.4 or more (the albedos 0.2, 0.5, 0.8).
constexpr double kLambertLobeError = 0.15;

std::string lambert_rgl_file(const test::ScratchDir& dir) {
  test::RglFileSpec s;
  s.theta = {0.0, 0.5, 1.0, 1.4};
  s.w = 9, s.h = 9;
  const double rho[3] = {0.2, 0.5, 0.8};
  s.value = [&](int, int t, int c, int k, int j) {
    // Node (k, j) of slice t: the half vector theta_m = (pi/2) (k/(w-1))^2, phi_m = (2 j/(h-1) - 1) pi; the
    // stored value is f cos(theta_o) (no Jacobian).
    const double u = k / (s.w - 1.0), tm = M_PI / 2 * u * u, pm = (2.0 * j / (s.h - 1) - 1) * M_PI;
    const Eigen::Vector3d wi(std::sin(s.theta[t]), 0.0, std::cos(s.theta[t]));
    const Eigen::Vector3d m(std::sin(tm) * std::cos(pm), std::sin(tm) * std::sin(pm), std::cos(tm));
    const Eigen::Vector3d wo = 2 * wi.dot(m) * m - wi;
    return rho[c] / M_PI * std::max(wo.z(), 0.0);
  };
  // The stem of the committed NBRDF network, so that the NBRDF column is filled from tests/data/nbrdf.
  const std::string path = dir / "paper_white_rgb.bsdf";
  write_tensor_file(path, test::rgl_fields(s));
  return path;
}

TEST(MeasuredBench, FixtureRunKeepsEveryLobeWithinItsBudget) {
  const test::ScratchDir dir;
  lab::MeasuredBenchOptions o;
  o.files = {lambert_rgl_file(dir)};
  o.nbrdf_dir = std::string(ICOBRDF_SOURCE_DIR) + "/tests/data/nbrdf";
  o.work_dir = dir.path();
  o.bank = false;
  o.pairs = 400;
  // 60 B: below the smallest lobe (8 x 8 x 4 rank 1 shared int8: 8 + 32 values, 2 column scales, 3 channel
  // scales, 37 B of header = 40 + 16 + 24 + 37 = 117 B).
  o.budgets = {60, 300, 700, 1400};
  const lab::MeasuredBench b = lab::run_measured_bench(o);
  ASSERT_EQ(b.rows.size(), 1u);
  const lab::MeasuredRow& r = b.rows[0];
  EXPECT_TRUE(r.has_nbrdf);
  EXPECT_TRUE(std::isfinite(r.nbrdf_error));
  ASSERT_EQ(r.budgets.size(), 3u);  // 60 B holds no lobe
  for (const auto& p : r.budgets) {
    EXPECT_GT(p.bytes, 0);
    EXPECT_LE(p.bytes, p.budget) << p.grid;
    EXPECT_LT(p.error, kLambertLobeError) << p.grid << " within " << p.budget << " B";
    EXPECT_LT(p.error_reciprocal, kLambertLobeError) << p.grid;
  }
  // 300 B: 3 channels x 8 + 32 float64 values alone are 960 B: only shared or narrower factors fit.
  EXPECT_TRUE(r.budgets[0].grid.find("shared") != std::string::npos || r.budgets[0].grid.find("int") != std::string::npos)
      << r.budgets[0].grid;
  const std::string md = lab::measured_bench_markdown(b);
  EXPECT_NE(md.find("<= 1400 B"), std::string::npos);
}

}  // namespace ICOBRDF_UNITY_ID
