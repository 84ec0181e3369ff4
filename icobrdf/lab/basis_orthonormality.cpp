#include "icobrdf/lab/basis_orthonormality.hpp"

#include <fmt/core.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>

#include "icobrdf/core/projection/discrete_basis.hpp"
#include "icobrdf/core/grid/gauss_legendre.hpp"
#include "icobrdf/core/basis/hemisphere_basis.hpp"
#include "icobrdf/core/grid/reference_grids.hpp"
#include "icobrdf/core/basis/zernike.hpp"
#include "icobrdf/lab/order_chart.hpp"
#include "icobrdf/lab/report_format.hpp"
#include "icobrdf/lab/timing.hpp"
#include "icobrdf/lab/zernike_reference.hpp"
#include "icobrdf/plot/line_chart.hpp"

namespace icobrdf::lab {
namespace {

constexpr double kDoubleEps = std::numeric_limits<double>::epsilon();  // 2^-52

}  // namespace

double ortho_bound(int order, int rings, int n_phi) {
  return 2.0 * std::sqrt(2.0) * kZernikeAbsError * std::sqrt(order + 1.0) + (rings + n_phi) * kDoubleEps;
}

OrthoResult orthonormality(int order, bool full) {
  OrthoResult r;
  r.order = order;
  r.rings = order / 2 + 2;
  r.n_phi = 2 * order + 2;
  r.modes = hemisphere_basis_count(order);
  r.bound = ortho_bound(order, r.rings, r.n_phi);
  r.seconds = seconds_of([&] {
    const auto gl = gauss_legendre(r.rings, 0.0, 1.0);
    const int m = r.modes, nrad = zernike_radial_count(order);
    std::vector<double> k(static_cast<size_t>(m));
    // Radial factors: rows = rings, columns = packed (n, |l|).
    Eigen::MatrixXd rad(r.rings, nrad);
    for (int q = 0; q < r.rings; ++q) {
      const double t = gl.nodes[q], z = 1.0 - t, s = std::sqrt(t * (2.0 - t));
      hemisphere_basis_eval(order, Eigen::Vector3d(s, 0.0, z), k.data());
      for (int j = 0; j < m; ++j) {
        const auto nl = ansi_to_nl(j);
        if (nl.l < 0) continue;
        rad(q, zernike_radial_index(nl.n, nl.l)) = k[static_cast<size_t>(j)] * (nl.l == 0 ? std::sqrt(2.0) : 1.0);
      }
    }
    const Eigen::MatrixXd rg = rad.transpose() * gl.weights.asDiagonal() * rad;
    // Azimuthal factors: rows = azimuth nodes, columns = l + order.
    Eigen::MatrixXd az(r.n_phi, 2 * order + 1);
    for (int p = 0; p < r.n_phi; ++p) {
      const double phi = 2.0 * M_PI * p / r.n_phi;
      hemisphere_basis_eval(order, Eigen::Vector3d(std::cos(phi), std::sin(phi), 0.0), k.data());
      for (int l = -order; l <= order; ++l)
        az(p, l + order) = k[static_cast<size_t>(ansi_index(std::abs(l), l))] / std::sqrt((std::abs(l) + 1.0) / M_PI);
    }
    const Eigen::MatrixXd ag = (2.0 * M_PI / r.n_phi) * (az.transpose() * az);
    std::vector<int> ri(static_cast<size_t>(m)), li(static_cast<size_t>(m));
    for (int j = 0; j < m; ++j) {
      const auto nl = ansi_to_nl(j);
      ri[static_cast<size_t>(j)] = zernike_radial_index(nl.n, std::abs(nl.l));
      li[static_cast<size_t>(j)] = nl.l + order;
    }
    double worst = 0.0;
#pragma omp parallel for reduction(max : worst) schedule(static)
    for (int a = 0; a < m; ++a)
      for (int b = 0; b < m; ++b) {
        const double g = rg(ri[static_cast<size_t>(a)], ri[static_cast<size_t>(b)]) * ag(li[static_cast<size_t>(a)], li[static_cast<size_t>(b)]);
        worst = std::max(worst, std::abs(g - (a == b ? 1.0 : 0.0)));
      }
    r.gram_error = worst;
  });
  if (full) {  // the same rule as a grid, B = K at the nodes, G = B^T W B: no factorization
    const auto b = build_discrete_basis(build_polar_gauss_grid(r.rings, r.n_phi), order);
    r.full_gram_error = b.gram_error;
  }
  return r;
}

void add_orthonormality(const SectionOptions& o, ReportSection& s, std::string& md) {
  const std::vector<int> orders = o.quick ? std::vector<int>{32, 64, 128} : std::vector<int>{32, 64, 96, 128};
  const int full_max = o.quick ? 32 : 64;
  std::vector<std::vector<std::string>> rows;
  nlohmann::json jo = nlohmann::json::array();
  for (int n : orders) {
    const auto r = orthonormality(n, n <= full_max);
    rows.push_back({std::to_string(n), std::to_string(r.modes), fmt::format("{} x {}", r.rings, r.n_phi), sci(r.gram_error),
                    std::isnan(r.full_gram_error) ? "-" : sci(r.full_gram_error), sci(r.bound), fixed(r.seconds, 3)});
    jo.push_back({{"order", n},
                  {"modes", r.modes},
                  {"rings", r.rings},
                  {"azimuths", r.n_phi},
                  {"gram_error", r.gram_error},
                  {"full_gram_error", num(r.full_gram_error)},
                  {"bound", r.bound},
                  {"seconds", r.seconds}});
  }
  s.data["orthonormality"] = jo;
  if (!o.report_dir.empty()) {
    plot::Series meas{"max|G - I| (factorized)", {}, {}}, bound{"expected bound", {}, {}};
    bound.dashed = true;
    for (const auto& r : jo) {
      meas.x.push_back(r["order"].get<double>());
      meas.y.push_back(r["gram_error"].get<double>());
      bound.x.push_back(r["order"].get<double>());
      bound.y.push_back(r["bound"].get<double>());
    }
    const plot::ChartOptions co = order_chart("Orthonormality of K by exact quadrature", "max|G - I|");
    const std::string file = "hard_cases_orthonormality.png";
    plot::draw_line_chart({meas, bound}, co, (o.report_dir / file).string());
    s.figures.push_back(file);
  }
  md += "### Continuous basis to order 128\n\n"
        "Gram matrix of K_n^l (all (N+1)(N+2)/2 functions) by the exact product rule N/2 + 2 Gauss-Legendre "
        "rings in rho^2 x 2N + 2 azimuths, factorized into radial and azimuthal sums of the library's K values; "
        "at moderate orders also unfactorized (B^T W B on the same nodes). Expected bound: the documented "
        "accuracy |dK| <= 1e-13 sqrt((n+1)/pi) gives |dG| <= 2 sqrt(2) 1e-13 sqrt(N+1) by Cauchy-Schwarz, plus "
        "(rings + azimuths) eps for the sums.\n\n";
  md += md_table({"order", "modes", "rule", "max|G - I| (factorized)", "max|G - I| (B^T W B)", "expected bound", "seconds"}, rows);
  for (const auto& f : s.figures) md += "![" + f + "](" + f + ")\n\n";
}

}  // namespace icobrdf::lab
