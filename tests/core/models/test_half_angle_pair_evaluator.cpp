// HalfAnglePairEvaluator (the per-sample pair code) against HalfAngleFactors::eval (the batch): bitwise the same
// values for every kind of lobe the per-pair code specializes (isotropic or not, stretched, ranks 1-4 unrolled and
// above, shared or per-channel factors, one or three channels, both horizon rules, ends or centred nodes, warps,
// the three quantities), at pairs chosen to reach every branch: random, grazing, both near the horizon (cells the
// horizon cuts: the per-sample evaluator decides them by its counts of valid h nodes, the batch by the node trig),
// mirror pairs, w_i = w_r, the normal, opposite horizontal directions, a NaN and directions just or far below
// the horizon. The expected values are the batch's, an independent path through the corners; the test would fail
// if the counts of valid h nodes, the rank dispatch or the shorter atan2 forms changed one value.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <random>

#include "icobrdf/core/basis/direction.hpp"
#include "icobrdf/core/models/half_angle_factors.hpp"
#include "tests/support/unity_id.hpp"

using namespace icobrdf;

namespace ICOBRDF_UNITY_ID {

struct PairSet {
  RowMatrix3d wi, wr;
};

PairSet hard_pairs(int n) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0, 1);
  PairSet p;
  p.wi.resize(n, 3), p.wr.resize(n, 3);
  for (int i = 0; i < n; ++i) {
    const int kind = i % 8;
    double za = u(rng), zb = u(rng);
    if (kind == 1) za = 1e-3 * u(rng);
    if (kind == 2) za = 0.05 * u(rng), zb = 0.05 * u(rng);
    Eigen::Vector3d a = direction_from_angles(std::acos(za), 2 * M_PI * u(rng));
    Eigen::Vector3d b = direction_from_angles(std::acos(zb), 2 * M_PI * u(rng));
    if (kind == 3) b = Eigen::Vector3d(-a.x(), -a.y(), a.z());
    if (kind == 4) b = a;
    if (kind == 5) a = Eigen::Vector3d(0, 0, 1);
    if (kind == 6) {
      a.z() = 0, a.normalize();
      if (i % 16 == 6) b = Eigen::Vector3d(-a.x(), -a.y(), 0.0);
    }
    if (kind == 7 && i % 64 == 7) a.x() = std::nan("");
    if (kind == 7 && i % 64 == 15) b.z() = -1e-13;
    if (kind == 7 && i % 64 == 23) b.z() = -0.5, b.normalize();
    p.wi.row(i) = a.transpose(), p.wr.row(i) = b.transpose();
  }
  return p;
}

// A lobe of random factors on a small grid of the given kind.
HalfAngleFactors random_lobe(std::mt19937_64& rng, bool isotropic, int rank, bool shared, int channels, bool valid_corners,
                             bool centred, double warp, HalfAngleQuantity quantity) {
  std::uniform_real_distribution<double> s(-1, 1);
  HalfAngleFactors F;
  F.isotropic = isotropic, F.quantity = quantity, F.h_warp = warp, F.centred = centred;
  F.corners = valid_corners ? HorizonCorners::Valid : HorizonCorners::All;
  F.n_t = 20 + rank, F.n_theta_d = 17 + channels, F.n_phi_d = 8 + rank, F.n_phi_h = isotropic ? 1 : 6, F.rank = rank;
  if (!isotropic && rank % 2 == 1) F.h_axis = 0.3, F.h_scale_1 = 2.0, F.h_scale_2 = 0.7;
  const auto random = [&](int rows) { return RowMatrixXd(RowMatrixXd::NullaryExpr(rows, rank, [&] { return s(rng); })); };
  for (int c = 0; c < (shared ? 1 : channels); ++c) F.u.push_back(random(F.h_nodes())), F.v.push_back(random(F.d_nodes()));
  if (shared) F.channel_scales = RowMatrixXd::NullaryExpr(channels, rank, [&] { return s(rng); });
  F.validate();
  return F;
}

TEST(HalfAnglePairEvaluator, BitwiseTheBatchForEveryKindOfLobeAndHardPairs) {
  const PairSet p = hard_pairs(4000);
  std::mt19937_64 rng(3);
  int lobes = 0;
  for (bool iso : {true, false})
    for (int rank : {1, 2, 3, 4, 6})
      for (int channels : {1, 3})
        for (bool shared : {false, true}) {
          if (shared && channels == 1) continue;
          for (bool valid : {true, false}) {
            const int v = lobes % 6;  // node placement, warp and quantity vary with the lobe
            const HalfAngleQuantity q = v % 3 == 0 ? HalfAngleQuantity::Cosine : v % 3 == 1 ? HalfAngleQuantity::F : HalfAngleQuantity::MeanCosine;
            const auto F = std::make_shared<const HalfAngleFactors>(
                random_lobe(rng, iso, rank, shared, channels, valid, v % 2 == 1, v < 2 ? 2.0 : v < 4 ? 1.0 : 1.5, q));
            const Eigen::MatrixXd batch = F->eval(p.wi, p.wr);
            const HalfAnglePairEvaluator ev(F);
            double one[3];
            for (Eigen::Index i = 0; i < p.wi.rows(); ++i) {
              ev.eval(p.wi.row(i).data(), p.wr.row(i).data(), one);
              for (int c = 0; c < channels; ++c)
                ASSERT_EQ(one[c], batch(i, c)) << "lobe " << lobes << " (isotropic " << iso << ", rank " << rank << ", shared "
                                               << shared << ", channels " << channels << ", valid corners " << valid
                                               << ") pair " << i;
            }
            ++lobes;
          }
        }
  EXPECT_EQ(lobes, 2 * 5 * 3 * 2);
}

// The pair set reaches the cells the horizon cuts, where the per-sample evaluator takes its counted path: there
// HorizonCorners::Valid (invalid corners dropped, the rest renormalized) differs from HorizonCorners::All.
TEST(HalfAnglePairEvaluator, ThePairsReachCellsTheHorizonCuts) {
  std::mt19937_64 rng(5);
  HalfAngleFactors valid = random_lobe(rng, true, 2, false, 1, true, false, 2.0, HalfAngleQuantity::Cosine);
  HalfAngleFactors all = valid;
  all.corners = HorizonCorners::All;
  const PairSet p = hard_pairs(4000);
  const Eigen::MatrixXd a = all.eval(p.wi, p.wr);
  const HalfAnglePairEvaluator ev(std::make_shared<const HalfAngleFactors>(valid));
  int cut = 0;
  for (Eigen::Index i = 0; i < p.wi.rows(); ++i) {
    double one;
    ev.eval(p.wi.row(i).data(), p.wr.row(i).data(), &one);
    if (std::isfinite(a(i, 0)) && one != a(i, 0)) ++cut;
  }
  // Pairs near the horizon (a quarter of the set is within 0.05 of it) have cut cells: the rule was applied.
  EXPECT_GT(cut, 100);
}

}  // namespace ICOBRDF_UNITY_ID
