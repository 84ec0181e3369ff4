#include "icobrdf/lab/streaming_benchmark.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>

#include "icobrdf/core/projection/streaming_projection.hpp"
#include "icobrdf/lab/process_usage.hpp"

namespace icobrdf::lab {
namespace {

double wall_seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// The request's share with StreamingShare::every = `every` (a one-process share when it has none).
std::shared_ptr<const StreamingShare> with_every(const FitRequest& request, int every) {
  auto s = request.share ? std::make_shared<StreamingShare>(*request.share) : std::make_shared<StreamingShare>();
  s->every = every;
  return s;
}

}  // namespace

double StreamingBenchmark::best_seconds() const { return *std::min_element(seconds.begin(), seconds.end()); }

double StreamingBenchmark::whole_estimate_seconds() const { return fixed_seconds + every * (best_seconds() - fixed_seconds); }

StreamingBenchmark measure_streaming(const BrdfSource& source, const FitRequest& request, int every, int repeat) {
  StreamingBenchmark b;
  b.every = every;
  FitContexts contexts;
  const auto t0 = std::chrono::steady_clock::now();
  const auto ctx = contexts.context(request);
  b.context_seconds = wall_seconds_since(t0);
  b.cells = ctx->grid->cells();
  FitRequest r = request;
  if (every > 1) {
    FitRequest one_block = request;
    one_block.share = with_every(request, kOneBlock);
    const auto t1 = std::chrono::steady_clock::now();
    fit_source(source, one_block, contexts);
    b.fixed_seconds = wall_seconds_since(t1);
    r.share = with_every(request, every);
  }
  const double cpu0 = process_cpu_seconds();
  for (int k = 0; k < repeat; ++k) {
    const auto t1 = std::chrono::steady_clock::now();
    b.spectrum = fit_source(source, r, contexts).spectrum;
    b.seconds.push_back(wall_seconds_since(t1));
  }
  // Per projection: the work this process did, which a loaded machine does not inflate as it does the wall
  // time (waiting for the other ranks costs no CPU: ranks wait by polling with sleeps).
  b.cpu_seconds_per_projection = (process_cpu_seconds() - cpu0) / repeat;
  double norm = 0.0;
  for (const auto& c : b.spectrum.channels) {
    b.max_abs_coefficient = std::max(b.max_abs_coefficient, c.cwiseAbs().maxCoeff());
    norm += c.squaredNorm();
  }
  b.frobenius_norm = std::sqrt(norm);
  return b;
}

nlohmann::json streaming_report(const StreamingBenchmark& b, int level, const std::string& sampling, const StreamingRanks& ranks) {
  const Spectrum& s = b.spectrum;
  return {{"source", s.source},
          {"level", level},
          {"cells", b.cells},
          {"order", s.order},
          {"modes", s.modes()},
          {"channels", s.channel_count()},
          {"sampling", sampling},
          {"cosine", s.cosine},
          {"ranks", ranks.ranks},
          {"threads_per_rank", ranks.threads_per_rank},
          {"every", b.every},
          {"operators", ranks.operators},
          {"projection_seconds_fixed", b.fixed_seconds},
          {"projection_seconds_whole_estimate", b.whole_estimate_seconds()},
          {"context_seconds", b.context_seconds},
          {"projection_seconds", b.best_seconds()},
          {"projection_seconds_all", b.seconds},
          {"peak_rss_bytes_per_rank", ranks.peak_rss_bytes},
          {"projection_cpu_seconds_per_rank", ranks.cpu_seconds},
          {"max_abs_coefficient", b.max_abs_coefficient},
          {"frobenius_norm", b.frobenius_norm}};
}

std::string streaming_text(const StreamingBenchmark& b, int level, const std::string& sampling, int repeat, int every,
                           const StreamingRanks& ranks) {
  const Spectrum& s = b.spectrum;
  const double best = b.best_seconds();
  std::string out = fmt::format("streaming projection of {}: level {} ({} cells), order {} ({} modes), {} channel(s), {} sampling{}\n", s.source,
                           level, b.cells, s.order, s.modes(), s.channel_count(), sampling, s.cosine ? ", g form" : "")
                    + fmt::format("  {} rank(s) x {} thread(s), operators {}; grid and operators {:.3f} s; projection {:.3f} s (best of {}){}\n", ranks.ranks,
                           ranks.threads_per_rank, ranks.operators, b.context_seconds, best, repeat,
                           every > 1 ? fmt::format(" for 1 block in {} ({:.1f} s of it fixed): {:.1f} s for all (estimate)", every,
                                                     b.fixed_seconds, b.whole_estimate_seconds()) : "");
  std::string mem;
  for (std::size_t k = 0; k < ranks.peak_rss_bytes.size(); ++k) mem += fmt::format("{}rank {} {:.0f} MB", k ? ", " : "", k, ranks.peak_rss_bytes[k] / 1e6);
  std::string work;
  for (std::size_t k = 0; k < ranks.cpu_seconds.size(); ++k) work += fmt::format("{}rank {} {:.2f} s", k ? ", " : "", k, ranks.cpu_seconds[k]);
  return out + "  CPU time of one projection: " + work + "\n" + "  peak resident memory: " + mem + "\n" +
         fmt::format("  max |C| {:.17g}, Frobenius norm {:.17g}\n", b.max_abs_coefficient, b.frobenius_norm);
}

}  // namespace icobrdf::lab
