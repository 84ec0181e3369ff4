#include "icobrdf/core/projection/streaming_projection.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/basis/grid_symmetry.hpp"
#include "icobrdf/core/support/in_order_sums.hpp"
#include "icobrdf/core/support/progress.hpp"
#include "icobrdf/core/projection/projection_tile.hpp"

namespace icobrdf {
namespace {

// The incident cells sampled, ascending, with their weights: one per D2 orbit weighted 1 / |stabilizer|
// (icobrdf/core/basis/grid_symmetry.hpp) when `use_symmetry`, else every cell with weight 1.
std::pair<std::vector<int>, std::vector<double>> incident_rows(const Grid& g, bool use_symmetry) {
  std::vector<int> cells;
  std::vector<double> weight;
  if (use_symmetry) {
    for (const auto& r : d2_representatives(g)) {
      cells.push_back(r.cell);
      weight.push_back(r.weight);
    }
  } else {
    for (int c = 0; c < g.cells(); ++c) {
      cells.push_back(c);
      weight.push_back(1.0);
    }
  }
  return {cells, weight};
}

// The number of the `blocks` that `share` projects: b = every (part + k parts) below blocks, k = 0, 1, ...
int blocks_of_share(int blocks, const StreamingShare& share) {
  const int kept = (blocks + share.every - 1) / share.every;
  return share.part < kept ? (kept - share.part + share.parts - 1) / share.parts : 0;
}

// The block number of the share's k-th block.
int block_of_share(int k, const StreamingShare& share) { return share.every * (share.part + k * share.parts); }

// Helmholtz reciprocity: f(wi, wr) = f(wr, wi) makes the f LUT symmetric (F_ir = F_ri, for centre and
// cell-averaged sampling alike), so only one triangle of F needs sampling. With g = D F in g form
// (D = diag cos theta of the cell directions, centre sampling only: a cell-averaged g is not D F), and
// Q = D P (Q = P in f form), C = Q^T F P splits over pairs of orbits I, J (single cells without the D2
// path) into T(I, J) = sum_{a in I, b in J} Q_a F_ab P_b^T, and symmetry of F gives T(J, I) = U(I, J)^T
// with U(I, J) = sum_{a in I, b in J} P_a F_ab Q_b^T. Ordering orbits by their representative (smallest
// cell index):
//   C = sum_{J <= I}' T(I, J) + (sum_{J <= I}' U(I, J))^T,   ' = the diagonal I = J weighted 1/2,
// and each T or U is the D2 average of its representative row's sum (as in the plain symmetric path).
// Columns are reordered by orbit, so that representative i needs a prefix of them: the cells of orbits
// before its own (weight 1) and its own orbit (weight 1/2). That is an eighth of F with D2, half without.
std::vector<Eigen::MatrixXd> reciprocal_projection(const BrdfModel& model, const Grid& sg, const ProjectionOperator& proj,
                                                   bool cosine, LutSampling sampling, bool use_symmetry, const StreamingShare& share) {
  const int cells = sg.cells(), ch = model.channels();
  const auto modes = proj.P.cols();
  std::vector<int> rep(static_cast<size_t>(cells));
  for (int c = 0; c < cells; ++c) rep[static_cast<size_t>(c)] = c;
  if (use_symmetry)
    for (const auto& s : d2_maps(sg))
      for (int c = 0; c < cells; ++c) rep[static_cast<size_t>(c)] = std::min(rep[static_cast<size_t>(c)], (*s.cells)[c]);
  const auto incident = incident_rows(sg, use_symmetry);
  const std::vector<int>& row_cells = incident.first;
  const std::vector<double>& row_weight = incident.second;
  // Columns in the order (representative, cell): orbit I occupies [start(I), end(I)).
  std::vector<int> perm(static_cast<size_t>(cells)), pos(static_cast<size_t>(cells)), orbit_end(static_cast<size_t>(cells), 0);
  for (int c = 0; c < cells; ++c) perm[static_cast<size_t>(c)] = c;
  std::stable_sort(perm.begin(), perm.end(), [&](int a, int b) { return rep[static_cast<size_t>(a)] < rep[static_cast<size_t>(b)]; });
  for (int k = 0; k < cells; ++k) pos[static_cast<size_t>(perm[static_cast<size_t>(k)])] = k;
  for (int k = 0; k < cells; ++k) orbit_end[static_cast<size_t>(rep[static_cast<size_t>(perm[static_cast<size_t>(k)])])] = k + 1;
  const bool identity = !use_symmetry;  // without D2 every orbit is one cell and the order is unchanged
  const Grid reordered = identity ? Grid() : cells_in_order(sg, perm);
  const Grid& rg = identity ? sg : reordered;
  // P and Q = D P with rows in the column order, side by side: F_block [P Q] in one product.
  const Eigen::Index width = cosine ? 2 * modes : modes;
  Eigen::MatrixXd pq(cells, width);
  for (int k = 0; k < cells; ++k) {
    const int c = perm[static_cast<size_t>(k)];
    pq.row(k).head(modes) = proj.P.row(c);
    if (cosine) pq.row(k).tail(modes) = sg.directions(c, 2) * proj.P.row(c);
  }
  // [P Q] packed once for the projection tile (icobrdf/core/projection/projection_tile.hpp), which forms each block's
  // (F [P Q])^T from the block's rows, sampled contiguous (sample_lut_columns).
  const PackedProjection packed = pack_projection(pq);
  const auto lanes = static_cast<int>(packed.lanes);  // each block's columns are sampled to a multiple of these
  const int rows_total = static_cast<int>(row_cells.size());
  const int blocks = (rows_total + kStreamingBlockRows - 1) / kStreamingBlockRows;
  // Per block and channel: X1 = sum w_i Q_i (F P)_i and X2 = sum w_i P_i (F Q)_i over the block's rows,
  // added to the sums in block order (icobrdf/core/support/in_order_sums.hpp), so the result does not depend on the
  // number of threads.
  const int parts = cosine ? 2 : 1;
  std::vector<Eigen::MatrixXd> sums(static_cast<size_t>(ch * parts), Eigen::MatrixXd::Zero(modes, modes));
  const int mine = blocks_of_share(blocks, share);
  // The progress counts sampled entries: a block samples the prefix of columns its last row needs, so later
  // blocks cost more, and counting blocks made the time left grow as the work went on.
  std::vector<double> block_work(static_cast<size_t>(mine));
  for (int k_block = 0; k_block < mine; ++k_block) {
    const int b = block_of_share(k_block, share);
    const int r0 = b * kStreamingBlockRows, r1 = std::min(rows_total, r0 + kStreamingBlockRows);
    int col_end = 0;
    for (int k = r0; k < r1; ++k) col_end = std::max(col_end, orbit_end[static_cast<size_t>(row_cells[static_cast<size_t>(k)])]);
    block_work[static_cast<size_t>(k_block)] = static_cast<double>(r1 - r0) * col_end;
  }
  ProgressMeter progress("projecting", std::move(block_work));
  InOrderSums in_order(sums, kStreamingBlocksAhead, &progress);
#pragma omp parallel
  {
    std::vector<Eigen::MatrixXd> f;
    std::vector<int> block;
    Eigen::MatrixXd t, left;
    std::vector<Eigen::MatrixXd> out;
    std::vector<double> scratch;
#pragma omp for schedule(dynamic)
    for (int k_block = 0; k_block < mine; ++k_block) {
      in_order.run(k_block, [&] {  // a failure is kept and rethrown below (icobrdf/core/support/in_order_sums.hpp)
        const int b = block_of_share(k_block, share);
        const int r0 = b * kStreamingBlockRows, r1 = std::min(rows_total, r0 + kStreamingBlockRows);
        block.clear();
        for (int k = r0; k < r1; ++k) block.push_back(pos[static_cast<size_t>(row_cells[static_cast<size_t>(k)])]);
        int col_end = 0;  // the longest prefix any row of the block needs, to a whole number of the tile's vectors
        for (int k = r0; k < r1; ++k) col_end = std::max(col_end, orbit_end[static_cast<size_t>(row_cells[static_cast<size_t>(k)])]);
        col_end = std::min(cells, (col_end + lanes - 1) / lanes * lanes);
        sample_lut_columns(model, rg, false, sampling, block, col_end, f);  // f[c]: col_end x rows
        left.resize(r1 - r0, width);  // row k: w_k [Q_k  P_k] (the left factors of X1 and X2)
        for (int k = r0; k < r1; ++k) {
          const int i = row_cells[static_cast<size_t>(k)];
          const int first = pos[static_cast<size_t>(i)], last = orbit_end[static_cast<size_t>(i)];
          const double w = row_weight[static_cast<size_t>(k)];
          const int pk = first;
          if (cosine) {
            left.row(k - r0).head(modes) = w * pq.row(pk).tail(modes);
            left.row(k - r0).tail(modes) = w * pq.row(pk).head(modes);
          } else {
            left.row(k - r0) = w * pq.row(pk);
          }
          for (auto& m : f) {
            m.col(k - r0).segment(first, last - first) *= 0.5;
            m.col(k - r0).tail(col_end - last).setZero();
          }
        }
        out.clear();
        for (int c = 0; c < ch; ++c) {
          const Eigen::MatrixXd& fc = f[static_cast<size_t>(c)];
          projection_tile(packed, pq, fc.data(), fc.rows(), fc.cols(), t, scratch, 0, col_end);  // t = (F [P Q])^T: width x rows
          if (cosine) {
            out.push_back(left.leftCols(modes).transpose() * t.topRows(modes).transpose());       // X1 part
            out.push_back(left.rightCols(modes).transpose() * t.bottomRows(modes).transpose());   // X2 part
          } else {
            out.push_back(left.transpose() * t.transpose());
          }
        }
        return std::move(out);
      });
      out.clear();
    }
  }
  in_order.rethrow();
  std::vector<Eigen::MatrixXd> out;
  for (int c = 0; c < ch; ++c) {
    Eigen::MatrixXd& x1 = sums[static_cast<size_t>(c * parts)];
    Eigen::MatrixXd x2;
    if (cosine) x2 = std::move(sums[static_cast<size_t>(c * parts + 1)]);
    if (use_symmetry) {
      x1 = d2_average(x1);
      if (cosine) x2 = d2_average(x2);
    }
    if (cosine) out.push_back(x1 + x2.transpose());
    else out.push_back(x1 + x1.transpose());
  }
  if (share.reduce) share.reduce(out);
  return out;
}

}  // namespace


std::vector<Eigen::MatrixXd> streaming_projection(const BrdfModel& model, const Grid& g, const ProjectionOperator& proj,
                                                  bool cosine, LutSampling sampling, const Grid* sampling_grid,
                                                  const StreamingShare* given_share) {
  const StreamingShare whole;
  const StreamingShare& share = given_share ? *given_share : whole;
  if (share.parts < 1 || share.part < 0 || share.part >= share.parts || share.every < 1 || (share.parts > 1 && !share.reduce))
    throw ArgumentError("projection: share " + std::to_string(share.part) + " of " + std::to_string(share.parts) +
                        (share.parts > 1 && !share.reduce ? " has no reduction" : " is out of range") +
                        " (every " + std::to_string(share.every) + "), expected 0 <= part < parts, every >= 1 and a reduction when parts > 1");
  const Grid& sg = sampling_grid ? *sampling_grid : g;
  const StreamingShortcuts shortcuts = streaming_shortcuts(model, g, sg, cosine, sampling);
  const auto deltas = model.delta_parts();
  if (proj.P.rows() != g.cells())
    throw ArgumentError("projection: operator has " + std::to_string(proj.P.rows()) + " rows, grid has " + std::to_string(g.cells()) + " cells");
  const int ch = model.channels();
  const auto modes = proj.P.cols();
  const bool use_symmetry = shortcuts.d2 && rows_are_d2_equivariant(g, proj.P, kStreamingSymmetryTol);
  if (shortcuts.reciprocal) {
    auto out = reciprocal_projection(model, sg, proj, cosine, sampling, use_symmetry, share);
    for (auto& x : out)
      for (const auto& d : deltas) x += delta_projection(d, g, proj);
    return out;
  }
  const auto incident = incident_rows(g, use_symmetry);
  const std::vector<int>& row_cells = incident.first;
  const std::vector<double>& row_weight = incident.second;
  const int rows_total = static_cast<int>(row_cells.size());
  const int blocks = (rows_total + kStreamingBlockRows - 1) / kStreamingBlockRows;
  // Per block: X_b = P_rows^T diag(weight) (F_rows P), added in block order (InOrderSums), so the result
  // does not depend on the number of threads. F_rows P by the projection tile (icobrdf/core/projection/projection_tile.hpp,
  // P packed once), from the block's rows sampled contiguous (sample_lut_columns).
  std::vector<Eigen::MatrixXd> sums(static_cast<size_t>(ch), Eigen::MatrixXd::Zero(modes, modes));
  const PackedProjection packed = pack_projection(proj.P);
  const int cells = g.cells();
  const int mine = blocks_of_share(blocks, share);
  ProgressMeter progress("projecting", mine);
  InOrderSums in_order(sums, kStreamingBlocksAhead, &progress);
#pragma omp parallel
  {
    std::vector<Eigen::MatrixXd> f, out;
    std::vector<double> scratch;
    Eigen::MatrixXd t, pr;
#pragma omp for schedule(dynamic)
    for (int k_block = 0; k_block < mine; ++k_block) {
      in_order.run(k_block, [&] {  // a failure is kept and rethrown below (icobrdf/core/support/in_order_sums.hpp)
        const int b = block_of_share(k_block, share);
        const int r0 = b * kStreamingBlockRows, r1 = std::min(rows_total, r0 + kStreamingBlockRows);
        const std::vector<int> block(row_cells.begin() + r0, row_cells.begin() + r1);
        sample_lut_columns(model, sg, cosine, sampling, block, cells, f);  // f[c]: cells x rows
        pr.resize(r1 - r0, modes);
        for (int k = r0; k < r1; ++k) pr.row(k - r0) = row_weight[static_cast<size_t>(k)] * proj.P.row(row_cells[static_cast<size_t>(k)]);
        out.clear();
        for (int c = 0; c < ch; ++c) {
          const Eigen::MatrixXd& fc = f[static_cast<size_t>(c)];
          projection_tile(packed, proj.P, fc.data(), fc.rows(), fc.cols(), t, scratch, 0, cells);  // t = (F_rows P)^T: modes x rows
          out.push_back(pr.transpose() * t.transpose());
        }
        return std::move(out);
      });
      out.clear();
    }
  }
  in_order.rethrow();
  std::vector<Eigen::MatrixXd> out;
  for (int c = 0; c < ch; ++c) {
    Eigen::MatrixXd x = std::move(sums[static_cast<size_t>(c)]);
    if (use_symmetry) x = d2_average(x);
    out.push_back(std::move(x));
  }
  if (share.reduce) share.reduce(out);
  for (auto& x : out)
    for (const auto& d : deltas) x += delta_projection(d, g, proj);
  return out;
}

Eigen::MatrixXd delta_projection(const DeltaPart& part, const Grid& g, const ProjectionOperator& proj) {
  const bool mirror = part.kind == DeltaPart::Kind::Mirror;
  if (mirror && g.rotate_pi.size() != g.cells())
    throw ArgumentError("mirror projection: grid of kind '" + std::string(to_string(g.kind)) + "' has no rotation-by-pi cell map");
  // Row i of F has weight / Omega_r at r = image(i), so (F P)_i = weight / Omega_r P_r.
  Eigen::MatrixXd t(g.cells(), proj.P.cols());
  for (int i = 0; i < g.cells(); ++i) {
    const int r = mirror ? g.rotate_pi[i] : i;
    t.row(i) = part.weight / g.solid_angles[r] * proj.P.row(r);
  }
  return proj.P.transpose() * t;
}

}  // namespace icobrdf
