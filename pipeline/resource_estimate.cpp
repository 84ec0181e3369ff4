#include "pipeline/resource_estimate.hpp"

#include <omp.h>

#include <cmath>

#include "core/memory_budget.hpp"

namespace icobrdf {
namespace {

constexpr double kDouble = 8.0;
// Mirrors of the block sizes of core/discrete_basis.cpp (kGramBlocks partial Gram matrices) and
// core/streaming_projection.cpp (kBlockRows incident cells per block and thread).
constexpr double kGramBlocks = 16;
constexpr double kBlockRows = 32;

double context_bytes(double cells, double modes) { return kDouble * (3 * cells * modes + (kGramBlocks + 3) * modes * modes); }

}  // namespace

double grid_cells(int level) { return 10.0 * std::pow(4.0, level) + std::pow(2.0, level + 1); }
double order_modes(int order) { return 0.5 * (order + 1.0) * (order + 2.0); }
int estimate_threads() { return omp_get_max_threads(); }

double model_fit_bytes(int level, int order, int channels, int threads) {
  const double c = grid_cells(level), m = order_modes(order), ch = channels, t = threads;
  return 2 * c * kGridBytesPerCell + context_bytes(c, m) +
         kDouble * (2 * c * m + t * kBlockRows * c * ch + (2 * t + 4) * ch * m * m);
}

double lut_bytes(int level, int order, int channels, bool float32, int threads) {
  const double c = grid_cells(level), m = order_modes(order), ch = channels;
  const double lut = kDouble * ch * c * c;
  const double fit = context_bytes(c, m) + kDouble * (threads + 4) * ch * m * m;
  return 2 * c * kGridBytesPerCell + lut * (float32 ? 1.5 : 2.0) + fit;
}

int largest_order_in_memory(int level, int order_max, int channels) {
  const double have = available_memory().bytes;
  const int t = estimate_threads();
  int n = order_max;
  while (n >= 0 && model_fit_bytes(level, n, channels, t) > have) --n;
  return n;
}

void require_model_fit_memory(int level, int order, int channels, const std::string& what) {
  const double need = model_fit_bytes(level, order, channels, estimate_threads());
  if (need <= available_memory().bytes) return;
  // Only the order is suggested: a lower level that fits in memory may not resolve the order at all.
  const int n = largest_order_in_memory(level, order, channels);
  require_memory(need, what + " at level " + std::to_string(level) + ", order " + std::to_string(order),
                 n >= 0 ? "order " + std::to_string(n) + " fits at level " + std::to_string(level) : "no order fits at this level");
}

void require_lut_memory(int level, int order, int channels, bool float32, const std::string& what) {
  const int t = estimate_threads();
  const double need = lut_bytes(level, order, channels, float32, t);
  if (need <= available_memory().bytes) return;
  int l = level;
  while (l >= 0 && lut_bytes(l, order, channels, float32, t) > available_memory().bytes) --l;
  require_memory(need, what + " (a " + std::to_string(static_cast<long long>(grid_cells(level))) + " x " +
                           std::to_string(static_cast<long long>(grid_cells(level))) + " LUT)",
                 l >= 0 ? "level " + std::to_string(l) + " fits" : "");
}

}  // namespace icobrdf
