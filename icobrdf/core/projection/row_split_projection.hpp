#pragma once
// Streaming projection with the operators split by rows over `parts` processes: each process holds the rows
// of B and P of its own block of cells only, so the operators take O(cells x modes / parts) per process
// instead of cells x modes each (icobrdf/core/projection/streaming_projection.hpp holds them whole on every process).
//
// Blocks: the cells in D2-orbit order (orbits by their smallest cell, cells ascending within one; every cell
// its own orbit on a grid without the maps), cut into `parts` contiguous blocks at orbit boundaries, so
// that every orbit lies in one block and a process can fill, check and use the D2 symmetry of its rows alone.
//
// Operators: each process evaluates its cells' rows of B (basis_rows; one cell per orbit when the grid's
// cubature is D2-equivariant, the others by the mode signs, as build_discrete_basis), adds W_c B_c^T B_c over them, and the
// sum over the processes (RowSplitExchange::sum) is G; then its rows of P = W B G^-1. G equals the one-process
// G up to the order of the sums.
//
// Projection: C = Q^T F P with F's entries sampled on the fly (Q = P, or D P in g form, as in
// streaming_projection) is a sum over pairs of blocks (A, B): the rows of A's incident cells (one per orbit
// with D2) against the columns of B's cells, which needs A's and B's rows of P only. The rows of P travel
// round a ring (RowSplitExchange::shift: each process sends the block it holds to the previous process and
// receives the next one's). A reciprocal model samples one triangle of the symmetric f LUT (pairs
// {A, B} once, the later block's rows against the earlier block's columns, and the triangle inside each
// block): floor(parts / 2) shifts, each process computing the same work (with an even count, each pair half
// way round is met by both of its processes at once, and each computes half of its rows). Other models take every pair
// (A, B): parts - 1 shifts. Each process sums its pairs' terms, applies the D2 average and the transposes of
// the triangle, adds its pairs' delta terms, and RowSplitExchange::sum adds the processes' matrices.
// Delta parts are added exactly, from the pairs that hold both a cell and its image.
//
// Memory per process (M modes, C cells, R parts, ch channels, T threads): its rows of P (C M / R doubles),
// the visiting block (C M / R), what the exchange holds while it shifts (icobrdf/cluster's: the block sent
// and the block received, 2 C M / R), per thread 32 x (C / R) x ch doubles of LUT rows, and ch M^2 (2 ch M^2
// in g form) of sums; plus the grid (about 1.6 kB per cell) on every process.
//
// The result equals streaming_projection's up to the order of the sums (the tests compare them to 1e-12
// relative); for a fixed number of parts it does not depend on the number of threads.
#include <Eigen/Core>

#include <memory>
#include <vector>

#include "icobrdf/core/models/brdf_model.hpp"
#include "icobrdf/core/projection/discrete_basis.hpp"
#include "icobrdf/core/grid/grid.hpp"
#include "icobrdf/core/projection/lut.hpp"

