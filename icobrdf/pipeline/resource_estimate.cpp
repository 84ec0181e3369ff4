#include "icobrdf/pipeline/resource_estimate.hpp"

#include <omp.h>

#include "icobrdf/core/projection/discrete_basis.hpp"
#include "icobrdf/core/basis/hemisphere_basis.hpp"
#include "icobrdf/core/support/memory_budget.hpp"
#include "icobrdf/core/projection/streaming_projection.hpp"
#include "icobrdf/io/sample_draws.hpp"
#include "icobrdf/io/spectrum_file.hpp"

namespace icobrdf {
namespace {

constexpr double kDouble = 8.0;
// The block sizes of the code whose memory is estimated (partial Gram matrices; LUT rows per thread).
constexpr double kGramBlocks = kGramPartialSums;
constexpr double kBlockRows = kStreamingBlockRows;

double context_bytes(double cells, double modes) { return kDouble * (3 * cells * modes + (kGramBlocks + 3) * modes * modes); }

// The largest x in [0, from] whose estimate bytes(x) is within `have` (-1: none): estimates grow with x.
template <class Bytes>
int largest_within(int from, double have, Bytes bytes) {
  int x = from;
  while (x >= 0 && bytes(x) > have) --x;
  return x;
}

double cells_of(int level) { return static_cast<double>(equal_area_cells(level)); }
double modes_of(int order) { return static_cast<double>(hemisphere_basis_count(order)); }

}  // namespace

int estimate_threads() { return omp_get_max_threads(); }

double model_fit_bytes(int level, int order, int channels, int threads, int parts) {
  const double c = cells_of(level), m = modes_of(order), ch = channels, t = threads;
  if (parts > 1) {
    // Split by rows (icobrdf/core/projection/row_split_projection.hpp): B and P of the own block while P is made (2),
    // then P, the visiting block and the exchange's sent and received copies (4), of C M / R each; LUT rows
    // of the widest pair (a block's columns plus its rows); G's solve and the sums.
    const double block = c / parts + 4;
    return 2 * c * kGridBytesPerCell + kDouble * (4 * block * m + t * kBlockRows * 2 * block * ch + (kGramBlocks + 3) * m * m +
                                                  (2 * (t + kStreamingBlocksAhead) + 4) * ch * m * m);
  }
  return 2 * c * kGridBytesPerCell + context_bytes(c, m) +
         kDouble * (4 * c * m + t * kBlockRows * c * ch + (2 * (t + kStreamingBlocksAhead) + 4) * ch * m * m);
}

double lut_bytes(int level, int order, int channels, bool float32, int threads) {
  const double c = cells_of(level), m = modes_of(order), ch = channels;
  const double lut = kDouble * ch * c * c;
  const double fit = context_bytes(c, m) + kDouble * (threads + 4) * ch * m * m;
  return 2 * c * kGridBytesPerCell + lut * (float32 ? 1.5 : 2.0) + fit;
}

// Cubature points per cell of the degree-9 rule a grid carries (the average of its 36-38).
constexpr double kCubaturePointsPerCell = 37.0;
// Doubles per draw of one block: u1, u2, the direction, pdf, cell, weights, and about 80 bytes of CSV text.
constexpr double kDrawBytesPerChannel = 2 * kDouble;
constexpr double kDrawBytes = 7 * kDouble + 80.0;

double sampling_bytes(int level, bool cell_average, int channels) {
  const double c = cells_of(level), ch = channels;
  const double points = cell_average ? kCubaturePointsPerCell * c : c;
  // w_i repeated per point, f per channel (and a copy the source may make), the value and the cell masses
  const double distribution = kDouble * points * (3 + 2 * ch + 1) + 2 * kDouble * c;
  const double block = static_cast<double>(kSampleDrawBlock) * (kDrawBytes + kDrawBytesPerChannel * ch);
  return 2 * c * kGridBytesPerCell + distribution + block;
}

void require_sampling_memory(int level, bool cell_average, int channels, const std::string& what) {
  const double need = sampling_bytes(level, cell_average, channels);
  const MemoryAvailable have = available_memory();
  if (need <= have.bytes) return;
  const int l = largest_within(level, have.bytes, [&](int x) { return sampling_bytes(x, cell_average, channels); });
  require_memory(need, have, what + " at level " + std::to_string(level) + (cell_average ? " (cell averages)" : ""),
                 l >= 0 ? "level " + std::to_string(l) + " fits; the number of draws does not change the memory" : "");
}

double grid_bytes(int level) { return 2 * cells_of(level) * kGridBytesPerCell; }
double basis_bytes(double cells, int order) { return context_bytes(cells, modes_of(order)); }
double lut_table_bytes(double cells, int channels) { return kDouble * channels * cells * cells; }

double projection_bench_bytes(int level, int order) {
  const double c = cells_of(level), m = modes_of(order);
  return 2 * c * kGridBytesPerCell + context_bytes(c, m) + kDouble * (c * c + 2 * c * m + 4 * m * m);
}

void require_projection_bench_memory(int level, int order) {
  const double need = projection_bench_bytes(level, order);
  const MemoryAvailable have = available_memory();
  if (need <= have.bytes) return;
  const int l = largest_within(level, have.bytes, [&](int x) { return projection_bench_bytes(x, order); });
  const std::string cells = std::to_string(equal_area_cells(level));
  require_memory(need, have, "bench project at level " + std::to_string(level) + ", order " + std::to_string(order) + " (a " + cells + " x " + cells + " LUT)",
                 l >= 0 ? "--level " + std::to_string(l) + " fits" : "");
}

// The largest order <= order_max whose model fit at `level` needs at most `have` bytes (-1: none).
int largest_order_within(int level, int order_max, int channels, double have, int parts = 1) {
  const int t = estimate_threads();
  return largest_within(order_max, have, [&](int n) { return model_fit_bytes(level, n, channels, t, parts); });
}

int largest_order_in_memory(int level, int order_max, int channels) {
  return largest_order_within(level, order_max, channels, available_memory().bytes);
}

void require_model_fit_memory(int level, int order, int channels, const std::string& what, int parts) {
  const double need = model_fit_bytes(level, order, channels, estimate_threads(), parts);
  const MemoryAvailable have = available_memory();  // read once: it reads /proc and /sys
  if (need <= have.bytes) return;
  // Only the order is suggested: a lower level that fits in memory may not resolve the order at all.
  const int n = largest_order_within(level, order, channels, have.bytes, parts);
  require_memory(need, have, what + " at level " + std::to_string(level) + ", order " + std::to_string(order),
                 n >= 0 ? "order " + std::to_string(n) + " fits at level " + std::to_string(level) : "no order fits at this level");
}

void require_lut_memory(int level, int order, int channels, bool float32, const std::string& what) {
  const int t = estimate_threads();
  const double need = lut_bytes(level, order, channels, float32, t);
  const MemoryAvailable have = available_memory();  // read once: it reads /proc and /sys
  if (need <= have.bytes) return;
  const int l = largest_within(level, have.bytes, [&](int x) { return lut_bytes(x, order, channels, float32, t); });
  const std::string cells = std::to_string(equal_area_cells(level));
  require_memory(need, have, what + " (a " + cells + " x " + cells + " LUT)",
                 l >= 0 ? "level " + std::to_string(l) + " fits" : "");
}

}  // namespace icobrdf
