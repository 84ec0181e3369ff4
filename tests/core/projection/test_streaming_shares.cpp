// Shares of the streaming projection (icobrdf/core/projection/streaming_projection.hpp StreamingShare), the core side of
// the distributed projection (icobrdf/cluster/distributed_projection.hpp), without MPI: the shares' matrices
// summed in share order equal the whole projection to the rounding of a reordered sum, bound derived below
// from the blocks' own contributions; every block belongs to exactly one share; delta parts are added once,
// after the reduction; a share without a reduction is refused.
#include <gtest/gtest.h>

#include <cfloat>
#include <memory>
#include <string>
#include <vector>

#include "icobrdf/core/projection/discrete_basis.hpp"
#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/basis/grid_symmetry.hpp"
#include "icobrdf/core/projection/lut.hpp"
#include "icobrdf/core/models/model_registry.hpp"
#include "icobrdf/core/projection/projection.hpp"
#include "icobrdf/core/grid/reference_grids.hpp"
#include "icobrdf/core/projection/streaming_projection.hpp"
#include "tests/support/unity_id.hpp"

namespace icobrdf {
namespace ICOBRDF_UNITY_ID {

// The rounding of reordered block sums, bounded from the LUT's magnitudes (reorder_bound below).
// Operations after a block's products that each add one rounding per entry: the D2 average (four terms) and
// X + X^T (one).
constexpr int kFinishingOps = 5;

// Entry-wise bound on the difference of two summation orders of the n block terms X_b of C = P^T F P: a
// rounded sum of n terms is within (n - 1) u sum_b |X_b| of the exact one (Higham, Accuracy and Stability,
// eq. 4.4), and sum_b |X_b| <= A = |P|^T |F| |P| (each block's term is a sum of products P_i F_ij P_j of the
// sampled rows, weighted by at most 1; the D2 average's factor 4 on a quarter of the rows gives back A). The
// triangle path sums X and adds X^T, both within that bound: 2 A. Two orders: twice.
Eigen::MatrixXd reorder_bound(const BrdfModel& m, const Grid& g, const ProjectionOperator& p, bool cosine, LutSampling sampling, int n) {
  const Eigen::MatrixXd f = build_lut(m, g, cosine, sampling).channels[0].cwiseAbs();
  const Eigen::MatrixXd a = p.P.cwiseAbs().transpose() * f * p.P.cwiseAbs();
  return 2.0 * 2.0 * (n - 1 + kFinishingOps) * DBL_EPSILON * a;
}

// The projection of `model` by `parts` shares, each reduction capturing its share's matrices; the shares'
// matrices, in share order.
std::vector<std::vector<Eigen::MatrixXd>> shares_of(const BrdfModel& m, const Grid& g, const ProjectionOperator& p, bool cosine,
                                                    LutSampling sampling, int parts, int every = 1) {
  std::vector<std::vector<Eigen::MatrixXd>> out(static_cast<size_t>(parts));
  for (int k = 0; k < parts; ++k) {
    StreamingShare s;
    s.part = k;
    s.parts = parts;
    s.every = every;
    s.reduce = [&out, k](std::vector<Eigen::MatrixXd>& x) { out[static_cast<size_t>(k)] = x; };
    streaming_projection(m, g, p, cosine, sampling, nullptr, &s);
  }
  return out;
}

// Blocks of incident rows of a projection: one per kStreamingBlockRows sampled rows.
int block_count(const Grid& g, bool symmetric) {
  const int rows = symmetric ? static_cast<int>(d2_representatives(g).size()) : g.cells();
  return (rows + kStreamingBlockRows - 1) / kStreamingBlockRows;
}

struct Case {
  std::string spec;
  bool cosine;
  LutSampling sampling;
};

// Lat-long grids with (16 x 32, D2-symmetric: 128 orbits, 4 blocks) and without (15 x 21: 315 cells, 10
// blocks) the symmetry; reciprocal isotropic (triangle of orbits), reciprocal anisotropic (triangle), and the
// full path (g form with cell averages), each split in 2 and 3 shares.
TEST(StreamingShares, SumOfSharesEqualsTheWholeToRounding) {
  const Grid symmetric = build_lat_long_grid(16, 32, 2);
  const Grid odd = build_lat_long_grid(15, 21, 2);
  ASSERT_TRUE(has_d2_maps(symmetric));
  ASSERT_FALSE(has_d2_maps(odd));
  const std::vector<Case> cases = {{"ggx:alpha=0.3", false, LutSampling::CellAverage},
                                   {"ggx-aniso:alpha_x=0.4,alpha_y=0.2,azimuth=30", false, LutSampling::CellCentre},
                                   {"ggx:alpha=0.3", true, LutSampling::CellAverage}};
  for (const Grid* g : {&symmetric, &odd}) {
    const auto p = make_projection(build_discrete_basis(*g, 4));
    for (const auto& c : cases) {
      const auto m = parse_model(c.spec);
      const std::string what = c.spec + (c.cosine ? " g" : " f") + (g == &symmetric ? " on the D2 grid" : " on the odd grid");
      const Eigen::MatrixXd whole = streaming_projection(*m, *g, p, c.cosine, c.sampling)[0];
      const int n = block_count(*g, g == &symmetric && m->is_isotropic());
      ASSERT_GE(n, 4) << what;
      const Eigen::MatrixXd bound = reorder_bound(*m, *g, p, c.cosine, c.sampling, n);
      for (int parts : {2, 3}) {
        const auto s = shares_of(*m, *g, p, c.cosine, c.sampling, parts);
        Eigen::MatrixXd sum = s[0][0];
        for (int k = 1; k < parts; ++k) sum += s[static_cast<size_t>(k)][0];
        EXPECT_TRUE(((sum - whole).cwiseAbs().array() <= bound.array()).all())
            << what << ", " << parts << " shares: largest excess " << ((sum - whole).cwiseAbs() - bound).maxCoeff();
        // Not the same as the whole by accident: each share alone is far from it (beyond rounding).
        EXPECT_GT((s[0][0] - whole).cwiseAbs().maxCoeff(), 1e6 * bound.maxCoeff()) << what;
      }
      // every = 2 keeps the even blocks: shares of it sum to the sum of those blocks alone.
      const auto even = shares_of(*m, *g, p, c.cosine, c.sampling, 2, 2);
      const auto single = shares_of(*m, *g, p, c.cosine, c.sampling, n);
      Eigen::MatrixXd expected = Eigen::MatrixXd::Zero(whole.rows(), whole.cols());
      for (int b = 0; b < n; b += 2) expected += single[static_cast<size_t>(b)][0];
      EXPECT_LE((even[0][0] + even[1][0] - expected).cwiseAbs().maxCoeff(), bound.maxCoeff()) << what << ", every 2";
    }
  }
}

// More shares than blocks: the extra shares reduce zero matrices, and the sum is still the whole.
TEST(StreamingShares, SharesWithoutBlocksAddNothing) {
  const Grid g = build_lat_long_grid(6, 12, 2);  // 18 orbits: one block
  const auto p = make_projection(build_discrete_basis(g, 3));
  const auto m = parse_model("ggx:alpha=0.5");
  const Eigen::MatrixXd whole = streaming_projection(*m, g, p, false, LutSampling::CellCentre)[0];
  const auto s = shares_of(*m, g, p, false, LutSampling::CellCentre, 3);
  EXPECT_EQ((s[0][0] - whole).cwiseAbs().maxCoeff(), 0.0);  // the one block, summed alone both times
  EXPECT_EQ(s[1][0].cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ(s[2][0].cwiseAbs().maxCoeff(), 0.0);
}

// Delta parts are not in a share's matrices: they are added once, after the reduction, exactly as in one
// process (the mirror's projection is the same bits whichever share the process projects).
TEST(StreamingShares, DeltaPartsAreAddedOnceAfterTheReduction) {
  const Grid g = build_lat_long_grid(16, 32, 2);
  const auto p = make_projection(build_discrete_basis(g, 4));
  const auto m = parse_model("0.7*lambert+0.3*mirror");
  const auto mirror = delta_projection({DeltaPart::Mirror, 0.3}, g, p);
  std::vector<Eigen::MatrixXd> reduced;
  StreamingShare s;
  s.parts = 2;
  // A stand-in for the cluster's reduction: the sum of both shares is the whole regular part.
  const auto regular = streaming_projection(*parse_model("0.7*lambert"), g, p, true, LutSampling::CellCentre);
  s.reduce = [&](std::vector<Eigen::MatrixXd>& x) {
    reduced = x;
    x = regular;
  };
  const auto out = streaming_projection(*m, g, p, true, LutSampling::CellCentre, nullptr, &s);
  EXPECT_EQ((out[0] - (regular[0] + mirror)).cwiseAbs().maxCoeff(), 0.0);
  // What the share handed to the reduction is the regular part's share alone (no delta in it).
  const auto lambert_share = shares_of(*parse_model("0.7*lambert"), g, p, true, LutSampling::CellCentre, 2)[0];
  EXPECT_EQ((reduced[0] - lambert_share[0]).cwiseAbs().maxCoeff(), 0.0);
}

TEST(StreamingShares, ASplitWithoutAReductionIsRefused) {
  const Grid g = build_lat_long_grid(6, 12, 2);
  const auto p = make_projection(build_discrete_basis(g, 2));
  const auto m = parse_model("lambert");
  StreamingShare s;
  s.parts = 2;
  EXPECT_THROW(streaming_projection(*m, g, p, false, LutSampling::CellCentre, nullptr, &s), ArgumentError);
  s.reduce = [](std::vector<Eigen::MatrixXd>&) {};
  s.part = 2;
  EXPECT_THROW(streaming_projection(*m, g, p, false, LutSampling::CellCentre, nullptr, &s), ArgumentError);
  s.part = 0;
  s.every = 0;
  EXPECT_THROW(streaming_projection(*m, g, p, false, LutSampling::CellCentre, nullptr, &s), ArgumentError);
}

}  // namespace
}  // namespace icobrdf
