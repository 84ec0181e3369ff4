// icobrdf bench streaming [SOURCE] --level L --order N [--sampling average|centre] [--cosine] [--every K] [--repeat R]
//                         [-o SPECTRUM.h5] [--json]
// Times the streaming projection of one material (C = P^T F P without its LUT, icobrdf/core/projection/streaming_projection.hpp),
// the fit `icobrdf fit` makes, apart from building the grid and the operators. Under `mpirun -np R` the
// projection is spread over the ranks (cli/distributed_run.hpp) and the report, from rank 0, gives the
// peak resident memory of every rank. The ranks split the operators by rows, as `fit` does (memory per rank
// O(cells x modes / ranks), icobrdf/core/projection/row_split_projection.hpp); the report says so ("operators").
// Default SOURCE: model:ggx:alpha=0.1 (issue #18's level-7 case).
// --every K projects only every K-th block of incident rows (one process: icobrdf/core/projection/streaming_projection.hpp
// StreamingShare::every; under mpirun: every K-th batch of each pair of blocks, row_split_projection's
// `every`), with every array at full size: the time of a projection too long to run whole (times K) and its
// memory.
#include <fmt/core.h>
#include <nlohmann/json.hpp>
#include <omp.h>
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "cli/bench_commands.hpp"
#include "cli/distributed_run.hpp"
#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/basis/hemisphere_basis.hpp"
#include "icobrdf/io/brdf_source.hpp"
#include "icobrdf/io/output_path.hpp"
#include "icobrdf/io/spectrum_file.hpp"
#include "icobrdf/pipeline/fit_source.hpp"

