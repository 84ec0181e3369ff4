// The reciprocal streaming projection (icobrdf/core/projection/streaming_projection.cpp): for a Helmholtz-reciprocal model
// only one triangle of the LUT is sampled (an eighth of it with the D2 symmetry, half without), in f form
// with any sampling and in g form with centre sampling. Each case must equal P^T F P of the materialized
// LUT, be bitwise the same on 1 and 2 threads, and a model that is not reciprocal must not take the path.
#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <memory>
#include <string>

#include "icobrdf/core/projection/discrete_basis.hpp"
#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/models/function_model.hpp"
#include "icobrdf/core/basis/grid_symmetry.hpp"
#include "icobrdf/core/projection/lut.hpp"
#include "icobrdf/core/models/model_registry.hpp"
#include "icobrdf/core/projection/projection.hpp"
#include "icobrdf/core/grid/reference_grids.hpp"
#include "icobrdf/core/projection/streaming_projection.hpp"
#include "tests/support/unity_id.hpp"

namespace icobrdf {
namespace ICOBRDF_UNITY_ID {

// Streaming and materialized projections add the same products in another order (the triangle path adds
// each off-diagonal pair once and transposes): rounding of sums of ~cells^2 terms, relative to max|C|.
constexpr double kAlgebraTol = 1e-12;

// f = 1 + wi_z: isotropic (depends on theta_i only) but not reciprocal, so its LUT is not symmetric.
class IncidenceOnly final : public ScalarBrdfModel {
 public:
  double value(const Eigen::Vector3d& wi, const Eigen::Vector3d&) const override { return 1.0 + wi.z(); }
  bool is_reciprocal() const override { return false; }
  std::string spec() const override { return "test:incidence-only"; }
};

// f = 1 + wi_x / 2 + wr_y / 4: neither isotropic nor reciprocal.
class Skewed final : public ScalarBrdfModel {
 public:
  double value(const Eigen::Vector3d& wi, const Eigen::Vector3d& wr) const override { return 1.0 + 0.5 * wi.x() + 0.25 * wr.y(); }
  bool is_isotropic() const override { return false; }
  bool is_reciprocal() const override { return false; }
  std::string spec() const override { return "test:skewed"; }
};

void expect_streaming_equals_lut(const BrdfModel& m, const Grid& g, const ProjectionOperator& p, bool cosine, LutSampling sampling) {
  const Eigen::MatrixXd direct = project_lut(p, build_lut(m, g, cosine, sampling).channels[0]);
  omp_set_num_threads(2);
  const auto two = streaming_projection(m, g, p, cosine, sampling);
  omp_set_num_threads(1);
  const auto one = streaming_projection(m, g, p, cosine, sampling);
  omp_set_num_threads(2);
  const double scale = direct.cwiseAbs().maxCoeff();
  const std::string what = m.spec() + " on " + std::string(to_string(g.kind)) + (cosine ? " g" : " f") +
                           (sampling == LutSampling::CellCentre ? " centre" : " average");
  EXPECT_LT((two[0] - direct).cwiseAbs().maxCoeff(), kAlgebraTol * scale) << what;
  EXPECT_EQ((two[0] - one[0]).cwiseAbs().maxCoeff(), 0.0) << what << ": 1 and 2 threads must agree bitwise";
}

// Reciprocal models on a D2-symmetric grid (lat-long with an even sector count) and on one without the
// rotation by pi (odd sector count): isotropic and anisotropic GGX, a diffuse + delta sum (in
// g form), in every form the path covers and in g form with cell averages (which it must leave alone).
TEST(ReciprocalStreaming, EqualsTheMaterializedLut) {
  const Grid symmetric = build_lat_long_grid(6, 12, 2);
  const Grid odd = build_lat_long_grid(5, 7, 2);
  ASSERT_TRUE(has_d2_maps(symmetric));
  ASSERT_FALSE(has_d2_maps(odd));
  const int order = 4;
  for (const Grid* g : {&symmetric, &odd}) {
    const auto p = make_projection(build_discrete_basis(*g, order));
    for (const std::string spec : {"ggx:alpha=0.3", "ggx-aniso:alpha_x=0.4,alpha_y=0.2,azimuth=30"}) {
      const auto m = parse_model(spec);
      ASSERT_TRUE(m->is_reciprocal());
      for (bool cosine : {false, true})
        for (auto sampling : {LutSampling::CellAverage, LutSampling::CellCentre}) expect_streaming_equals_lut(*m, *g, p, cosine, sampling);
    }
    // The mirror's delta needs the rotation by pi, which the odd grid lacks; the retroreflector's does not.
    const auto with_delta = parse_model(g == &symmetric ? "0.7*lambert+0.3*mirror" : "0.7*lambert+0.3*retroreflector");
    expect_streaming_equals_lut(*with_delta, *g, p, true, LutSampling::CellCentre);
  }
}

// A non-reciprocal model's LUT is not symmetric (so sampling one triangle would be wrong, and this test
// would catch it); the streaming projection must still equal the materialized LUT's.
TEST(ReciprocalStreaming, NonReciprocalModelsTakeTheFullPath) {
  const Grid symmetric = build_lat_long_grid(6, 12, 2);
  const Grid odd = build_lat_long_grid(5, 7, 2);
  // The relative antisymmetric part of f = 1 + wi_z is ~0.1 on any grid; 0.01 proves the LUT asymmetric.
  constexpr double kClearlyAsymmetric = 0.01;
  const IncidenceOnly incidence;
  const Skewed skewed;
  for (const Grid* g : {&symmetric, &odd}) {
    const auto p = make_projection(build_discrete_basis(*g, 4));
    for (const BrdfModel* m : {static_cast<const BrdfModel*>(&incidence), static_cast<const BrdfModel*>(&skewed)}) {
      EXPECT_GT(reciprocity_violation(build_lut(*m, *g, false, LutSampling::CellCentre).channels[0], g->solid_angles), kClearlyAsymmetric)
          << m->spec();
      for (bool cosine : {false, true})
        for (auto sampling : {LutSampling::CellAverage, LutSampling::CellCentre}) expect_streaming_equals_lut(*m, *g, p, cosine, sampling);
    }
  }
}

// Many blocks (2,560 cells: 20 blocks of D2 representatives of unequal cost on the reciprocal path, 80 on
// the full path, against kStreamingBlocksAhead = 4 waiting): partial sums finished out of order are still
// added in block order, so 1 and 2 threads agree bitwise, and both equal the materialized LUT's projection.
TEST(ReciprocalStreaming, ManyBlocksAreAddedInBlockOrder) {
  const Grid g = build_lat_long_grid(40, 64, 2);
  ASSERT_EQ(g.cells(), 2560);
  const auto p = make_projection(build_discrete_basis(g, 4));
  expect_streaming_equals_lut(*parse_model("ggx:alpha=0.2"), g, p, false, LutSampling::CellCentre);
  expect_streaming_equals_lut(Skewed(), g, p, false, LutSampling::CellCentre);
}

// Centre sampling: entry (i, r) of a block is the model at the two cells' directions times cos theta of the
// incident one, for a row count that fills one group of rows and part of the next (the block is written a
// group of rows at a time) and an anisotropic, so unequal-under-transposition, model.
// The model evaluated for one pair may round differently from the same pair in a long vector run (SIMD
// lanes against the scalar tail): a few ulps, far below any misplaced entry.
constexpr double kPairRounding = 1e-13;

TEST(LutBlock, CentreEntriesAreTheModelAtTheCellDirections) {
  const Grid g = build_lat_long_grid(4, 8, 2);
  const auto m = parse_model("ggx-aniso:alpha_x=0.4,alpha_y=0.2,azimuth=30");
  const std::vector<int> rows{5, 0, 17, 3, 30, 8, 9, 21, 2, 31, 12};
  const int col_end = g.cells() - 3;
  std::vector<Eigen::MatrixXd> block;
  sample_lut_block(*m, g, true, LutSampling::CellCentre, rows, col_end, block);
  ASSERT_EQ(block[0].rows(), static_cast<Eigen::Index>(rows.size()));
  ASSERT_EQ(block[0].cols(), col_end);
  RowMatrix3d wi(1, 3), wr(1, 3);
  Eigen::MatrixXd f(1, 1);
  for (size_t i = 0; i < rows.size(); ++i)
    for (int r = 0; r < col_end; ++r) {
      wi = g.directions.row(rows[i]);
      wr = g.directions.row(r);
      m->eval(wi, wr, f);
      const double expected = f(0, 0) * g.directions(rows[i], 2);
      EXPECT_NEAR(block[0](static_cast<Eigen::Index>(i), r), expected, kPairRounding * std::abs(expected)) << "row " << i << ", column " << r;
    }
}

// sample_lut_columns is sample_lut_block transposed, bit for bit: both samplings, 1 and 3 channels, some
// columns left out, rows in any order, and no rows or no columns at all.
TEST(LutBlock, ColumnsAreTheBlockTransposedBitForBit) {
  const Grid g = build_lat_long_grid(4, 8, 2);
  const auto ggx = parse_model("ggx-aniso:alpha_x=0.4,alpha_y=0.2,azimuth=30");
  const FunctionModel rgb(
      3,
      [&ggx](const RowMatrix3d& wi, const RowMatrix3d& wr, Eigen::Ref<Eigen::MatrixXd> out) {
        Eigen::MatrixXd f(wi.rows(), 1);
        ggx->eval(wi, wr, f);
        for (int c = 0; c < 3; ++c) out.col(c) = (1.0 + c) * f.col(0) + (wi.col(2) - 0.5 * c * wr.col(0)).matrix();
      },
      "test:rgb", false, false);
  const std::vector<int> rows{5, 0, 17, 3, 30, 8, 9, 21, 2, 31, 12};
  for (const BrdfModel* m : {static_cast<const BrdfModel*>(ggx.get()), static_cast<const BrdfModel*>(&rgb)})
    for (auto sampling : {LutSampling::CellAverage, LutSampling::CellCentre})
      for (bool cosine : {false, true})
        for (int col_end : {g.cells(), g.cells() - 5, 0}) {
          std::vector<Eigen::MatrixXd> block, columns;
          sample_lut_block(*m, g, cosine, sampling, rows, col_end, block);
          sample_lut_columns(*m, g, cosine, sampling, rows, col_end, columns);
          ASSERT_EQ(columns.size(), static_cast<size_t>(m->channels()));
          for (int c = 0; c < m->channels(); ++c) {
            ASSERT_EQ(columns[c].rows(), col_end);
            ASSERT_EQ(columns[c].cols(), static_cast<Eigen::Index>(rows.size()));
            EXPECT_TRUE(columns[c] == block[c].transpose()) << m->spec() << ", channel " << c << ", col_end " << col_end;
          }
        }
  std::vector<Eigen::MatrixXd> none;
  sample_lut_columns(*ggx, g, false, LutSampling::CellCentre, {}, g.cells(), none);
  EXPECT_EQ(none[0].rows(), g.cells());
  EXPECT_EQ(none[0].cols(), 0);
  EXPECT_THROW(sample_lut_columns(*ggx, g, false, LutSampling::CellCentre, {g.cells()}, 1, none), ArgumentError);
}

// sample_lut_block gives the leading columns of the full rows, bit for bit, in both samplings.
TEST(LutBlock, LeadingColumnsOfTheFullRows) {
  const Grid g = build_lat_long_grid(4, 8, 2);
  const auto m = parse_model("ggx:alpha=0.3");
  for (auto sampling : {LutSampling::CellAverage, LutSampling::CellCentre}) {
    std::vector<Eigen::MatrixXd> full, block;
    sample_lut_rows(*m, g, true, sampling, std::vector<int>{5, 0, 17}, full);
    sample_lut_block(*m, g, true, sampling, std::vector<int>{5, 0, 17}, 11, block);
    ASSERT_EQ(block[0].rows(), 3);
    ASSERT_EQ(block[0].cols(), 11);
    EXPECT_EQ((block[0] - full[0].leftCols(11)).cwiseAbs().maxCoeff(), 0.0);
    sample_lut_block(*m, g, true, sampling, std::vector<int>{5}, 0, block);
    EXPECT_EQ(block[0].cols(), 0);
  }
  std::vector<Eigen::MatrixXd> out;
  EXPECT_THROW(sample_lut_block(*m, g, true, LutSampling::CellCentre, std::vector<int>{0}, g.cells() + 1, out), ArgumentError);
  EXPECT_THROW(sample_lut_block(*m, g, true, LutSampling::CellCentre, std::vector<int>{0}, -1, out), ArgumentError);
}

}  // namespace
}  // namespace icobrdf
