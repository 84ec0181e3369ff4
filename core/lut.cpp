#include "core/lut.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.hpp"

namespace icobrdf {
namespace {

// Block of incident cells handled at once: big enough for vectorized model evaluation, small enough that
// the pair buffers (block points x all points x 3 doubles) stay in the tens of MB.
constexpr int kRowBlock = 16;

}  // namespace

Eigen::VectorXd cell_mean_cosines(const Grid& g) {
  Eigen::VectorXd d(g.cells());
  for (int c = 0; c < g.cells(); ++c) {
    double s = 0.0;
    for (auto q = g.cubature_offsets[c]; q < g.cubature_offsets[c + 1]; ++q) s += g.cubature_weights[q] * g.cubature_points(q, 2);
    d[c] = s / g.solid_angles[c];
  }
  return d;
}

void sample_lut_rows(const BrdfModel& model, const Grid& g, bool cosine, LutSampling sampling, int row_begin, int row_end,
                     std::vector<Eigen::MatrixXd>& out) {
  const int cells = g.cells(), rows = row_end - row_begin, ch = model.channels();
  out.assign(static_cast<size_t>(ch), Eigen::MatrixXd::Zero(rows, cells));
  if (sampling == LutSampling::CellCentre) {
    RowMatrix3d wi(static_cast<Eigen::Index>(rows) * cells, 3), wr(static_cast<Eigen::Index>(rows) * cells, 3);
    for (int i = 0; i < rows; ++i)
      for (int r = 0; r < cells; ++r) {
        wi.row(static_cast<Eigen::Index>(i) * cells + r) = g.directions.row(row_begin + i);
        wr.row(static_cast<Eigen::Index>(i) * cells + r) = g.directions.row(r);
      }
    Eigen::MatrixXd f(wi.rows(), ch);
    model.eval(wi, wr, f);
    for (int i = 0; i < rows; ++i)
      for (int c = 0; c < ch; ++c)
        out[c].row(i) = f.col(c).segment(static_cast<Eigen::Index>(i) * cells, cells).transpose() *
                        (cosine ? g.directions(row_begin + i, 2) : 1.0);
    return;
  }
  const Eigen::Index total_points = g.cubature_points.rows();
  // Weight of each remitted point relative to its cell: w_q / Omega_r, and the cell of each point.
  std::vector<int> cell_of(static_cast<size_t>(total_points));
  Eigen::VectorXd rel(total_points);
  for (int r = 0; r < cells; ++r)
    for (auto q = g.cubature_offsets[r]; q < g.cubature_offsets[r + 1]; ++q) {
      cell_of[static_cast<size_t>(q)] = r;
      rel[q] = g.cubature_weights[q] / g.solid_angles[r];
    }
  for (int i = 0; i < rows; ++i) {
    const int cell = row_begin + i;
    for (auto p = g.cubature_offsets[cell]; p < g.cubature_offsets[cell + 1]; ++p) {
      const double wp = g.cubature_weights[p] / g.solid_angles[cell] * (cosine ? g.cubature_points(p, 2) : 1.0);
      RowMatrix3d wi = g.cubature_points.row(p).replicate(total_points, 1);
      Eigen::MatrixXd f(total_points, ch);
      model.eval(wi, g.cubature_points, f);
      for (Eigen::Index q = 0; q < total_points; ++q)
        for (int c = 0; c < ch; ++c) out[c](i, cell_of[static_cast<size_t>(q)]) += wp * rel[q] * f(q, c);
    }
  }
}

void add_delta_lut(const DeltaPart& part, const Grid& g, Eigen::MatrixXd& lut) {
  if (part.kind == DeltaPart::Kind::Mirror && g.rotate_pi.size() != g.cells())
    throw ArgumentError("mirror LUT: grid of kind '" + g.kind + "' has no rotation-by-pi cell map");
  for (int i = 0; i < g.cells(); ++i) {
    const int r = part.kind == DeltaPart::Kind::Mirror ? g.rotate_pi[i] : i;
    lut(i, r) += part.weight / g.solid_angles[r];
  }
}

Lut build_lut(const BrdfModel& model, const Grid& g, bool cosine, LutSampling sampling) {
  const auto deltas = model.delta_parts();
  if (!deltas.empty() && !cosine)
    throw ArgumentError("LUT of '" + model.spec() + "': a delta BRDF has no finite f; use the cosine-weighted form g = f cos theta_i");
  const int cells = g.cells(), ch = model.channels();
  Lut lut;
  lut.cosine = cosine;
  lut.channels.assign(static_cast<size_t>(ch), Eigen::MatrixXd::Zero(cells, cells));
  const int blocks = (cells + kRowBlock - 1) / kRowBlock;
#pragma omp parallel for schedule(dynamic)
  for (int b = 0; b < blocks; ++b) {
    const int r0 = b * kRowBlock, r1 = std::min(cells, r0 + kRowBlock);
    std::vector<Eigen::MatrixXd> part;
    sample_lut_rows(model, g, cosine, sampling, r0, r1, part);
    for (int c = 0; c < ch; ++c) lut.channels[c].middleRows(r0, r1 - r0) = part[c];
  }
  for (const auto& d : deltas)
    for (auto& m : lut.channels) add_delta_lut(d, g, m);
  return lut;
}

double reciprocity_violation(const Eigen::MatrixXd& f, const Eigen::VectorXd& w) {
  const Eigen::MatrixXd ww = w * w.transpose();
  const double total = (ww.array() * f.array().square()).sum();
  if (total == 0.0) return 0.0;
  const double anti = (ww.array() * (0.5 * (f - f.transpose())).array().square()).sum();
  return std::sqrt(anti / total);
}

Eigen::MatrixXd symmetrize(const Eigen::MatrixXd& f) { return 0.5 * (f + f.transpose()); }

}  // namespace icobrdf
