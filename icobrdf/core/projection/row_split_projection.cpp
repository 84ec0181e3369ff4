#include "icobrdf/core/projection/row_split_projection.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/basis/grid_symmetry.hpp"
#include "icobrdf/core/basis/hemisphere_basis.hpp"
#include "icobrdf/core/support/in_order_sums.hpp"
#include "icobrdf/core/support/progress.hpp"
#include "icobrdf/core/projection/streaming_shortcuts.hpp"

namespace icobrdf {
namespace {

// Whether the rows `m` of block b (in block order) satisfy m(image(c)) = sign m(c) for every map.
bool block_rows_equivariant(const Grid& g, const CellBlocks& cb, int b, const Eigen::MatrixXd& m, double tol) {
  if (!has_d2_maps(g) || m.size() == 0) return false;
  const auto maps = d2_maps(g);
  const int first = cb.start[static_cast<size_t>(b)], n = cb.size(b);
  std::vector<int> local(static_cast<size_t>(g.cells()), -1);
  for (int k = 0; k < n; ++k) local[static_cast<size_t>(cb.order[static_cast<size_t>(first + k)])] = k;
  const double bound = tol * m.cwiseAbs().maxCoeff();
  const Eigen::Index modes = m.cols();
  for (const auto& s : maps) {
    Eigen::VectorXd sign(modes);
    for (Eigen::Index j = 0; j < modes; ++j) sign[j] = s.sign(ansi_to_nl(static_cast<int>(j)).l);
    for (int k = 0; k < n; ++k) {
      const int t = local[static_cast<size_t>((*s.cells)[cb.order[static_cast<size_t>(first + k)]])];
      if (t < 0) return false;  // an orbit split between blocks cannot happen (cell_blocks); refuse the shortcut
      if ((m.row(t).transpose() - sign.cwiseProduct(m.row(k).transpose())).cwiseAbs().maxCoeff() > bound) return false;
    }
  }
  return true;
}

// One incident row of a pair: its cell's index in the pair's grid, its weight, its row of P, which of the
// pair's columns it takes (the first `col_end`) and which it halves ([half_begin, half_end)).
struct PairRow {
  int local;
  double weight;
  const double* p;  // modes doubles, column stride p_stride
  Eigen::Index p_stride;
  int col_end, half_begin, half_end;
};

// The sums of one part's pairs.
class PartProjector {
 public:
  PartProjector(const BrdfModel& model, const Grid& g, const Grid& sg, const CellBlocks& cb, int part, bool cosine, LutSampling sampling,
                bool use_symmetry, bool reciprocal, Eigen::Index modes, int every = 1)
      : model_(model), g_(g), sg_(sg), cb_(cb), part_(part), cosine_(cosine), sampling_(sampling), symmetric_(use_symmetry),
        reciprocal_(reciprocal), modes_(modes), every_(every), deltas_(model.delta_parts()) {
    const int ch = model.channels();
    const int sums = reciprocal && cosine ? 2 : 1;
    x_.assign(static_cast<size_t>(ch * sums), Eigen::MatrixXd::Zero(modes, modes));
    delta_ = Eigen::MatrixXd::Zero(modes, modes);
    for (const auto& d : deltas_)
      if (d.kind == DeltaPart::Kind::Mirror && g.rotate_pi.size() != g.cells())
        throw ArgumentError("mirror projection: grid of kind '" + std::string(to_string(g.kind)) + "' has no rotation-by-pi cell map");
  }

  // The pair of this part's block and block `v` (this part's own block when v == part): p_own and p_v are
  // their rows of P in block order.
  // `half` (a reciprocal pair half way round the ring, which both of its parts hold at once): 0 the whole
  // pair, 1 the first half of its incident rows (with the pair's delta terms), 2 the second half.
  void step(int v, const Eigen::MatrixXd& p_own, const Eigen::MatrixXd& p_v, int half = 0) {
    if (v == part_) {
      diagonal(p_own);
      add_deltas(part_, p_own, part_, p_own);
    } else if (reciprocal_) {
      const bool own_high = part_ > v;
      pair(own_high ? part_ : v, own_high ? p_own : p_v, own_high ? v : part_, own_high ? p_v : p_own, half);
      if (half != 2) {
        add_deltas(part_, p_own, v, p_v);
        add_deltas(v, p_v, part_, p_own);
      }
    } else {
      pair(part_, p_own, v, p_v);
      add_deltas(part_, p_own, v, p_v);
    }
  }

