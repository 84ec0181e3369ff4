#include "icobrdf/lab/direct_vs_matrix.hpp"

#include <Eigen/LU>

#include "icobrdf/core/projection/direct_projection.hpp"
#include "icobrdf/core/projection/discrete_basis.hpp"
#include "icobrdf/core/models/model_registry.hpp"
#include "icobrdf/core/projection/projection.hpp"
#include "icobrdf/core/projection/streaming_projection.hpp"
#include "icobrdf/lab/report_format.hpp"
#include "icobrdf/lab/timing.hpp"
#include "icobrdf/mesh/tessellation.hpp"

namespace icobrdf::lab {

nlohmann::json direct_vs_matrix(const DirectCase& dc, std::vector<std::string>& row) {
  const auto model = parse_model(kDirectModel);
  const Grid g = build_fitting_grid(dc.level, GridKind::EqualArea, true);  // one point per cell (centre sampling)
  // Matrix path as `icobrdf fit` runs it: B and P once, then C = P^T F P with F's rows streamed.
  DiscreteBasis basis;
  ProjectionOperator ls, plain;
  std::vector<Eigen::MatrixXd> c_ls, c_plain, d_pair, d_cached;
  const double t_operators = best_seconds(kDirectRepeats, [&] {
    basis = build_discrete_basis(g, dc.order);
    ls = make_projection(basis);
  });
  const double t_stream = best_seconds(kDirectRepeats, [&] { c_ls = streaming_projection(*model, g, ls, false); });
  plain = make_projection(basis, ProjectionOperator::Kind::Plain);
  c_plain = streaming_projection(*model, g, plain, false);
  const double t_pair = best_seconds(kDirectRepeats, [&] { d_pair = direct_projection(*model, g, dc.order, false, DirectModes::PerPair); });
  const double t_cached = best_seconds(kDirectRepeats, [&] { d_cached = direct_projection(*model, g, dc.order, false, DirectModes::Cached); });
  // Direct sums are the plain projection; the least-squares one is G^-1 D G^-1 (icobrdf/core/projection/direct_projection.hpp).
  const Eigen::MatrixXd gi = basis.G.inverse();
  const Eigen::MatrixXd d_ls = gi * d_pair[0] * gi;
  const double scale = c_plain[0].cwiseAbs().maxCoeff();
  const double agree_plain = (d_pair[0] - c_plain[0]).cwiseAbs().maxCoeff() / scale;
  const double agree_cached = (d_cached[0] - c_plain[0]).cwiseAbs().maxCoeff() / scale;
  const double agree_ls = (d_ls - c_ls[0]).cwiseAbs().maxCoeff() / c_ls[0].cwiseAbs().maxCoeff();
  const double t_matrix = t_operators + t_stream;
  const long long pairs = static_cast<long long>(g.cells()) * g.cells();
  row = {std::to_string(dc.level),     std::to_string(g.cells()),        std::to_string(dc.order),
         std::to_string(basis.modes()), fixed(t_matrix, 3),               fixed(t_pair, 3),
         fixed(t_cached, 3),            fixed(t_pair / t_matrix, 1) + "x", fixed(t_cached / t_matrix, 1) + "x",
         sci(agree_plain),              sci(agree_ls)};
  return {{"level", dc.level},
          {"cells", g.cells()},
          {"order", dc.order},
          {"modes", basis.modes()},
          {"pairs", pairs},
          {"model", kDirectModel},
          {"matrix_operator_seconds", t_operators},
          {"matrix_projection_seconds", t_stream},
          {"matrix_seconds", t_matrix},
          {"direct_per_pair_seconds", t_pair},
          {"direct_cached_seconds", t_cached},
          {"per_pair_over_matrix", t_pair / t_matrix},
          {"cached_over_matrix", t_cached / t_matrix},
          {"agreement_plain", agree_plain},
          {"agreement_cached_plain", agree_cached},
          {"agreement_least_squares", agree_ls},
          {"gram_error", basis.gram_error},
          {"condition", basis.condition}};
}

std::vector<std::string> direct_vs_matrix_header() {
  return {"level", "cells", "order", "modes", "matrix [s]", "direct per pair [s]", "direct cached [s]", "per pair / matrix",
          "cached / matrix", "max diff plain (rel)", "max diff least squares (rel)"};
}

}  // namespace icobrdf::lab
