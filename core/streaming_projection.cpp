#include "core/streaming_projection.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.hpp"
#include "core/grid_symmetry.hpp"

namespace icobrdf {
namespace {

// Incident cells per block: each thread holds block x cells doubles per channel (2.6 MB at level 5).
constexpr int kBlockRows = 32;
// Tolerances of the symmetry check (cubature points and weights mapped by the grid's symmetries; P
// equivariant): a grid built symmetric matches to rounding, 1e-12 leaves room for a few ulps of the
// mesh construction and of G^-1 while rejecting any grid that is symmetric only up to discretization.
constexpr double kSymmetryTol = 1e-12;

// True when every cell's sampling points (cubature, or the directions for centre sampling) and weights are
// mapped by each symmetry onto those of the image cell.
bool sampling_is_symmetric(const Grid& sg, LutSampling sampling) {
  for (const auto& s : d2_maps(sg)) {
    for (int c = 0; c < sg.cells(); ++c) {
      const int m = (*s.cells)[c];
      if (m < 0 || m >= sg.cells()) return false;
      if (sampling == LutSampling::CellCentre) {
        if (std::abs(s.sx * sg.directions(c, 0) - sg.directions(m, 0)) > kSymmetryTol ||
            std::abs(s.sy * sg.directions(c, 1) - sg.directions(m, 1)) > kSymmetryTol ||
            std::abs(sg.directions(c, 2) - sg.directions(m, 2)) > kSymmetryTol)
          return false;
        continue;
      }
      const auto b = sg.cubature_offsets[c], e = sg.cubature_offsets[c + 1];
      const auto mb = sg.cubature_offsets[m], me = sg.cubature_offsets[m + 1];
      if (e - b != me - mb) return false;
      for (auto p = b; p < e; ++p) {
        bool found = false;
        for (auto q = mb; q < me && !found; ++q)
          found = std::abs(s.sx * sg.cubature_points(p, 0) - sg.cubature_points(q, 0)) <= kSymmetryTol &&
                  std::abs(s.sy * sg.cubature_points(p, 1) - sg.cubature_points(q, 1)) <= kSymmetryTol &&
                  std::abs(sg.cubature_points(p, 2) - sg.cubature_points(q, 2)) <= kSymmetryTol &&
                  std::abs(sg.cubature_weights[p] - sg.cubature_weights[q]) <= kSymmetryTol * sg.cubature_weights[p];
        if (!found) return false;
      }
    }
  }
  return true;
}

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
  // An isotropic model on a D2-symmetric grid has F(s i, s r) = F(i, r) for each symmetry s, so row s i of
  // F P is row i times the signs of the modes: only one incident cell per orbit is sampled (a quarter of
  // the rows), and C = sum_s D_s X D_s with X = sum over representatives i of P_i^T (F P)_i / |stabilizer
  // of i|, D_s the diagonal of mode signs. The sum over the four symmetries keeps 4 X_ab where modes a and b
  // have the same signs under all of them and zeroes the rest (entries that vanish exactly by symmetry).
  // (core/grid_symmetry.hpp)
  const bool use_symmetry = model.is_isotropic() && has_d2_maps(g) && has_d2_maps(sg) && g.rotate_pi == sg.rotate_pi &&
                            g.mirror_xz == sg.mirror_xz && g.mirror_yz == sg.mirror_yz && sampling_is_symmetric(sg, sampling) &&
                            rows_are_d2_equivariant(g, proj.P, kSymmetryTol);
  std::vector<int> row_cells;
  std::vector<double> row_weight;
  if (use_symmetry) {
    for (const auto& r : d2_representatives(g)) {
      row_cells.push_back(r.cell);
      row_weight.push_back(r.weight);
    }
  } else {
    for (int c = 0; c < cells; ++c) {
      row_cells.push_back(c);
      row_weight.push_back(1.0);
    }
  }
  const int rows_total = static_cast<int>(row_cells.size());
  const int blocks = (rows_total + kBlockRows - 1) / kBlockRows;
  // Per block: X_b = P_rows^T diag(weight) (F_rows P). Blocks are summed in block order, so the result does
  // not depend on the number of threads.
  std::vector<std::vector<Eigen::MatrixXd>> partial(static_cast<size_t>(blocks));
#pragma omp parallel
  {
    std::vector<Eigen::MatrixXd> rows;
    Eigen::MatrixXd t, pr;
#pragma omp for schedule(dynamic)
    for (int b = 0; b < blocks; ++b) {
      const int r0 = b * kBlockRows, r1 = std::min(rows_total, r0 + kBlockRows);
      const std::vector<int> block(row_cells.begin() + r0, row_cells.begin() + r1);
      sample_lut_rows(model, sg, cosine, sampling, block, rows);
      pr.resize(r1 - r0, modes);
      for (int k = r0; k < r1; ++k) pr.row(k - r0) = row_weight[static_cast<size_t>(k)] * proj.P.row(row_cells[static_cast<size_t>(k)]);
      auto& out = partial[static_cast<size_t>(b)];
      for (int c = 0; c < ch; ++c) {
        t.noalias() = rows[c] * proj.P;
        out.push_back(pr.transpose() * t);
      }
    }
  }
  std::vector<Eigen::MatrixXd> out;
  for (int c = 0; c < ch; ++c) {
    Eigen::MatrixXd x = Eigen::MatrixXd::Zero(modes, modes);
    for (const auto& p : partial) x += p[static_cast<size_t>(c)];
    if (use_symmetry) x = d2_average(x);
    out.push_back(std::move(x));
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