  std::vector<Eigen::MatrixXd> finish() {
    std::vector<Eigen::MatrixXd> out;
    const int ch = model_.channels();
    for (int c = 0; c < ch; ++c) {
      if (!reciprocal_) {
        Eigen::MatrixXd x = std::move(x_[static_cast<size_t>(c)]);
        out.push_back(symmetric_ ? d2_average(x) : x);
      } else if (cosine_) {
        Eigen::MatrixXd x1 = std::move(x_[static_cast<size_t>(2 * c)]), x2 = std::move(x_[static_cast<size_t>(2 * c + 1)]);
        if (symmetric_) {
          x1 = d2_average(x1);
          x2 = d2_average(x2);
        }
        out.push_back(x1 + x2.transpose());
      } else {
        Eigen::MatrixXd x1 = std::move(x_[static_cast<size_t>(c)]);
        if (symmetric_) x1 = d2_average(x1);
        out.push_back(x1 + x1.transpose());
      }
      out.back() += delta_;
    }
    return out;
  }

 private:
  // The incident rows of block b: one per orbit with D2 (weighted 1 / |stabilizer|), else every cell.
  std::vector<int> incident_positions(int b) const {
    std::vector<int> pos;
    for (int p = cb_.start[static_cast<size_t>(b)]; p < cb_.start[static_cast<size_t>(b) + 1]; ++p)
      if (!symmetric_ || cb_.weight[static_cast<size_t>(p)] > 0.0) pos.push_back(p);
    return pos;
  }
  double row_weight(int p) const { return symmetric_ ? cb_.weight[static_cast<size_t>(p)] : 1.0; }

  // The triangle of block a in the reciprocal case (each row against the columns of its orbit and the
  // orbits before it, its own orbit halved), or all of block a against itself otherwise.
  void diagonal(const Eigen::MatrixXd& pa) {
    if (!reciprocal_) return pair(part_, pa, part_, pa);  // every incident row against every column of the block
    const int first = cb_.start[static_cast<size_t>(part_)], n = cb_.size(part_);
    const Grid lg = cells_in_order(sg_, cb_.cells(part_));
    std::vector<PairRow> rows;
    for (const int p : incident_positions(part_)) {
      const int ob = symmetric_ ? cb_.orbit_begin[static_cast<size_t>(p)] : p, oe = symmetric_ ? cb_.orbit_end[static_cast<size_t>(p)] : p + 1;
      rows.push_back({p - first, row_weight(p), pa.data() + (p - first), pa.rows(), oe - first, ob - first, oe - first});
    }
    run(lg, rows, pa, n);
  }

  // Block r's incident rows (all, or the first or second half: `half` 1 or 2) against every column of block c.
  void pair(int r, const Eigen::MatrixXd& pr, int c, const Eigen::MatrixXd& pc, int half = 0) {
    std::vector<int> cells = cb_.cells(c);
    const int n = cb_.size(c), first = cb_.start[static_cast<size_t>(r)];
    auto incident = incident_positions(r);
    if (half != 0) {
      const auto mid = incident.begin() + static_cast<std::ptrdiff_t>(incident.size() / 2);
      incident = half == 1 ? std::vector<int>(incident.begin(), mid) : std::vector<int>(mid, incident.end());
    }
    for (const int p : incident) cells.push_back(cb_.order[static_cast<size_t>(p)]);
    const Grid lg = cells_in_order(sg_, cells);
    std::vector<PairRow> rows;
    int k = n;
    for (const int p : incident) rows.push_back({k++, row_weight(p), pr.data() + (p - first), pr.rows(), n, 0, 0});
    run(lg, rows, pc, n);
  }

