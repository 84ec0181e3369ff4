// icobrdf bench measured FILE.bsdf|FOLDER... [--nbrdf DIR] [--target T] [--representations half-angle,hybrid]
//                        [--pairs N] [--materials-at-once W] [--no-small-lobes] [--no-bank] [--budgets B,...] [--quiet] --report DIR
// Real measured materials (RGL .bsdf files; a folder stands for its *.bsdf files) through the bank builder,
// beside small half-angle lobes within byte budgets and the released Neural-BRDF networks
// (icobrdf/lab/measured_benchmark.hpp). Writes DIR/report.md, DIR/error-vs-bytes.png and, as the work of the
// run, DIR/measured-scene.toml and DIR/measured-bank.h5.
#include <iostream>
#include <memory>

#include "cli/bench_commands.hpp"
#include "icobrdf/core/support/error.hpp"
#include "icobrdf/lab/measured_benchmark.hpp"

namespace icobrdf::cli {
namespace {

struct MeasuredArgs {
  std::vector<std::string> inputs, representations{"half-angle", "hybrid"};
  std::string nbrdf, report;
  double target = 0.02;
  int pairs = 20000, materials_at_once = 0;
  bool quiet = false, no_small = false, no_bank = false;
  std::vector<long long> budgets;
};

void run_measured(const MeasuredArgs& a) {
  lab::MeasuredBenchOptions o;
  o.files = lab::bsdf_files(a.inputs);
  o.nbrdf_dir = a.nbrdf;
  o.work_dir = a.report;
  o.target = a.target;
  o.representations = a.representations;
  o.pairs = a.pairs;
  o.materials_at_once = a.materials_at_once;
  o.small_lobes = !a.no_small;
  o.bank = !a.no_bank;
  if (!a.budgets.empty()) o.budgets = a.budgets;
  if (!a.quiet) o.progress = [](const std::string& line) { std::cerr << line << std::endl; };
  std::cout << lab::write_measured_report(lab::run_measured_bench(o), a.report);
}

void add_measured(CLI::App& bench) {
  auto a = std::make_shared<MeasuredArgs>();
  auto* cmd = bench.add_subcommand("measured", "Measured RGL materials: the bank's representations, small lobes and NBRDF, error against bytes");
  cmd->add_option("inputs", a->inputs, "RGL .bsdf files or folders of them")->required();
  cmd->add_option("--nbrdf", a->nbrdf, "Folder of NBRDF networks named <file stem>.h5 (Sztrajman et al. 2021)");
  cmd->add_option("--target", a->target, "Target of the bank (cosine metric)")->capture_default_str()->check(CLI::PositiveNumber);
  cmd->add_option("--representations", a->representations, "Representations the bank tries")->delimiter(',')->capture_default_str();
  cmd->add_option("--pairs", a->pairs, "Test pairs per material")->capture_default_str()->check(CLI::Range(100, 10000000));
  cmd->add_option("--materials-at-once", a->materials_at_once, "As bank build --materials-at-once (0 chooses)")->check(CLI::NonNegativeNumber);
  cmd->add_flag("--no-small-lobes", a->no_small, "Skip the small lobes within byte budgets");
  cmd->add_flag("--no-bank", a->no_bank, "Skip the bank build (small lobes and NBRDF only)");
  cmd->add_option("--budgets", a->budgets, "Byte budgets of the small lobes (default 1350,2700,5400,10800,21600,43200,65536)")->delimiter(',');
  cmd->add_flag("--quiet,-q", a->quiet, "No progress lines on stderr");
  cmd->add_option("--report", a->report, "Folder for report.md, the figure, the scene and the bank (created if missing)")->required();
  cmd->callback([a] { run_measured(*a); });
}

const BenchRegistrar kBenchMeasuredRegistrar("measured", add_measured);

}  // namespace
}  // namespace icobrdf::cli
