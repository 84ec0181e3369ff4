// icobrdf bench streaming [SOURCE] --level L --order N [--sampling average|centre] [--cosine] [--repeat K] [--json]
// Times the streaming projection of one material (C = P^T F P without its LUT, icobrdf/core/streaming_projection.hpp),
// the fit `icobrdf fit` makes, apart from building the grid and the operators. Under `mpirun -np R` the
// projection is spread over the ranks (cli/distributed_run.hpp) and the report, from rank 0, gives the
// peak resident memory of every rank. Default SOURCE: model:ggx:alpha=0.1 (issue #18's level-7 case).
// --every K projects only every K-th block of incident rows (icobrdf/core/streaming_projection.hpp
// StreamingShare::every), with every array at full size: the time of a projection too long to run whole
// (times K) and its memory.
#include <fmt/core.h>
#include <nlohmann/json.hpp>
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "cli/bench_commands.hpp"
#include "cli/distributed_run.hpp"
#include "icobrdf/core/error.hpp"
#include "icobrdf/core/hemisphere_basis.hpp"
#include "icobrdf/io/brdf_source.hpp"
#include "icobrdf/pipeline/fit_source.hpp"

namespace icobrdf::cli {
namespace {

struct StreamArgs {
  std::string source = "model:ggx:alpha=0.1", sampling = "average";
  int level = 4, order = 8, repeat = 1, every = 1;
  bool cosine = false, json = false;
};

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void run_streaming(const StreamArgs& a, const DistributedRun& run) {
  FitRequest r;
  r.level = a.level;
  r.order = a.order;
  r.cosine = a.cosine;
  if (a.every > 1) {  // a fraction of the blocks (StreamingShare::every): times and memory, not C
    auto s = run.share ? std::make_shared<StreamingShare>(*run.share) : std::make_shared<StreamingShare>();
    s->every = a.every;
    r.share = s;
  } else {
    r.share = run.share;
  }
  const auto sampling = lut_sampling_named(a.sampling);
  if (!sampling) throw ArgumentError("--sampling: expected 'average' or 'centre', found '" + a.sampling + "'");
  r.sampling = *sampling;
  const auto source = open_source(a.source);
  run.setup_done();
  FitContexts contexts;
  const auto t0 = std::chrono::steady_clock::now();
  const auto ctx = contexts.context(r);
  const double context_seconds = seconds_since(t0);
  std::vector<double> times;
  Spectrum s;
  for (int k = 0; k < a.repeat; ++k) {
    const auto t1 = std::chrono::steady_clock::now();
    s = fit_source(*source, r, contexts).spectrum;
    times.push_back(seconds_since(t1));
  }
  if (run.exchanges() == 0 && run.ranks > 1)
    throw UnsupportedError("bench streaming: " + quoted_text(a.source) + " is not fitted by streaming projection (samples or stored modes)");
  const std::vector<double> rss = run.gather(peak_resident_bytes());
  if (!run.writes()) return;
  double max_abs = 0.0, norm = 0.0;
  for (const auto& c : s.channels) {
    max_abs = std::max(max_abs, c.cwiseAbs().maxCoeff());
    norm += c.squaredNorm();
  }
  const double best = *std::min_element(times.begin(), times.end());
  const nlohmann::json j{{"source", s.source},
                         {"level", a.level},
                         {"cells", ctx->grid->cells()},
                         {"order", s.order},
                         {"modes", s.modes()},
                         {"channels", s.channel_count()},
                         {"sampling", a.sampling},
                         {"cosine", s.cosine},
                         {"ranks", run.ranks},
                         {"threads_per_rank", omp_get_max_threads()},
                         {"every", a.every},
                         {"projection_seconds_whole_estimate", best * a.every},
                         {"context_seconds", context_seconds},
                         {"projection_seconds", best},
                         {"projection_seconds_all", times},
                         {"peak_rss_bytes_per_rank", rss},
                         {"max_abs_coefficient", max_abs},
                         {"frobenius_norm", std::sqrt(norm)}};
  if (a.json) {
    std::cout << j.dump(2) << "\n";
    return;
  }
  std::cout << fmt::format("streaming projection of {}: level {} ({} cells), order {} ({} modes), {} channel(s), {} sampling{}\n", s.source,
                           a.level, ctx->grid->cells(), s.order, s.modes(), s.channel_count(), a.sampling, s.cosine ? ", g form" : "")
            << fmt::format("  {} rank(s) x {} thread(s); grid and operators {:.3f} s; projection {:.3f} s (best of {}){}\n", run.ranks,
                           omp_get_max_threads(), context_seconds, best, a.repeat,
                           a.every > 1 ? fmt::format(" for every {}th block: {:.1f} s for all (estimate)", a.every, best * a.every) : "");
  std::string mem;
  for (std::size_t k = 0; k < rss.size(); ++k) mem += fmt::format("{}rank {} {:.0f} MB", k ? ", " : "", k, rss[k] / 1e6);
  std::cout << "  peak resident memory: " << mem << "\n"
            << fmt::format("  max |C| {:.17g}, Frobenius norm {:.17g}\n", max_abs, std::sqrt(norm));
}

void add_streaming(CLI::App& bench) {
  auto a = std::make_shared<StreamArgs>();
  auto* cmd = bench.add_subcommand("streaming", "Time the streaming projection of one material (distributed under mpirun)");
  cmd->add_option("source", a->source, "SOURCE that is projected by streaming (a model, an RGL material, a half-angle material)")
      ->capture_default_str();
  cmd->add_option("--level,-l", a->level, "Tessellation level")->capture_default_str()->check(CLI::Range(0, 8));
  cmd->add_option("--order,-n", a->order, "Expansion order")->capture_default_str()->check(CLI::Range(0, 128));
  cmd->add_option("--sampling", a->sampling, "LUT sampling: average (cell cubature, as fit) or centre")->capture_default_str();
  cmd->add_flag("--cosine", a->cosine, "Project g = f cos(theta_i)");
  cmd->add_option("--every", a->every, "Project only every K-th block of incident rows (times K estimates the whole; the matrices are not C)")
      ->capture_default_str()->check(CLI::Range(1, 1000000));
  cmd->add_option("--repeat", a->repeat, "Timed projections (the best is reported)")->capture_default_str()->check(CLI::Range(1, 100));
  cmd->add_flag("--json", a->json, "JSON: projection_seconds, context_seconds, peak_rss_bytes_per_rank, ...");
  cmd->callback([a] { run_distributed("bench streaming", a->repeat, [a](const DistributedRun& run) { run_streaming(*a, run); }); });
}

const BenchRegistrar kRegistrar("streaming", add_streaming);

}  // namespace
}  // namespace icobrdf::cli