  // Sum over cells i of block a whose image r lies in block b of P_i^T (weight / Omega_r) P_r.
  void add_deltas(int a, const Eigen::MatrixXd& pa, int b, const Eigen::MatrixXd& pb) {
    if (deltas_.empty()) return;
    const int fa = cb_.start[static_cast<size_t>(a)], fb = cb_.start[static_cast<size_t>(b)], nb = cb_.size(b);
    for (const auto& d : deltas_) {
      const bool mirror = d.kind == DeltaPart::Kind::Mirror;
      std::vector<int> ia, ib;
      std::vector<double> w;
      for (int k = 0; k < cb_.size(a); ++k) {
        const int i = cb_.order[static_cast<size_t>(fa + k)];
        const int img = mirror ? g_.rotate_pi[i] : i;
        const int q = cb_.position[static_cast<size_t>(img)] - fb;
        if (q < 0 || q >= nb) continue;
        ia.push_back(k);
        ib.push_back(q);
        w.push_back(d.weight / g_.solid_angles[img]);
      }
      if (ia.empty()) continue;
      Eigen::MatrixXd left(static_cast<Eigen::Index>(ia.size()), modes_), right(static_cast<Eigen::Index>(ia.size()), modes_);
      for (size_t k = 0; k < ia.size(); ++k) {
        left.row(static_cast<Eigen::Index>(k)) = pa.row(ia[k]);
        right.row(static_cast<Eigen::Index>(k)) = w[k] * pb.row(ib[k]);
      }
      delta_.noalias() += left.transpose() * right;
    }
  }

  // The rows' products with the columns pc (rows of P of the pair grid's first n cells), in batches of
  // kStreamingBlockRows added in batch order (icobrdf/core/support/in_order_sums.hpp: the same bits for any thread
  // count).
  void run(const Grid& lg, const std::vector<PairRow>& all_rows, const Eigen::MatrixXd& pc, int n) {
    std::vector<PairRow> kept;  // with every_ > 1: the batches b with b % every_ == 0 only
    if (every_ > 1)
      for (size_t k = 0; k < all_rows.size(); ++k)
        if ((k / kStreamingBlockRows) % static_cast<size_t>(every_) == 0) kept.push_back(all_rows[k]);
    const std::vector<PairRow>& rows = every_ > 1 ? kept : all_rows;
    const int total = static_cast<int>(rows.size());
    const int batches = (total + kStreamingBlockRows - 1) / kStreamingBlockRows;
    const int ch = model_.channels();
    const bool g_form = cosine_ && !reciprocal_;  // the reciprocal sums sample f and weigh by cos themselves
    Eigen::VectorXd col_cos;
    if (reciprocal_ && cosine_) col_cos = lg.directions.col(2).head(n);
    InOrderSums in_order(x_, kStreamingBlocksAhead);
#pragma omp parallel
    {
      std::vector<Eigen::MatrixXd> f, out;
      std::vector<int> idx;
      Eigen::MatrixXd t, left_q, left_p;
#pragma omp for schedule(dynamic)
      for (int bt = 0; bt < batches; ++bt) {
        in_order.run(bt, [&] {  // a failure is kept and rethrown below (icobrdf/core/support/in_order_sums.hpp)
          const int r0 = bt * kStreamingBlockRows, r1 = std::min(total, r0 + kStreamingBlockRows), nr = r1 - r0;
          idx.clear();
          int col_end = 0;
          for (int k = r0; k < r1; ++k) {
            idx.push_back(rows[static_cast<size_t>(k)].local);
            col_end = std::max(col_end, rows[static_cast<size_t>(k)].col_end);
          }
          sample_lut_block(model_, lg, g_form, sampling_, idx, col_end, f);
          left_q.resize(nr, modes_);
          left_p.resize(nr, modes_);
          for (int k = r0; k < r1; ++k) {
            const PairRow& row = rows[static_cast<size_t>(k)];
            const Eigen::Map<const Eigen::RowVectorXd, 0, Eigen::InnerStride<>> p(row.p, modes_, Eigen::InnerStride<>(row.p_stride));
            left_p.row(k - r0) = row.weight * p;
            left_q.row(k - r0) = (reciprocal_ && cosine_ ? lg.directions(row.local, 2) : 1.0) * left_p.row(k - r0);
            for (auto& m : f) {
              if (row.half_end > row.half_begin) m.row(k - r0).segment(row.half_begin, row.half_end - row.half_begin) *= 0.5;
              if (row.col_end < col_end) m.row(k - r0).tail(col_end - row.col_end).setZero();
            }
          }
          out.clear();
          for (int c = 0; c < ch; ++c) {
            Eigen::MatrixXd& fc = f[static_cast<size_t>(c)];
            t.noalias() = fc * pc.topRows(col_end);
            out.push_back(left_q.transpose() * t);  // X1 (Q_i (F P)_i), or X in the general case
            if (reciprocal_ && cosine_) {
              fc.array().rowwise() *= col_cos.head(col_end).transpose().array();
              t.noalias() = fc * pc.topRows(col_end);
              out.push_back(left_p.transpose() * t);  // X2 (P_i (F Q)_i)
            }
          }
          return std::move(out);
        });
        out.clear();
      }
    }
    in_order.rethrow();
  }

