#include "core/streaming_projection.hpp"

#include <algorithm>
#include <string>

#include "core/error.hpp"

namespace icobrdf {
namespace {

// Incident cells per block: each thread holds block x cells doubles per channel (2.6 MB at level 5).
constexpr int kBlockRows = 32;

}  // namespace

std::vector<Eigen::MatrixXd> streaming_projection(const BrdfModel& model, const Grid& g, const ProjectionOperator& proj,
                                                  bool cosine, LutSampling sampling, const Grid* sampling_grid) {
  const Grid& sg = sampling_grid ? *sampling_grid : g;
  if (sg.cells() != g.cells() || (sg.solid_angles - g.solid_angles).cwiseAbs().maxCoeff() > 1e-12 * g.solid_angles.maxCoeff())
    throw ArgumentError("projection: the sampling grid's cells differ from the projection grid's (" + std::to_string(sg.cells()) +
                        " vs " + std::to_string(g.cells()) + " cells)");
  const auto deltas = model.delta_parts();
  if (!deltas.empty() && !cosine)
    throw ArgumentError("projection of '" + model.spec() + "': a delta BRDF has no finite f; use the cosine-weighted form g");
  if (proj.P.rows() != g.cells())
    throw ArgumentError("projection: operator has " + std::to_string(proj.P.rows()) + " rows, grid has " + std::to_string(g.cells()) + " cells");
  const int cells = g.cells(), ch = model.channels();
  const auto modes = proj.P.cols();
  const int blocks = (cells + kBlockRows - 1) / kBlockRows;
  // T = F P accumulated row block by row block; C = P^T T. Each block writes its own rows of T, so the
  // result does not depend on the number of threads.
  std::vector<Eigen::MatrixXd> t(static_cast<size_t>(ch), Eigen::MatrixXd::Zero(cells, modes));
#pragma omp parallel
  {
    std::vector<Eigen::MatrixXd> rows;
#pragma omp for schedule(dynamic)
    for (int b = 0; b < blocks; ++b) {
      const int r0 = b * kBlockRows, r1 = std::min(cells, r0 + kBlockRows);
      sample_lut_rows(model, sg, cosine, sampling, r0, r1, rows);
      for (int c = 0; c < ch; ++c) t[c].middleRows(r0, r1 - r0).noalias() = rows[c] * proj.P;
    }
  }
  std::vector<Eigen::MatrixXd> out;
  for (int c = 0; c < ch; ++c) {
    out.push_back(proj.P.transpose() * t[c]);
    for (const auto& d : deltas) out.back() += delta_projection(d, g, proj);
  }
  return out;
}

Eigen::MatrixXd delta_projection(const DeltaPart& part, const Grid& g, const ProjectionOperator& proj) {
  const bool mirror = part.kind == DeltaPart::Kind::Mirror;
  if (mirror && g.rotate_pi.size() != g.cells())
    throw ArgumentError("mirror projection: grid of kind '" + g.kind + "' has no rotation-by-pi cell map");
  // Row i of F has weight / Omega_r at r = image(i), so (F P)_i = weight / Omega_r P_r.
  Eigen::MatrixXd t(g.cells(), proj.P.cols());
  for (int i = 0; i < g.cells(); ++i) {
    const int r = mirror ? g.rotate_pi[i] : i;
    t.row(i) = part.weight / g.solid_angles[r] * proj.P.row(r);
  }
  return proj.P.transpose() * t;
}

}  // namespace icobrdf
