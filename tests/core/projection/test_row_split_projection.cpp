// The streaming projection with its operators split by rows (icobrdf/core/projection/row_split_projection.hpp), without
// MPI: the ring schedule computes every pair of blocks once and its sends meet its receives; the blocks
// keep orbits whole; the parts' sum equals the one-process streaming projection (icobrdf/core/
// streaming_projection.hpp, operators held whole) to rounding, on D2-symmetric and asymmetric grids, for the
// reciprocal triangle, the general path and delta parts; and the driver run by threads exchanging through
// memory gives the serial driver's bits.
#include <gtest/gtest.h>

#include <map>
#include <set>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "icobrdf/core/projection/discrete_basis.hpp"
#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/basis/grid_symmetry.hpp"
#include "icobrdf/core/models/model_registry.hpp"
#include "icobrdf/core/projection/projection.hpp"
#include "icobrdf/core/grid/reference_grids.hpp"
#include "icobrdf/core/projection/row_split_projection.hpp"
#include "icobrdf/core/projection/streaming_projection.hpp"
#include "tests/core/thread_exchange.hpp"
#include "tests/support/unity_id.hpp"

namespace icobrdf {
namespace ICOBRDF_UNITY_ID {

using test::ThreadExchange;

// Split against whole operators, relative to max|C|: the split P comes from G summed in another order and
// from B rows evaluated directly instead of by symmetry, each off by a few ulps times cond(G) (below 2 at
// order 4 on these grids), and the sums over blocks run in another order (at most a few hundred terms of
// rounding u each); 1e-12 is 100x that budget, and far below what any missing or doubled pair gives (a
// part alone is off by more than 1e-3, checked below).
constexpr double kSplitRelTol = 1e-12;
// A projection missing work (one part's share alone, or every other batch of rows) differs from the whole by
// at least this, relative to max|C|: each share carries a sizeable fraction of every coefficient, so the
// gap is of order 0.1-1, and 1e-3 stays 1e9 times above kSplitRelTol.
constexpr double kMissingWorkRelGap = 1e-3;

// The 15 x 21 grid resolves order 4 to a Gram error of 0.12 (condition 1.14): above the default tolerance,
// harmless for comparing two ways of computing the same projection.
constexpr double kOddGridGramTolerance = 0.2;

TEST(RowSplitProjection, RingScheduleComputesEveryPairOnceAndEverySendMeetsAReceive) {
  for (const bool reciprocal : {false, true}) {
    for (int parts = 1; parts <= 7; ++parts) {
      std::map<std::pair<int, int>, int> met;
      std::vector<int> work(static_cast<size_t>(parts), 0);  // in half pairs; a reciprocal block's own triangle is one
      std::vector<RingSchedule> s;
      for (int p = 0; p < parts; ++p) s.push_back(ring_schedule(p, parts, reciprocal));
      for (int p = 0; p < parts; ++p) {
        ASSERT_EQ(s[static_cast<size_t>(p)].steps(), s[0].steps());
        EXPECT_TRUE(s[static_cast<size_t>(p)].compute[0]) << "own block first";
        for (int t = 1; t < s[0].steps(); ++t) {
          const int next = (p + 1) % parts;
          // What part p receives at step t, part p + 1 sends.
          EXPECT_EQ(s[static_cast<size_t>(p)].receive[static_cast<size_t>(t)], s[static_cast<size_t>(next)].send[static_cast<size_t>(t)]);
          // A part computes at step t only with the block it received then.
          if (s[static_cast<size_t>(p)].compute[static_cast<size_t>(t)]) {
            EXPECT_TRUE(s[static_cast<size_t>(p)].receive[static_cast<size_t>(t)]);
          }
          // It sends at step t what it held at step t - 1: that must have been received (or be its own).
          if (t > 1 && s[static_cast<size_t>(p)].send[static_cast<size_t>(t)]) {
            EXPECT_TRUE(s[static_cast<size_t>(p)].receive[static_cast<size_t>(t - 1)]);
          }
        }
        for (int t = 0; t < s[0].steps(); ++t) {
          if (!s[static_cast<size_t>(p)].compute[static_cast<size_t>(t)]) continue;
          const int v = (p + t) % parts;
          // Halves count 1 each, whole pairs 2: every pair must reach 2.
          const int weight = s[static_cast<size_t>(p)].half[static_cast<size_t>(t)] ? 1 : 2;
          met[reciprocal ? std::make_pair(std::min(p, v), std::max(p, v)) : std::make_pair(p, v)] += weight;
          work[static_cast<size_t>(p)] += reciprocal && t == 0 ? 1 : weight;
          if (s[static_cast<size_t>(p)].half[static_cast<size_t>(t)]) {
            // The other part of the pair computes the other half at the same step.
            ASSERT_TRUE(reciprocal);
            EXPECT_EQ(s[static_cast<size_t>(v)].half[static_cast<size_t>(t)], 3 - s[static_cast<size_t>(p)].half[static_cast<size_t>(t)]);
          }
        }
      }
      const size_t pairs = reciprocal ? static_cast<size_t>(parts * (parts + 1) / 2) : static_cast<size_t>(parts * parts);
      EXPECT_EQ(met.size(), pairs) << parts << " parts";
      for (const auto& [pair, count] : met) EXPECT_EQ(count, 2) << pair.first << "," << pair.second << " of " << parts;
      // Every part does the same work.
      for (int p = 1; p < parts; ++p) EXPECT_EQ(work[static_cast<size_t>(p)], work[0]) << "part " << p << " of " << parts;
    }
  }
  EXPECT_THROW(ring_schedule(2, 2, true), ArgumentError);
}

TEST(RowSplitProjection, BlocksKeepOrbitsWholeAndShareTheCellsEvenly) {
  const Grid g = build_lat_long_grid(16, 32, 2);
  ASSERT_TRUE(has_d2_maps(g));
  for (int parts : {1, 2, 3, 5}) {
    const CellBlocks cb = cell_blocks(g, parts);
    ASSERT_EQ(cb.parts(), parts);
    std::set<int> seen;
    for (int b = 0; b < parts; ++b) {
      const auto cells = cb.cells(b);
      // Within one orbit (at most 4 cells) of an even share.
      EXPECT_LE(std::abs(cb.size(b) - g.cells() / parts), 4) << parts;
      std::set<int> mine(cells.begin(), cells.end());
      for (const int c : cells) {
        seen.insert(c);
        for (const auto& s : d2_maps(g)) EXPECT_TRUE(mine.count((*s.cells)[c])) << "orbit of cell " << c << " split, " << parts << " parts";
      }
    }
    EXPECT_EQ(static_cast<int>(seen.size()), g.cells());
  }
  EXPECT_THROW(cell_blocks(g, 0), ArgumentError);
  EXPECT_THROW(cell_blocks(g, g.cells()), ArgumentError);  // more parts than orbits
}

struct Case {
  std::string spec;
  bool cosine;
  LutSampling sampling;
};

// Lat-long grids with (16 x 32, D2-symmetric) and without (15 x 21) the symmetry; reciprocal isotropic
// (triangle of orbits), reciprocal anisotropic (triangle of cells), the general path (g form with cell
// averages) and a mirror delta part; split in 1 to 4 parts.
TEST(RowSplitProjection, SumOfPartsEqualsTheWholeProjectionToRounding) {
  const Grid symmetric = build_lat_long_grid(16, 32, 2);
  const Grid odd = build_lat_long_grid(15, 21, 2);
  ASSERT_FALSE(has_d2_maps(odd));
  const std::vector<Case> cases = {{"ggx:alpha=0.3", false, LutSampling::CellAverage},
                                   {"ggx-aniso:alpha_x=0.4,alpha_y=0.2,azimuth=30", false, LutSampling::CellCentre},
                                   {"ggx:alpha=0.3", true, LutSampling::CellAverage},
                                   {"ggx-aniso:alpha_x=0.4,alpha_y=0.2,azimuth=30", true, LutSampling::CellAverage},
                                   {"0.7*lambert+0.3*mirror", true, LutSampling::CellCentre}};
  for (const Grid* g : {&symmetric, &odd}) {
    const auto p = make_projection(build_discrete_basis(*g, 4));
    for (const auto& c : cases) {
      const auto m = parse_model(c.spec);
      if (!m->delta_parts().empty() && g == &odd) continue;  // a mirror needs the rotation-by-pi map
      const std::string what = c.spec + (c.cosine ? " g" : " f") + (g == &symmetric ? " on the D2 grid" : " on the odd grid");
      const Eigen::MatrixXd whole = streaming_projection(*m, *g, p, c.cosine, c.sampling)[0];
      const double scale = whole.cwiseAbs().maxCoeff();
      for (int parts : {1, 2, 3, 4}) {
        const Eigen::MatrixXd split = row_split_projection_serial(*m, *g, 4, parts, c.cosine, c.sampling, nullptr, kOddGridGramTolerance)[0];
        EXPECT_LE((split - whole).cwiseAbs().maxCoeff(), kSplitRelTol * scale) << what << ", " << parts << " parts";
      }
    }
  }
}

// The driver itself (operators built split, the ring shifts, one sum), on threads: every part ends with the
// serial driver's bits, and holds only its own block's rows of P.
TEST(RowSplitProjection, DriverOnThreadsGivesTheSerialResultOnEveryPart) {
  const Grid g = build_lat_long_grid(16, 32, 2);
  for (const auto& c : std::vector<Case>{{"ggx:alpha=0.3", false, LutSampling::CellAverage},
                                         {"ggx-aniso:alpha_x=0.4,alpha_y=0.2,azimuth=30", true, LutSampling::CellAverage}}) {
    const auto m = parse_model(c.spec);
    for (int parts : {2, 3, 4}) {
      const auto serial = row_split_projection_serial(*m, g, 4, parts, c.cosine, c.sampling);
      ThreadExchange x(parts);
      std::vector<std::vector<Eigen::MatrixXd>> out(static_cast<size_t>(parts));
      std::vector<Eigen::Index> rows(static_cast<size_t>(parts));
      std::vector<std::thread> threads;
      for (int p = 0; p < parts; ++p)
        threads.emplace_back([&, p] {
          ThreadExchange::Part e(x, p);
          const SplitOperators ops = split_operators(g, 4, kDefaultGramTolerance, e);
          rows[static_cast<size_t>(p)] = ops.P.rows();
          out[static_cast<size_t>(p)] = row_split_projection(*m, g, ops, c.cosine, c.sampling, nullptr, e);
        });
      for (auto& t : threads) t.join();
      for (int p = 0; p < parts; ++p) {
        EXPECT_EQ((out[static_cast<size_t>(p)][0] - serial[0]).cwiseAbs().maxCoeff(), 0.0) << c.spec << ", part " << p << " of " << parts;
        EXPECT_LE(rows[static_cast<size_t>(p)], g.cells() / parts + 4) << "rows of P held by part " << p;
        // Each part's own matrices are far from the whole: the sum is not one part doing all the work.
        const Eigen::MatrixXd& own = x.last_contributions_.at(p)[0];
        EXPECT_GT((own - serial[0]).cwiseAbs().maxCoeff(), kMissingWorkRelGap * serial[0].cwiseAbs().maxCoeff()) << c.spec << ", part " << p;
      }
    }
  }
}

// `every` (bench streaming --every K under mpirun): every K-th batch of each pair's incident rows. K = 1 is the
// projection; K = 2 drops every other batch (a different matrix); K < 1 is refused on every part.
TEST(RowSplitProjection, EveryKeepsEveryKthBatchOfEachPair) {
  const Grid g = build_lat_long_grid(16, 32, 2);
  const auto m = parse_model("ggx-aniso:alpha_x=0.4,alpha_y=0.2,azimuth=30");
  const auto serial = row_split_projection_serial(*m, g, 4, 2, true, LutSampling::CellAverage);
  std::map<int, Eigen::MatrixXd> by_every;
  for (int every : {1, 2}) {
    ThreadExchange x(2);
    std::vector<Eigen::MatrixXd> out(2);
    std::vector<std::thread> threads;
    for (int p = 0; p < 2; ++p)
      threads.emplace_back([&, p] {
        ThreadExchange::Part e(x, p);
        const SplitOperators ops = split_operators(g, 4, kDefaultGramTolerance, e);
        out[static_cast<size_t>(p)] = row_split_projection(*m, g, ops, true, LutSampling::CellAverage, nullptr, e, every)[0];
      });
    for (auto& t : threads) t.join();
    EXPECT_EQ((out[1] - out[0]).cwiseAbs().maxCoeff(), 0.0) << "every " << every << ": both parts the same bits";
    by_every[every] = out[0];
  }
  EXPECT_EQ((by_every[1] - serial[0]).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_GT((by_every[2] - serial[0]).cwiseAbs().maxCoeff(), kMissingWorkRelGap * serial[0].cwiseAbs().maxCoeff()) << "every other batch dropped";
  ThreadExchange one(1);
  ThreadExchange::Part e(one, 0);
  const SplitOperators ops = split_operators(g, 4, kDefaultGramTolerance, e);
  EXPECT_THROW(row_split_projection(*m, g, ops, true, LutSampling::CellAverage, nullptr, e, 0), ArgumentError);
}

}  // namespace
}  // namespace icobrdf