  const BrdfModel& model_;
  const Grid& g_;
  const Grid& sg_;
  const CellBlocks& cb_;
  int part_;
  bool cosine_;
  LutSampling sampling_;
  bool symmetric_, reciprocal_;
  Eigen::Index modes_;
  int every_;  // project every every_-th batch of each pair's incident rows (benchmarks: --every)
  std::vector<DeltaPart> deltas_;
  std::vector<Eigen::MatrixXd> x_;
  Eigen::MatrixXd delta_;
};

// Block b's rows of B and its part of G (lower triangle summed, then mirrored), and whether its rows are
// D2-equivariant.
struct BlockBasis {
  Eigen::MatrixXd B;
  Eigen::VectorXd W;
  Eigen::MatrixXd G;
  bool equivariant = false;
};
// Block b's rows of B: on a grid with the D2 maps, the first cell of each orbit is evaluated and every other
// cell whose cubature is the image of the first's under a map (cubature_is_image) takes the first's row times
// the mode signs, as build_discrete_basis does (a quarter of the evaluations); any other cell is evaluated.
Eigen::MatrixXd block_rows_of_b(const Grid& grid, int order, const CellBlocks& cb, int b, const std::vector<int>& cells) {
  if (!has_d2_maps(grid)) return basis_rows(grid, order, cells);
  const int first = cb.start[static_cast<size_t>(b)], n = cb.size(b);
  const auto maps = d2_maps(grid);
  const int modes = hemisphere_basis_count(order);
  std::vector<Eigen::VectorXd> sign(maps.size(), Eigen::VectorXd(modes));
  for (size_t s = 0; s < maps.size(); ++s)
    for (int j = 0; j < modes; ++j) sign[s][j] = maps[s].sign(ansi_to_nl(j).l);
  // Per cell of the block: the map that carries its orbit's first cell's sampling onto it, or -1 (evaluate).
  std::vector<int> via(static_cast<size_t>(n), -1);
  std::vector<int> evaluate;
  for (int k = 0; k < n; ++k) {
    const int p = first + k, c = cb.order[static_cast<size_t>(p)], o = cb.orbit_begin[static_cast<size_t>(p)];
    if (o != p) {
      const int r = cb.order[static_cast<size_t>(o)];
      for (size_t s = 0; s < maps.size() && via[static_cast<size_t>(k)] < 0; ++s)
        if ((*maps[s].cells)[r] == c && cubature_is_image(grid, maps[s], r, c)) via[static_cast<size_t>(k)] = static_cast<int>(s);
    }
    if (via[static_cast<size_t>(k)] < 0) evaluate.push_back(k);
  }
  std::vector<int> eval_cells;
  for (const int k : evaluate) eval_cells.push_back(cells[static_cast<size_t>(k)]);
  const Eigen::MatrixXd e = basis_rows(grid, order, eval_cells);
  Eigen::MatrixXd rows(n, modes);
  for (size_t i = 0; i < evaluate.size(); ++i) rows.row(evaluate[i]) = e.row(static_cast<Eigen::Index>(i));
  for (int k = 0; k < n; ++k)  // orbits in order: the first cell's row is filled before the others of its orbit
    if (via[static_cast<size_t>(k)] >= 0)
      rows.row(k) = rows.row(cb.orbit_begin[static_cast<size_t>(first + k)] - first).cwiseProduct(sign[static_cast<size_t>(via[static_cast<size_t>(k)])].transpose());
  return rows;
}

BlockBasis block_basis(const Grid& grid, int order, const CellBlocks& cb, int b) {
  BlockBasis out;
  const std::vector<int> cells = cb.cells(b);
  out.B = block_rows_of_b(grid, order, cb, b, cells);
  out.W.resize(static_cast<Eigen::Index>(cells.size()));
  for (size_t k = 0; k < cells.size(); ++k) out.W[static_cast<Eigen::Index>(k)] = grid.solid_angles[cells[k]];
  const Eigen::MatrixXd wb = out.W.cwiseSqrt().asDiagonal() * out.B;
  Eigen::MatrixXd lower = Eigen::MatrixXd::Zero(out.B.cols(), out.B.cols());
  lower.selfadjointView<Eigen::Lower>().rankUpdate(wb.transpose());
  out.G = lower.selfadjointView<Eigen::Lower>();
  out.equivariant = block_rows_equivariant(grid, cb, b, out.B, kStreamingSymmetryTol);
  return out;
}

// P's rows = W B G^-1 (P^T = G^-1 (W B)^T); `basis` holds the summed G.
Eigen::MatrixXd projection_rows(const DiscreteBasis& basis, const BlockBasis& bb) {
  Eigen::LLT<Eigen::MatrixXd> llt(basis.G);
  if (llt.info() != Eigen::Success)
    throw UnsupportedError("projection: Gram matrix of order " + std::to_string(basis.order) + " on " + std::to_string(basis.cells()) +
                           " cells is not positive definite (condition number " + std::to_string(basis.condition) + ")");
  return llt.solve((bb.W.asDiagonal() * bb.B).transpose()).transpose();
}

DiscreteBasis summed_basis(const Grid& grid, int order, Eigen::MatrixXd g, double gram_tolerance) {
  DiscreteBasis d;
  d.order = order;
  d.grid_cells = grid.cells();
  d.evaluated_cells = grid.cells();
  d.G = std::move(g);
  set_gram_figures(d);
  check_supported(d, gram_tolerance);
  return d;
}

}  // namespace

std::vector<int> CellBlocks::cells(int b) const {
  return std::vector<int>(order.begin() + start[static_cast<size_t>(b)], order.begin() + start[static_cast<size_t>(b) + 1]);
}

CellBlocks cell_blocks(const Grid& g, int parts) {
  const int cells = g.cells();
  CellBlocks cb;
  std::vector<int> rep(static_cast<size_t>(cells));
  for (int c = 0; c < cells; ++c) rep[static_cast<size_t>(c)] = c;
  std::vector<double> rep_weight(static_cast<size_t>(cells), 1.0);
  if (has_d2_maps(g)) {
    for (const auto& s : d2_maps(g))
      for (int c = 0; c < cells; ++c) rep[static_cast<size_t>(c)] = std::min(rep[static_cast<size_t>(c)], (*s.cells)[c]);
    for (const auto& r : d2_representatives(g)) rep_weight[static_cast<size_t>(r.cell)] = r.weight;
  }
  cb.order.resize(static_cast<size_t>(cells));
  for (int c = 0; c < cells; ++c) cb.order[static_cast<size_t>(c)] = c;
  std::stable_sort(cb.order.begin(), cb.order.end(), [&](int a, int b) { return rep[static_cast<size_t>(a)] < rep[static_cast<size_t>(b)]; });
  cb.position.assign(static_cast<size_t>(cells), 0);
  cb.orbit_begin.assign(static_cast<size_t>(cells), 0);
  cb.orbit_end.assign(static_cast<size_t>(cells), 0);
  cb.weight.assign(static_cast<size_t>(cells), 0.0);
  int orbits = 0;
  for (int p = 0; p < cells;) {
    int e = p;
    while (e < cells && rep[static_cast<size_t>(cb.order[static_cast<size_t>(e)])] == rep[static_cast<size_t>(cb.order[static_cast<size_t>(p)])]) ++e;
    for (int q = p; q < e; ++q) {
      cb.orbit_begin[static_cast<size_t>(q)] = p;
      cb.orbit_end[static_cast<size_t>(q)] = e;
      cb.position[static_cast<size_t>(cb.order[static_cast<size_t>(q)])] = q;
    }
    cb.weight[static_cast<size_t>(p)] = rep_weight[static_cast<size_t>(cb.order[static_cast<size_t>(p)])];
    ++orbits;
    p = e;
  }
  if (parts < 1 || parts > orbits)
    throw ArgumentError("row split: " + std::to_string(parts) + " parts of a grid of " + std::to_string(cells) + " cells in " +
                        std::to_string(orbits) + " orbits, expected 1 to " + std::to_string(orbits));
  cb.start.assign(1, 0);
  for (int b = 1; b < parts; ++b) {
    int p = static_cast<int>(static_cast<long long>(cells) * b / parts);
    p = std::max(p, cb.start.back() + 1);
    while (p < cells && cb.orbit_begin[static_cast<size_t>(p)] != p) ++p;  // the next orbit boundary
    if (p >= cells)
      throw ArgumentError("row split: " + std::to_string(parts) + " parts of a grid of " + std::to_string(cells) +
                          " cells leave a part without a cell, expected fewer parts");
    cb.start.push_back(p);
  }
  cb.start.push_back(cells);
  return cb;
}

RingSchedule ring_schedule(int part, int parts, bool reciprocal) {
  if (parts < 1 || part < 0 || part >= parts)
    throw ArgumentError("ring schedule: part " + std::to_string(part) + " of " + std::to_string(parts) + ", expected 0 <= part < parts");
  RingSchedule s;
  const int steps = reciprocal ? parts / 2 + 1 : parts;
  for (int t = 0; t < steps; ++t) {
    // Reciprocal: the pair at distance t is met by this part at step t and by the part t ahead at step
    // parts - t; steps beyond parts / 2 are left out, and half way round (t == parts - t) both parts of a
    // pair meet it at the same step and each computes half of its rows (else, with 2 parts, part 0 would
    // do its triangle and the whole pair, 3 times part 1's work).
    const bool half_way = reciprocal && 2 * t == parts && t > 0;
    s.compute.push_back(1);
    s.half.push_back(static_cast<char>(half_way ? (part < parts / 2 ? 1 : 2) : 0));
    s.receive.push_back(t > 0);
    s.send.push_back(t > 0);
  }
  return s;
}

SplitOperators split_operators(const Grid& grid, int order, double gram_tolerance, RowSplitExchange& exchange) {
  SplitOperators ops;
  ops.part = exchange.part();
  ops.blocks = std::make_shared<const CellBlocks>(cell_blocks(grid, exchange.parts()));
  BlockBasis bb = block_basis(grid, order, *ops.blocks, ops.part);
  // One sum: G, and the number of parts whose rows are not D2-equivariant.
  std::vector<Eigen::MatrixXd> sums{std::move(bb.G), Eigen::MatrixXd::Constant(1, 1, bb.equivariant ? 0.0 : 1.0)};
  exchange.sum(sums);
  ops.basis = summed_basis(grid, order, std::move(sums[0]), gram_tolerance);
  ops.rows_equivariant = sums[1](0, 0) == 0.0;
  ops.basis.W = bb.W;
  ops.P = projection_rows(ops.basis, bb);
  // A second sum, of nothing, once every part has its rows of P: a part that failed after the sum of G (a
  // refused order fails on all alike; memory on one) can still take part in an exchange with its error
  // (icobrdf/cluster), instead of leaving the others waiting for its block in the ring.
  std::vector<Eigen::MatrixXd> ready{Eigen::MatrixXd::Zero(1, 1)};
  exchange.sum(ready);
  return ops;
}

std::vector<Eigen::MatrixXd> row_split_projection(const BrdfModel& model, const Grid& grid, const SplitOperators& ops, bool cosine,
                                                  LutSampling sampling, const Grid* sampling_grid, RowSplitExchange& exchange, int every) {
  const Grid& sg = sampling_grid ? *sampling_grid : grid;
  if (every < 1) throw ArgumentError("row split projection: every " + std::to_string(every) + ", expected >= 1");
  if (!ops.blocks || ops.blocks->parts() != exchange.parts() || ops.part != exchange.part() ||
      static_cast<int>(ops.blocks->order.size()) != grid.cells() || ops.P.rows() != ops.blocks->size(ops.part))
    throw ArgumentError("row split projection: the operators were split for another grid or another set of processes");
  const StreamingShortcuts k = streaming_shortcuts(model, grid, sg, cosine, sampling);
  PartProjector projector(model, grid, sg, *ops.blocks, ops.part, cosine, sampling, k.d2 && ops.rows_equivariant, k.reciprocal, ops.P.cols(),
                          every);
  const RingSchedule s = ring_schedule(ops.part, exchange.parts(), k.reciprocal);
  ProgressMeter progress("projecting", s.steps());
  Eigen::MatrixXd held;  // the visiting block's rows (steps >= 1)
  for (int t = 0; t < s.steps(); ++t) {
    if (t > 0) {
      const bool send = s.send[static_cast<size_t>(t)];
      // Step 1 sends a copy of this part's own rows (kept for every step); later steps pass the visitor on.
      Eigen::MatrixXd out = !send ? Eigen::MatrixXd() : t == 1 ? Eigen::MatrixXd(ops.P) : std::move(held);
      held = exchange.shift(std::move(out), send, s.receive[static_cast<size_t>(t)]);
    }
    const int v = (ops.part + t) % exchange.parts();
    if (s.compute[static_cast<size_t>(t)]) projector.step(v, ops.P, t == 0 ? ops.P : held, s.half[static_cast<size_t>(t)]);
    progress.step();
  }
  held.resize(0, 0);
  auto out = projector.finish();
  exchange.sum(out);
  return out;
}

std::vector<Eigen::MatrixXd> row_split_projection_serial(const BrdfModel& model, const Grid& grid, int order, int parts, bool cosine,
                                                         LutSampling sampling, const Grid* sampling_grid, double gram_tolerance) {
  const Grid& sg = sampling_grid ? *sampling_grid : grid;
  const CellBlocks cb = cell_blocks(grid, parts);
  std::vector<BlockBasis> bases;
  Eigen::MatrixXd g;
  bool equivariant = true;
  for (int b = 0; b < parts; ++b) {
    bases.push_back(block_basis(grid, order, cb, b));
    g = b == 0 ? bases.back().G : Eigen::MatrixXd(g + bases.back().G);
    equivariant = equivariant && bases.back().equivariant;
  }
  const DiscreteBasis basis = summed_basis(grid, order, std::move(g), gram_tolerance);
  std::vector<Eigen::MatrixXd> p;
  for (const auto& bb : bases) p.push_back(projection_rows(basis, bb));
  const StreamingShortcuts k = streaming_shortcuts(model, grid, sg, cosine, sampling);
  std::vector<Eigen::MatrixXd> total;
  for (int part = 0; part < parts; ++part) {
    PartProjector projector(model, grid, sg, cb, part, cosine, sampling, k.d2 && equivariant, k.reciprocal, p[0].cols());
    const RingSchedule s = ring_schedule(part, parts, k.reciprocal);
    for (int t = 0; t < s.steps(); ++t) {
      const int v = (part + t) % parts;
      if (s.compute[static_cast<size_t>(t)]) projector.step(v, p[static_cast<size_t>(part)], p[static_cast<size_t>(v)], s.half[static_cast<size_t>(t)]);
    }
    auto out = projector.finish();
    if (total.empty()) total = std::move(out);
    else
      for (size_t c = 0; c < out.size(); ++c) total[c] += out[c];
  }
  return total;
}

}  // namespace icobrdf
