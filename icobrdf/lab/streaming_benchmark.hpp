#pragma once
// The timing of the streaming projection of one material (C = P^T F P without its LUT,
// icobrdf/core/projection/streaming_projection.hpp): the fit `icobrdf fit` makes, apart from building the grid
// and the operators (`icobrdf bench streaming`). Under mpirun the request's share spreads the projection over
// the ranks; every rank calls measure_streaming, and the report carries one CPU time and one peak resident
// memory per rank.
//
// `every` K > 1 projects only every K-th block of incident rows (StreamingShare::every), with every array at
// full size: the time of a projection too long to run whole, and its memory; the matrices are then not C.
// The costs that do not grow with the blocks (P reordered for the triangle, the fit's albedo figure) are timed
// apart, by a projection of block 0 alone, so that the whole is estimated as fixed + K (best - fixed).
#include <nlohmann/json.hpp>

#include <string>
#include <vector>

#include "icobrdf/core/spectrum/spectrum.hpp"
#include "icobrdf/io/brdf_source.hpp"
#include "icobrdf/pipeline/fit_source.hpp"

namespace icobrdf::lab {

// StreamingShare::every beyond any projection's blocks (level 8: 5,124 blocks): block 0 alone.
inline constexpr int kOneBlock = 1 << 30;

struct StreamingBenchmark {
  Spectrum spectrum;                      // of the last projection (with every > 1: of those blocks only)
  int cells = 0;                          // of the fitting grid
  int every = 1;                          // as asked
  double context_seconds = 0.0;           // the grid and the operators
  double fixed_seconds = 0.0;             // every > 1: block 0 alone; else 0
  std::vector<double> seconds;            // wall seconds of each timed projection
  double cpu_seconds_per_projection = 0;  // of this process (all threads), averaged over the timed projections
  double max_abs_coefficient = 0.0;       // max |C| over the channels
  double frobenius_norm = 0.0;            // sqrt(sum over the channels of |C|_F^2)

  double best_seconds() const;            // the least of `seconds`
  double whole_estimate_seconds() const;  // fixed + every (best - fixed): the whole projection
};

// Builds the request's grid and operators (timed), then makes `repeat` projections of `source` (each timed);
// with every > 1, first block 0 alone (above). Collective under mpirun (the request's share).
StreamingBenchmark measure_streaming(const BrdfSource& source, const FitRequest& request, int every, int repeat);

// How the projection was spread, for the report.
struct StreamingRanks {
  int ranks = 1;
  int threads_per_rank = 1;
  std::string operators;                  // "whole (one process)", "split by rows" or "whole on every rank"
  std::vector<double> peak_rss_bytes;     // per rank (rank order)
  std::vector<double> cpu_seconds;        // of one projection, per rank (rank order)
};

// The report as JSON: source, level, cells, order, modes, channels, sampling (the text given), cosine, ranks,
// threads_per_rank, every, operators, projection_seconds_fixed, projection_seconds_whole_estimate,
// context_seconds, projection_seconds (the best), projection_seconds_all, peak_rss_bytes_per_rank,
// projection_cpu_seconds_per_rank, max_abs_coefficient, frobenius_norm.
nlohmann::json streaming_report(const StreamingBenchmark& b, int level, const std::string& sampling, const StreamingRanks& ranks);
// The text report of the same: sizes, ranks and threads, the best time (and the estimate for all blocks when
// only 1 in `every` was projected), CPU time and peak memory per rank, max |C| and the Frobenius norm.
std::string streaming_text(const StreamingBenchmark& b, int level, const std::string& sampling, int repeat, int every,
                           const StreamingRanks& ranks);

}  // namespace icobrdf::lab
