#include "icobrdf/core/projection/lut.hpp"
#include "icobrdf/core/support/first_failure.hpp"
#include "icobrdf/core/support/huge_pages.hpp"
#include "icobrdf/core/support/progress.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "icobrdf/core/support/error.hpp"

namespace icobrdf {
namespace {

// Block of incident cells handled at once by one thread of build_lut (its rows are written together).
constexpr int kRowBlock = 16;
// Rows of sample_lut_block's centre sampling evaluated before they are written: 8 doubles, one 64-byte cache
// line of a column of the column-major block.
constexpr int kRowGroup = 8;

}  // namespace

std::optional<LutSampling> lut_sampling_named(const std::string& word) {
  if (word == "average") return LutSampling::CellAverage;
  if (word == "centre" || word == "center") return LutSampling::CellCentre;
  return std::nullopt;
}

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
  std::vector<int> rows(static_cast<size_t>(std::max(0, row_end - row_begin)));
  for (size_t i = 0; i < rows.size(); ++i) rows[i] = row_begin + static_cast<int>(i);
  sample_lut_rows(model, g, cosine, sampling, rows, out);
}

void sample_lut_rows(const BrdfModel& model, const Grid& g, bool cosine, LutSampling sampling, const std::vector<int>& row_cells,
                     std::vector<Eigen::MatrixXd>& out) {
  sample_lut_block(model, g, cosine, sampling, row_cells, g.cells(), out);
}

namespace {

// The rows of a LUT over its first col_end remitted cells, one incident cell at a time: what the sampling
// needs of the remitted side is prepared once (their directions, or the cubature points with their
// relative weights).
class RowSampler {
 public:
  RowSampler(const BrdfModel& model, const Grid& g, bool cosine, LutSampling sampling, const std::vector<int>& row_cells, int col_end)
      : model_(model), g_(g), cosine_(cosine), sampling_(sampling), col_end_(col_end) {
    const int cells = g.cells();
    for (int cell : row_cells)
      if (cell < 0 || cell >= cells)
        throw ArgumentError("LUT rows: cell " + std::to_string(cell) + " is outside [0, " + std::to_string(cells) + ")");
    if (col_end < 0 || col_end > cells)
      throw ArgumentError("LUT rows: column end " + std::to_string(col_end) + " is outside [0, " + std::to_string(cells) + "]");
    if (sampling == LutSampling::CellCentre) {
      // One incident direction at a time against every remitted cell's direction (copied only when some
      // columns are left out).
      if (col_end < cells) part_ = g.directions.topRows(col_end);
      wr_ = col_end < cells ? &part_ : &g.directions;
      return;
    }
    // Entry (i, r) = sum_p sum_q (w_p / Omega_i) (w_q / Omega_r) f(x_p, x_q) [cos theta_p]: for each incident
    // point p the model runs against every remitted point at once; the incident cell's points are summed
    // first (acc), then each remitted cell's points (contiguous in the cubature arrays).
    const Eigen::Index points = g.cubature_offsets[static_cast<size_t>(col_end)];
    rel_.resize(points);  // w_q / Omega_r of each point
    for (int r = 0; r < col_end; ++r)
      for (auto q = g.cubature_offsets[r]; q < g.cubature_offsets[r + 1]; ++q) rel_[q] = g.cubature_weights[q] / g.solid_angles[r];
    if (points < g.cubature_points.rows()) part_ = g.cubature_points.topRows(points);
    wr_ = points < g.cubature_points.rows() ? &part_ : &g.cubature_points;
    f_.resize(points, model.channels());
    acc_.resize(points, model.channels());
  }

  // The LUT row of incident cell `cell`: out is col_end x channels.
  void row(int cell, Eigen::Ref<Eigen::MatrixXd> out) {
    if (sampling_ == LutSampling::CellCentre) {
      model_.eval_row(g_.directions.row(cell).transpose(), *wr_, out);
      if (cosine_) out *= g_.directions(cell, 2);
      return;
    }
    acc_.setZero();
    for (auto p = g_.cubature_offsets[cell]; p < g_.cubature_offsets[cell + 1]; ++p) {
      const double wp = g_.cubature_weights[p] / g_.solid_angles[cell] * (cosine_ ? g_.cubature_points(p, 2) : 1.0);
      model_.eval_row(g_.cubature_points.row(p).transpose(), *wr_, f_);
      acc_.noalias() += wp * f_;
    }
    for (Eigen::Index c = 0; c < acc_.cols(); ++c) {
      weighted_ = rel_.cwiseProduct(acc_.col(c));
      for (int r = 0; r < col_end_; ++r) {
        const auto b = g_.cubature_offsets[r], e = g_.cubature_offsets[r + 1];
        out(r, c) = weighted_.segment(b, e - b).sum();
      }
    }
  }

 private:
  const BrdfModel& model_;
  const Grid& g_;
  bool cosine_;
  LutSampling sampling_;
  int col_end_;
  RowMatrix3d part_;            // the remitted directions or points, when only some columns are sampled
  const RowMatrix3d* wr_ = nullptr;
  Eigen::VectorXd rel_, weighted_;
  Eigen::MatrixXd f_, acc_;
};

}  // namespace