namespace icobrdf {

// The processes' communication, implemented over MPI in icobrdf/cluster (core knows nothing of MPI). Every
// process calls each member in the same sequence.
class RowSplitExchange {
 public:
  virtual ~RowSplitExchange() = default;
  virtual int part() const = 0;
  virtual int parts() const = 0;
  // Replaces `m` (the same sizes on every process) by the sum over the processes, added in part order so
  // that the result does not depend on timing; every process gets the sum.
  virtual void sum(std::vector<Eigen::MatrixXd>& m) = 0;
  // One step of the ring: when `send`, gives `block` to part - 1 (mod parts); when `receive`, returns the
  // block part + 1 (mod parts) sent, else an empty matrix. `block` is consumed either way.
  virtual Eigen::MatrixXd shift(Eigen::MatrixXd block, bool send, bool receive) = 0;
};

// The blocks of a grid's cells (see above). Positions index `order`.
struct CellBlocks {
  std::vector<int> order;        // the cells in orbit order
  std::vector<int> position;     // per cell: its position in `order`
  std::vector<int> start;        // block b holds positions [start[b], start[b + 1])
  std::vector<int> orbit_begin;  // per position: the first position of its orbit
  std::vector<int> orbit_end;    // per position: one past the last position of its orbit
  std::vector<double> weight;    // per position: 1 / |stabilizer| for the first of an orbit, 0 for the rest
  int parts() const { return static_cast<int>(start.size()) - 1; }
  int size(int b) const { return start[static_cast<size_t>(b) + 1] - start[static_cast<size_t>(b)]; }
  std::vector<int> cells(int b) const;  // block b's cells in order
};

// ArgumentError unless 1 <= parts <= the number of orbits. Blocks hold as equal numbers of cells as whole
// orbits allow (each within one orbit of cells / parts).
CellBlocks cell_blocks(const Grid& grid, int parts);

// One process's operators: its cells' rows of B (overwritten by those of P) and the summed G with its figures.
struct SplitOperators {
  std::shared_ptr<const CellBlocks> blocks;
  int part = 0;
  DiscreteBasis basis;  // W: the block's cells; B not kept (P replaces it); G and its figures: the whole grid's; grid_cells set
  Eigen::MatrixXd P;    // the block's rows of P = W B G^-1 (block size x modes)
  bool rows_equivariant = false;  // every part's rows of B are D2-equivariant (the symmetric shortcut may be used)
};

// Collective (exchange.sum twice: G, then an empty sum once P is made). UnsupportedError as check_supported when the summed G fails `gram_tolerance`
// (on every process alike, since G is the same).
SplitOperators split_operators(const Grid& grid, int order, double gram_tolerance, RowSplitExchange& exchange);

// C per model channel, as streaming_projection(model, grid, P, cosine, sampling, sampling_grid) would give.
// Collective (the shifts, one exchange.sum). `sampling_grid`: as streaming_projection's.
// `every` > 1 (benchmarks only: `icobrdf bench streaming --every K`, as StreamingShare::every): each pair of
// blocks projects only its batches of kStreamingBlockRows incident rows b with b % every == 0, for the time
// of a projection too long to run whole (about 1 / every of the pairs' work; the ring, the sums and the
// memory stay whole); the matrices are then not C. ArgumentError for every < 1.
std::vector<Eigen::MatrixXd> row_split_projection(const BrdfModel& model, const Grid& grid, const SplitOperators& ops, bool cosine,
                                                  LutSampling sampling, const Grid* sampling_grid, RowSplitExchange& exchange,
                                                  int every = 1);

// The pairs of blocks part `part` computes at each ring step s = 0, 1, ...: at step s it holds the rows of
// block (part + s) mod parts, and computes with them when `compute[s]` (all of the pair's rows, or with
// half[s] = 1 or 2 the first or second half of them); it receives at step s >= 1 when `receive[s]` and sends
// at step s >= 1 when `send[s]` (what it held at step s - 1). Every pair of blocks is computed exactly once
// over all parts (ordered pairs, or unordered ones for a reciprocal model; a pair half way round the ring,
// with an even number of parts, as two halves by its two parts).
struct RingSchedule {
  std::vector<char> compute, half, receive, send;
  int steps() const { return static_cast<int>(compute.size()); }
};
RingSchedule ring_schedule(int part, int parts, bool reciprocal);

// All parts in one process, one after another (tests and checks: no memory saving): the operators of every
// block, then each part's pairs by its schedule, summed in part order. Equals row_split_projection's result
// on `parts` processes up to the order of the sums.
std::vector<Eigen::MatrixXd> row_split_projection_serial(const BrdfModel& model, const Grid& grid, int order, int parts, bool cosine,
                                                         LutSampling sampling, const Grid* sampling_grid = nullptr,
                                                         double gram_tolerance = kDefaultGramTolerance);

}  // namespace icobrdf
