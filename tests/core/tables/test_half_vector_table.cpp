// HalfVectorTable (icobrdf/core/tables/half_vector_table.hpp): the density a draw reports against pdf() at the
// drawn direction, for incident directions between every pair of neighbouring nodes. An aliased draw takes
// the drawn node's slopes at the alias cell from its alias entry (read with it) and the blend nodes' masses
// (and the other nodes' slopes) from the cell-major table; the density it reports uses those slopes, while
// pdf() reads every entry from the cell-major table. The two agree only if the draw picks the right blend
// node's entries of the right cell and the alias entries carry the right node's slopes of the right cell: a
// partner's entry from the wrong side, or slopes of another node or cell, change the density by the
// difference of two nodes' (or cells') densities, which for a GGX lobe of alpha 0.2 is far above rounding.
#include <gtest/gtest.h>

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <memory>
#include <random>
#include <string>

#include "icobrdf/core/basis/direction.hpp"
#include "icobrdf/core/models/model_registry.hpp"
#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/support/memory_budget.hpp"
#include "icobrdf/core/tables/half_vector_table.hpp"
#include "tests/support/unity_id.hpp"

namespace icobrdf {
namespace ICOBRDF_UNITY_ID {

// pdf() finds the drawn cell and position again from (w_i, w_r): the rounding of h (1e-16) over the pole
// cell's cos range (1.2e-6 with 32 t bins) moves the position by 1e-10, the linear density by twice that.
constexpr double kPdfRoundTripRelTol = 1e-8;
// Draws per incident direction (many of them aliased: the alias method tops up the many cells below the mean
// mass of a lobe this narrow from the lobe's cells).
constexpr int kDraws = 4000;

NonNegativeBrdf model_fbar(const std::string& spec) {
  const std::shared_ptr<const BrdfModel> m(parse_model_source(spec));
  return [m](const RowMatrix3d& wi, const RowMatrix3d& wr) {
    Eigen::MatrixXd v(wi.rows(), m->channels());
    m->eval(wi, wr, v);
    return Eigen::VectorXd(v.col(0).cwiseMax(0.0));
  };
}

// Draws at incident directions a quarter and three quarters of the way between nodes a and a + 1 (unequal
// blend weights, so a swap of the two nodes' roles changes the density too), at two azimuths; every draw's
// density must be pdf() at its direction. Returns the number of valid draws.
int check_draws_between_nodes(const HalfVectorTable& t, const std::string& name) {
  const HalfVectorTableOptions& o = t.options();
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int valid = 0, mismatched = 0;
  for (int a = 0; a + 1 < o.theta_nodes; ++a)
    for (const double frac : {0.25, 0.75})
      for (const double phi : {0.0, 2.1}) {
        const double theta = kHalfVectorThetaMax * (a + frac) / (o.theta_nodes - 1);
        const Eigen::Vector3d wi = direction_from_angles(theta, phi);
        for (int i = 0; i < kDraws; ++i) {
          Eigen::Vector3d wr;
          double p = 0.0;
          if (!t.sample(wi, u(rng), u(rng), wr, p)) continue;
          ++valid;
          const double q = t.pdf(wi, wr);
          if (std::abs(p - q) > kPdfRoundTripRelTol * q && ++mismatched <= 5)
            ADD_FAILURE() << name << ": between nodes " << a << " and " << a + 1 << " (" << frac << "), phi_i " << phi
                          << ": sample's pdf " << p << ", pdf() " << q;
        }
      }
  EXPECT_EQ(mismatched, 0) << name;
  return valid;
}

TEST(HalfVectorTable, DrawsReportThePdfBetweenEveryPairOfNodes) {
  HalfVectorTableOptions mirrored;
  mirrored.theta_nodes = 8;
  mirrored.t_bins = mirrored.phi_bins = 32;
  HalfVectorTableOptions full = mirrored;
  full.mirror = false;
  HalfVectorTableOptions odd = mirrored;  // an odd phi_bins: not mirrored either
  odd.phi_bins = 33;
  const NonNegativeBrdf ggx = model_fbar("model:ggx:alpha=0.2");
  for (const auto& [name, o] : {std::pair<std::string, HalfVectorTableOptions>{"mirrored", mirrored}, {"full", full}, {"odd", odd}}) {
    const HalfVectorTable t(ggx, o);
    // Most draws are valid (w_r below the horizon only from the floor's share and the lobe's tail).
    EXPECT_GT(check_draws_between_nodes(t, name), (o.theta_nodes - 1) * 4 * kDraws / 2) << name;
  }
}

// Anisotropic tables: 4 blend nodes, the drawn one anywhere among them.
TEST(HalfVectorTable, AnisotropicDrawsReportThePdfBetweenEveryPairOfNodes) {
  HalfVectorTableOptions o;
  o.theta_nodes = 6;
  o.azimuth_nodes = 4;
  o.t_bins = o.phi_bins = 32;
  const HalfVectorTable t(model_fbar("model:ggx-aniso:alpha_x=0.1,alpha_y=0.4,azimuth=30"), o);
  EXPECT_GT(check_draws_between_nodes(t, "anisotropic"), (o.theta_nodes - 1) * 4 * kDraws / 2);
}

// The blend's polar angle: 2 asin(sin(theta / 2)) by asin's series to u^15. With u = sin(theta / 2) and the
// series' coefficients c_n = (2n)! / (4^n (n!)^2 (2n + 1)) falling with n, what is left out is at most
// 2 u c_8 u^16 / (1 - u^2) (c_8 from factorials here, not from the code's recurrence). The angle is taken from
// z = cos(theta) alone, so z's own rounding (std::cos within an ulp of 1, kCosRounding) moves it by up to
// kCosRounding / sin(theta) (dtheta/dz = -1 / sin theta): 1e-13 rad at 1e-3 rad; the series' own rounding adds a
// few ulps of theta.
constexpr double kCosRounding = 2.220446049250313e-16;  // an ulp of 1 (std::numeric_limits<double>::epsilon())
constexpr double kBlendThetaRoundingTol = 1e-15;

TEST(HalfVectorTable, BlendThetaIsThePolarAngleWithinTheSeriesTail) {
  const double c8 = std::tgamma(17.0) / (std::pow(4.0, 8) * std::pow(std::tgamma(9.0), 2) * 17.0);
  EXPECT_EQ(HalfVectorTable::blend_theta(1.0), 0.0);
  double worst = 0.0;
  for (int i = 1; i <= 2000; ++i) {
    const double theta = kHalfVectorThetaMax * i / 2000, u = std::sin(theta / 2);
    const double tail = 2 * u * c8 * std::pow(u, 16) / (1 - u * u) + kCosRounding / std::sin(theta);
    const double err = std::abs(HalfVectorTable::blend_theta(std::cos(theta)) - theta);
    EXPECT_LE(err, tail + kBlendThetaRoundingTol) << theta;
    worst = std::max(worst, err);
  }
  // The header's figure: below 1.2e-4 rad up to theta_max.
  EXPECT_LT(worst, 1.2e-4);
  // Beyond the horizon's side of the range the angle is held: z > 1 (rounding) gives 0, z < 0 at most pi / 2.
  EXPECT_EQ(HalfVectorTable::blend_theta(1.0 + 1e-12), 0.0);
  EXPECT_NEAR(HalfVectorTable::blend_theta(0.0), M_PI / 2, 2 * c8 * std::pow(0.5, 8.5) / 0.5 + kBlendThetaRoundingTol);
}

TEST(HalfVectorTable, TablesNeedingMoreThanTheMemoryBudgetAreRefusedBeforeAnyWork) {
  struct BudgetGuard {
    ~BudgetGuard() { set_memory_budget(0); }
  } guard;
  HalfVectorTableOptions o;  // defaults: 48 nodes, 128 x 64 stored (mirrored) bins
  // The tables alone: a mass (float) and two int16 slopes per node and cell, and an alias entry (float, int,
  // two int16); the work arrays add less than half of that with 48 nodes.
  const double tables = 48.0 * 128 * 64 * (4 + 2 + 2 + 4 + 4 + 2 + 2);
  EXPECT_GE(HalfVectorTable::bytes(o), tables);
  EXPECT_LE(HalfVectorTable::bytes(o), 1.5 * tables);
  HalfVectorTableOptions full = o;
  full.mirror = false;  // every phi bin stored: twice the tables
  EXPECT_NEAR(HalfVectorTable::bytes(full) / HalfVectorTable::bytes(o), 2.0, 1e-12);
  int calls = 0;
  const NonNegativeBrdf lambert = [&calls](const RowMatrix3d& wi, const RowMatrix3d&) {
    ++calls;
    return Eigen::VectorXd(Eigen::VectorXd::Constant(wi.rows(), 1.0 / M_PI));
  };
  set_memory_budget(HalfVectorTable::bytes(o) - 1);
  try {
    HalfVectorTable t(lambert, o);
    FAIL() << "tables of " << HalfVectorTable::bytes(o) << " bytes were built under a smaller budget";
  } catch (const ResourceError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("half-vector tables of 48 incident nodes x 128 x 128 half-vector bins needs about"), std::string::npos) << m;
    EXPECT_NE(m.find("(memory budget)"), std::string::npos) << m;
    EXPECT_NE(m.find("fewer t_bins"), std::string::npos) << m;
  }
  EXPECT_EQ(calls, 0);  // refused before the first node's values were asked for
  set_memory_budget(HalfVectorTable::bytes(o) + 1);
  EXPECT_NO_THROW(HalfVectorTable(lambert, o));
  EXPECT_GT(calls, 0);
}

}  // namespace ICOBRDF_UNITY_ID
}  // namespace icobrdf