namespace icobrdf::cli {
namespace {

// StreamingShare::every beyond any projection's blocks (level 8: 5,124 blocks): block 0 alone.
constexpr int kOneBlock = 1 << 30;

struct StreamArgs {
  std::string source = "model:ggx:alpha=0.1", sampling = "average", output;
  int level = 4, order = 8, repeat = 1, every = 1;
  bool cosine = false, json = false;
};

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// CPU seconds of this process so far, all threads (user + system).
double process_cpu_seconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) + 1e-6 * static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

void run_streaming(const StreamArgs& a, const DistributedRun& run) {
  FitRequest r;
  r.level = a.level;
  r.order = a.order;
  r.cosine = a.cosine;
  r.share = run.share;
  const auto sampling = lut_sampling_named(a.sampling);
  if (!sampling) throw ArgumentError("--sampling: expected 'average' or 'centre', found '" + a.sampling + "'");
  r.sampling = *sampling;
  const auto source = open_source(a.source);
  if (run.writes() && !a.output.empty()) check_output_path(a.output, {a.source});
  run.setup_done();
  FitContexts contexts;
  const auto t0 = std::chrono::steady_clock::now();
  const auto ctx = contexts.context(r);
  const double context_seconds = seconds_since(t0);
  // With --every K: a fraction of the blocks (StreamingShare::every), for the time and the memory of a
  // projection too long to run whole; the matrices are not C. The costs that do not grow with the blocks
  // (P reordered for the triangle, the fit's albedo figure) are timed apart, by a projection of block 0
  // alone (every = a number beyond the blocks), so that the whole is estimated as fixed + K (t - fixed).
  const auto with_every = [&](int every) {
    auto s = run.share ? std::make_shared<StreamingShare>(*run.share) : std::make_shared<StreamingShare>();
    s->every = every;
    return s;
  };
  double fixed = 0.0;
  if (a.every > 1) {
    FitRequest one_block = r;
    one_block.share = with_every(kOneBlock);
    const auto t1 = std::chrono::steady_clock::now();
    fit_source(*source, one_block, contexts);
    fixed = seconds_since(t1);
    r.share = with_every(a.every);
  }
  std::vector<double> times;
  Spectrum s;
  const double cpu0 = process_cpu_seconds();
  for (int k = 0; k < a.repeat; ++k) {
    const auto t1 = std::chrono::steady_clock::now();
    s = fit_source(*source, r, contexts).spectrum;
    times.push_back(seconds_since(t1));
  }
  // Per projection, on every rank: the work a rank did, which a loaded machine does not inflate as it
  // does the wall time (waiting for the other ranks costs no CPU: ranks wait by polling with sleeps).
  const std::vector<double> cpu = run.gather((process_cpu_seconds() - cpu0) / a.repeat);
  if (run.exchanges() == 0 && run.ranks > 1)
    throw UnsupportedError("bench streaming: " + quoted_text(a.source) + " is not fitted by streaming projection (samples or stored modes)");
  const std::vector<double> rss = run.gather(peak_resident_bytes());
  if (!run.writes()) return;
  if (!a.output.empty()) write_spectrum_file(a.output, s, nullptr, "material");
  double max_abs = 0.0, norm = 0.0;
  for (const auto& c : s.channels) {
    max_abs = std::max(max_abs, c.cwiseAbs().maxCoeff());
    norm += c.squaredNorm();
  }
  const double best = *std::min_element(times.begin(), times.end());
  const std::string operators = run.ranks == 1 ? "whole (one process)" : run.share && run.share->rows ? "split by rows" : "whole on every rank";
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
                         {"operators", operators},
                         {"projection_seconds_fixed", fixed},
                         {"projection_seconds_whole_estimate", fixed + a.every * (best - fixed)},
                         {"context_seconds", context_seconds},
                         {"projection_seconds", best},
                         {"projection_seconds_all", times},
                         {"peak_rss_bytes_per_rank", rss},
                         {"projection_cpu_seconds_per_rank", cpu},
                         {"max_abs_coefficient", max_abs},
                         {"frobenius_norm", std::sqrt(norm)}};
  if (a.json) {
    std::cout << j.dump(2) << "\n";
    return;
  }
  std::cout << fmt::format("streaming projection of {}: level {} ({} cells), order {} ({} modes), {} channel(s), {} sampling{}\n", s.source,
                           a.level, ctx->grid->cells(), s.order, s.modes(), s.channel_count(), a.sampling, s.cosine ? ", g form" : "")
            << fmt::format("  {} rank(s) x {} thread(s), operators {}; grid and operators {:.3f} s; projection {:.3f} s (best of {}){}\n", run.ranks,
                           omp_get_max_threads(), operators, context_seconds, best, a.repeat,
                           a.every > 1 ? fmt::format(" for 1 block in {} ({:.1f} s of it fixed): {:.1f} s for all (estimate)", a.every, fixed,
                                                     fixed + a.every * (best - fixed)) : "");
  std::string mem;
  for (std::size_t k = 0; k < rss.size(); ++k) mem += fmt::format("{}rank {} {:.0f} MB", k ? ", " : "", k, rss[k] / 1e6);
  std::string work;
  for (std::size_t k = 0; k < cpu.size(); ++k) work += fmt::format("{}rank {} {:.2f} s", k ? ", " : "", k, cpu[k]);
  std::cout << "  CPU time of one projection: " << work << "\n"
            << "  peak resident memory: " << mem << "\n"
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
  cmd->add_option("-o,--output", a->output, "Also write the spectrum (with --every K, of those blocks only), to compare runs");
  cmd->add_flag("--json", a->json, "JSON: projection_seconds, context_seconds, peak_rss_bytes_per_rank, ...");
  cmd->callback([a] {
    const int projections = a->repeat + (a->every > 1 ? 1 : 0);
    // Under mpirun the ranks split the operators by rows, as `fit` does (with --every K too).
    run_distributed("bench streaming", projections, [a](const DistributedRun& run) { run_streaming(*a, run); }, true);
  });
}

const BenchRegistrar kBenchStreamingRegistrar("streaming", add_streaming);

}  // namespace
}  // namespace icobrdf::cli
