#include "icobrdf/lab/grid_comparison.hpp"

#include <fmt/core.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "icobrdf/core/basis/hemisphere_basis.hpp"
#include "icobrdf/core/grid/reference_grids.hpp"
#include "icobrdf/lab/timing.hpp"
#include "icobrdf/mesh/tessellation.hpp"

namespace icobrdf::lab {

std::vector<double> gram_errors(const DiscreteBasis& b) {
  std::vector<double> e;
  for (int n = 0; n <= b.order; ++n) {
    const int m = hemisphere_basis_count(n);
    e.push_back((b.G.topLeftCorner(m, m) - Eigen::MatrixXd::Identity(m, m)).cwiseAbs().maxCoeff());
  }
  return e;
}

double condition_of_block(const DiscreteBasis& b, int n) {
  const int m = hemisphere_basis_count(n);
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(b.G.topLeftCorner(m, m), Eigen::EigenvaluesOnly);
  const double lo = eig.eigenvalues().minCoeff(), hi = eig.eigenvalues().maxCoeff();
  return lo > 0.0 ? hi / lo : std::numeric_limits<double>::infinity();
}

GridRun measure_grid(const std::string& kind, const std::string& size, int level, const std::function<Grid()>& build, int order,
                     const std::vector<int>& condition_orders) {
  GridRun r;
  r.kind = kind;
  r.size = size;
  r.level = level;
  Grid g;
  r.grid_seconds = seconds_of([&] { g = build(); });
  DiscreteBasis b;
  r.basis_seconds = seconds_of([&] { b = build_discrete_basis(g, order); });
  r.cells = g.cells();
  r.points = g.cubature_points.rows();
  r.gram = gram_errors(b);
  for (int n : condition_orders) r.condition[n] = condition_of_block(b, n);
  for (double tol : kBaselineTolerances) r.largest.push_back(largest_supported_order(b, tol));
  return r;
}

std::vector<GridRun> measure_matched_grids(const std::vector<int>& levels, int order, const std::vector<int>& condition_orders) {
  std::vector<GridRun> runs;
  for (int level : levels) {
    const std::string name = "level " + std::to_string(level);
    Grid ea;
    const double t_ea = seconds_of([&] { ea = build_equal_area_grid(level); });
    runs.push_back(measure_grid("equal-area", name, level, [&] { return ea; }, order, condition_orders));
    runs.back().grid_seconds = t_ea;
    runs.push_back(measure_grid("equal-area-centre", name, level, [&] { return with_centre_cubature(ea); }, order, condition_orders));
    runs.push_back(measure_grid("geodesic", name, level, [&] { return build_geodesic_grid(level); }, order, condition_orders));
    const int k = std::max(1, static_cast<int>(std::lround(std::sqrt(ea.cells() / 4.0))));
    const std::string matched = fmt::format("{} x {}", k, 4 * k);
    runs.push_back(measure_grid("lat-long", matched, level, [&] { return build_lat_long_grid(k, 4 * k, kLatLongPoints); }, order,
                                condition_orders));
    runs.push_back(measure_grid("polar-gauss", matched, level, [&] { return build_polar_gauss_grid(k, 4 * k); }, order, condition_orders));
    for (auto* r : {&runs[runs.size() - 2], &runs.back()}) {
      r->rings = k;
      r->azimuths = 4 * k;
    }
  }
  return runs;
}

PolarSearch polar_gauss_search(int n, double tol) {
  PolarSearch s;
  const int n_phi = 2 * n + 1;
  double previous = std::numeric_limits<double>::quiet_NaN();
  for (int rings = 1; rings <= n + 2; ++rings) {
    const auto b = build_discrete_basis(build_polar_gauss_grid(rings, n_phi), n);
    if (b.gram_error <= tol) {
      s.rings = rings;
      s.cells = rings * n_phi;
      s.gram = b.gram_error;
      s.gram_one_ring_less = previous;
      return s;
    }
    previous = b.gram_error;
  }
  return s;
}

CellsNeeded cells_needed(const std::vector<const GridRun*>& family, int n, double tol) {
  CellsNeeded c;
  for (size_t k = 0; k < family.size(); ++k) {
    const double e = family[k]->gram[static_cast<size_t>(n)];
    if (e > tol) continue;
    c.smallest_built = family[k]->cells;
    if (k > 0) {
      const double e0 = family[k - 1]->gram[static_cast<size_t>(n)];
      const double c0 = family[k - 1]->cells, c1 = family[k]->cells;
      if (e0 > tol && e > 0.0)
        c.interpolated = std::exp(std::log(c0) + (std::log(tol) - std::log(e0)) * (std::log(c1) - std::log(c0)) / (std::log(e) - std::log(e0)));
    }
    break;
  }
  return c;
}

}  // namespace icobrdf::lab