void sample_lut_block(const BrdfModel& model, const Grid& g, bool cosine, LutSampling sampling, const std::vector<int>& row_cells,
                      int col_end, std::vector<Eigen::MatrixXd>& out) {
  RowSampler sampler(model, g, cosine, sampling, row_cells, col_end);
  const int rows = static_cast<int>(row_cells.size()), ch = model.channels();
  // Every entry is written below: resize without clearing (buffers are reused across calls).
  out.resize(static_cast<size_t>(ch));
  for (auto& m : out) m.resize(rows, col_end);
  if (rows == 0 || col_end == 0) return;  // nothing to sample (and no block of an empty matrix to take)
  // Rows are evaluated kRowGroup at a time into columns of `group`, then written to `out` by columns: a
  // row of the column-major `out` is strided, and writing each row in turn touched every cache line of
  // `out` (2.6 MB for 32 rows at level 5) once per row (perf: 30% of streaming GGX at level 5, order 8).
  Eigen::MatrixXd f(col_end, ch);
  std::vector<Eigen::MatrixXd> group(static_cast<size_t>(ch), Eigen::MatrixXd(col_end, kRowGroup));
  for (int i0 = 0; i0 < rows; i0 += kRowGroup) {
    const int n = std::min(kRowGroup, rows - i0);
    for (int i = i0; i < i0 + n; ++i) {
      sampler.row(row_cells[static_cast<size_t>(i)], f);
      for (int c = 0; c < ch; ++c) group[c].col(i - i0) = f.col(c);
    }
    for (int c = 0; c < ch; ++c) out[c].middleRows(i0, n) = group[c].leftCols(n).transpose();
  }
}

void sample_lut_columns(const BrdfModel& model, const Grid& g, bool cosine, LutSampling sampling, const std::vector<int>& row_cells,
                        int col_end, std::vector<Eigen::MatrixXd>& out) {
  RowSampler sampler(model, g, cosine, sampling, row_cells, col_end);
  const int rows = static_cast<int>(row_cells.size()), ch = model.channels();
  out.resize(static_cast<size_t>(ch));
  for (auto& m : out) m.resize(col_end, rows);
  if (rows == 0 || col_end == 0) return;
  if (ch == 1) {  // straight into the column
    for (int i = 0; i < rows; ++i) sampler.row(row_cells[static_cast<size_t>(i)], out[0].col(i));
    return;
  }
  Eigen::MatrixXd f(col_end, ch);
  for (int i = 0; i < rows; ++i) {
    sampler.row(row_cells[static_cast<size_t>(i)], f);
    for (int c = 0; c < ch; ++c) out[c].col(i) = f.col(c);
  }
}

void add_delta_lut(const DeltaPart& part, const Grid& g, Eigen::MatrixXd& lut) {
  if (part.kind == DeltaPart::Kind::Mirror && g.rotate_pi.size() != g.cells())
    throw ArgumentError("mirror LUT: grid of kind '" + std::string(to_string(g.kind)) + "' has no rotation-by-pi cell map");
  for (int i = 0; i < g.cells(); ++i) {
    const int r = part.kind == DeltaPart::Kind::Mirror ? g.rotate_pi[i] : i;
    lut(i, r) += part.weight / g.solid_angles[r];
  }
}

Lut build_lut(const BrdfModel& model, const Grid& g, bool cosine, LutSampling sampling) {
  const auto deltas = model.delta_parts();
  if (!deltas.empty() && !cosine)
    throw ArgumentError("LUT of '" + quoted_text(model.spec()) + "': a delta BRDF has no finite f; use the cosine-weighted form g = f cos theta_i");
  const int cells = g.cells(), ch = model.channels();
  Lut lut;
  lut.cosine = cosine;
  lut.channels.resize(static_cast<size_t>(ch));  // each cells x cells matrix allocated once, no temporary
  for (auto& m : lut.channels) {
    m = huge_page_matrix(cells, cells);  // advised before the first write (icobrdf/core/support/huge_pages.hpp)
    m.setZero();
  }
  const int blocks = (cells + kRowBlock - 1) / kRowBlock;
  ProgressMeter progress("sampling the LUT", blocks);
  FirstFailure failure;  // a block's exception, rethrown after the region (icobrdf/core/support/first_failure.hpp)
#pragma omp parallel for schedule(dynamic)
  for (int b = 0; b < blocks; ++b) {
    if (failure.failed()) continue;
    try {
      const int r0 = b * kRowBlock, r1 = std::min(cells, r0 + kRowBlock);
      std::vector<Eigen::MatrixXd> part;
      sample_lut_rows(model, g, cosine, sampling, r0, r1, part);
      for (int c = 0; c < ch; ++c) lut.channels[c].middleRows(r0, r1 - r0) = part[c];
      progress.step();
    } catch (...) {
      failure.keep();
    }
  }
  failure.rethrow();
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
