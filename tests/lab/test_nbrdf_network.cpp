// The Neural-BRDF evaluator against the authors' forward pass: values of the committed paper_white network
// (tests/data/nbrdf/README.md) at pairs, computed independently by a NumPy port of the published Keras model
// and coordinate code (dense layers in float64, io_to_hd with Rodrigues rotations), with NBRDF's
// illumination slot given icobrdf's w_r.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/lab/nbrdf_network.hpp"
#include "tests/support/unity_id.hpp"

namespace ICOBRDF_UNITY_ID {

using namespace icobrdf;
using namespace icobrdf::lab;

// Both evaluations run in float64 on the same float32 weights; three layers of 21-term sums and an exp
// leave differences of a few ulps.
constexpr double kForwardTolerance = 1e-12;

const std::string kNetwork = std::string(ICOBRDF_SOURCE_DIR) + "/tests/data/nbrdf/paper_white_rgb.h5";

Eigen::Vector3d direction(double theta_deg, double phi_deg) {
  const double t = theta_deg * M_PI / 180, p = phi_deg * M_PI / 180;
  return {std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)};
}

TEST(NbrdfNetwork, ReadsTheReleasedWeights) {
  const NbrdfNetwork n = read_nbrdf_network(kNetwork);
  EXPECT_EQ(n.w1.rows(), 6);
  EXPECT_EQ(n.w1.cols(), 21);
  EXPECT_EQ(n.w2.rows(), 21);
  EXPECT_EQ(n.w3.cols(), 3);
  EXPECT_EQ(n.b3.size(), 3);
  EXPECT_EQ(kNbrdfBytes, 2700);  // 675 float32 numbers
}

TEST(NbrdfNetwork, MatchesTheReferenceForwardPass) {
  // theta_i, phi_i, theta_r, phi_r [deg]; f_r, f_g, f_b [1/sr] from the reference evaluator.
  const double rows[][7] = {
      {0, 0, 30, 0, 0.26334963548118484, 0.26801821101426815, 0.31457511124507453},
      {30, 0, 30, 180, 0.28248826299192409, 0.28584040335550154, 0.33048883532429985},
      {60, 0, 20, 0, 0.25103147756582955, 0.25494400042026011, 0.29843410929729353},
      {20, 0, 60, 0, 0.23861287032798306, 0.2430521872924376, 0.28679240190064692},
      {75, 0, 75, 180, 0.7160440185868, 0.70446361937844193, 0.73298808154816353},
      {45, 10, 50, 100, 0.25819048589183291, 0.26195113429742234, 0.30515379194828807},
      {10, 200, 70, 30, 0.26686046566893751, 0.26967846972862364, 0.31104270427511649},
      {0.1, 0, 0.1, 180, 0.26740792773194033, 0.27184955096423602, 0.31894589970915277},  // h within the pole cap
  };
  const int n = static_cast<int>(std::size(rows));
  RowMatrix3d wi(n, 3), wr(n, 3);
  for (int k = 0; k < n; ++k) {
    wi.row(k) = direction(rows[k][0], rows[k][1]).transpose();
    wr.row(k) = direction(rows[k][2], rows[k][3]).transpose();
  }
  const Eigen::MatrixXd f = read_nbrdf_network(kNetwork).eval(wi, wr);
  for (int k = 0; k < n; ++k)
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(f(k, c), rows[k][4 + c], kForwardTolerance * rows[k][4 + c]) << "pair " << k << " channel " << c;
  // The slots differ: swapping the directions (rows 2 and 3) changes the value by ~5%.
  EXPECT_GT(std::abs(f(2, 0) - f(3, 0)), 0.01 * f(2, 0));
}

TEST(NbrdfNetwork, ZeroBelowTheHorizon) {
  RowMatrix3d wi(2, 3), wr(2, 3);
  wi << 0, 0, 1, 0.6, 0, -0.8;
  wr << 0.6, 0, -0.8, 0, 0, 1;
  EXPECT_TRUE(read_nbrdf_network(kNetwork).eval(wi, wr).isZero(0.0));
}

TEST(NbrdfNetwork, RefusesAFileWithoutTheLayers) {
  const std::string path = ::testing::TempDir() + "nbrdf_not_h5.h5";
  std::ofstream(path) << "not an hdf5 file\n";
  EXPECT_THROW(read_nbrdf_network(path), InputError);
  std::filesystem::remove(path);
}

}  // namespace ICOBRDF_UNITY_ID
