// icobrdf bench streaming [SOURCE] --level L --order N [--sampling average|centre] [--cosine] [--every K] [--repeat R]
//                         [-o SPECTRUM.h5] [--json]
// Times the streaming projection of one material (C = P^T F P without its LUT, icobrdf/core/projection/streaming_projection.hpp),
// the fit `icobrdf fit` makes, apart from building the grid and the operators. Under `mpirun -np R` the
// projection is spread over the ranks (icobrdf/cluster/distributed_run.hpp) and the report, from rank 0, gives the
// peak resident memory of every rank. The ranks split the operators by rows, as `fit` does (memory per rank
// O(cells x modes / ranks), icobrdf/core/projection/row_split_projection.hpp); the report says so ("operators").
// Default SOURCE: model:ggx:alpha=0.1 (issue #18's level-7 case).
// --every K projects only every K-th block of incident rows (icobrdf/lab/streaming_benchmark.hpp; under mpirun: every K-th batch of each
// pair of blocks, row_split_projection's `every`).
#include <fmt/core.h>
#include <omp.h>

#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "cli/bench_commands.hpp"
#include "cli/error_report.hpp"
#include "icobrdf/core/support/error.hpp"
#include "icobrdf/io/brdf_source.hpp"
#include "icobrdf/io/output_path.hpp"
#include "icobrdf/io/spectrum_file.hpp"
#include "icobrdf/lab/process_usage.hpp"
#include "icobrdf/lab/streaming_benchmark.hpp"
#include "icobrdf/pipeline/fit_source.hpp"

namespace icobrdf::cli {
namespace {

struct StreamArgs {
  std::string source = "model:ggx:alpha=0.1", sampling = "average", output;
  int level = 4, order = 8, repeat = 1, every = 1;
  bool cosine = false, json = false;
};

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
  const lab::StreamingBenchmark b = lab::measure_streaming(*source, r, a.every, a.repeat);
  lab::StreamingRanks ranks;
  ranks.cpu_seconds = run.gather(b.cpu_seconds_per_projection);  // collective
  if (run.exchanges() == 0 && run.ranks > 1)
    throw UnsupportedError("bench streaming: " + quoted_text(a.source) + " is not fitted by streaming projection (samples or stored modes)");
  ranks.peak_rss_bytes = run.gather(lab::peak_resident_bytes());
  if (!run.writes()) return;
  if (!a.output.empty()) write_spectrum_file(a.output, b.spectrum, nullptr, "material");
  ranks.ranks = run.ranks;
  ranks.threads_per_rank = omp_get_max_threads();
  ranks.operators = run.ranks == 1 ? "whole (one process)" : run.share && run.share->rows ? "split by rows" : "whole on every rank";
  if (a.json)
    std::cout << lab::streaming_report(b, a.level, a.sampling, ranks).dump(2) << "\n";
  else
    std::cout << lab::streaming_text(b, a.level, a.sampling, a.repeat, a.every, ranks);
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
    run_distributed("bench streaming", projections, [a](const DistributedRun& run) { run_streaming(*a, run); }, true,
                    rank_errors());
  });
}

const BenchRegistrar kBenchStreamingRegistrar("streaming", add_streaming);

}  // namespace
}  // namespace icobrdf::cli
