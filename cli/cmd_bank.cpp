// icobrdf bank build SCENE.toml -o BANK.h5 [--resume] [--json]
// icobrdf bank info BANK.h5 [--json]
// icobrdf bank extract BANK.h5#MATERIAL -o SPECTRUM.h5
#include <fmt/core.h>

#include <csignal>
#include <iostream>
#include <memory>
#include <optional>

#include "cli/commands.hpp"
#include "cli/error_report.hpp"
#include "cli/exit_codes.hpp"
#include "icobrdf/cluster/launcher.hpp"
#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/support/progress.hpp"
#include "icobrdf/io/bank_file.hpp"
#include "icobrdf/io/bank_summary.hpp"
#include "icobrdf/io/program_end.hpp"
#include "icobrdf/io/scene.hpp"
#include "icobrdf/pipeline/bank_builder.hpp"
#include "icobrdf/pipeline/bank_report.hpp"
#ifdef ICOBRDF_WITH_MPI
#include "icobrdf/cluster/distributed_bank.hpp"
#include "icobrdf/cluster/distributed_run.hpp"
#else
namespace icobrdf {
class Cluster;  // the ranks of an mpirun job: only in a build with MPI
}
#endif

namespace icobrdf::cli {
namespace {

struct BuildArgs {
  std::string scene, output;
  bool resume = false, json = false, quiet = false, strict = false;
  int materials_at_once = 0;
};

// Exit code of a build that ended without error: 0, or the signal's conventional code. `cluster`: the ranks
// of an mpirun job, null in one process (always null in a build without MPI).
int build_and_report(const BuildArgs& a, [[maybe_unused]] Cluster* cluster) {
#ifdef ICOBRDF_WITH_MPI
  const std::optional<Scene> read = cluster ? read_scene_on_every_rank(a.scene, *cluster) : read_scene(a.scene);
  if (!read) return kExitOk;  // another rank could not read the scene and says so
  const Scene& scene = *read;
#else
  if (launcher_world_size() > 1)
    throw UnsupportedError(fmt::format("bank build: started by mpirun with {} processes, but this icobrdf was built without MPI "
                                       "(every process would build the whole bank); install libopenmpi-dev and rebuild, or run it without mpirun",
                                       launcher_world_size()));
  const Scene scene = read_scene(a.scene);
#endif
  std::atomic<int>& stop_signal = record_stop_signals();
  BankBuildOptions o;
  o.output = a.output;
  o.resume = a.resume;
  o.stop = &stop_signal;
  o.strict = a.strict;
  o.materials_at_once = a.materials_at_once;
  o.warnings = &std::cerr;
  // One write per line (cerr is unbuffered): under mpirun rank 0's lines and the other ranks' warnings share
  // one merged stream, and a line written in two pieces could take another rank's line into its middle.
  if (!a.quiet) o.progress = [](const std::string& line) { std::cerr << (line + "\n") << std::flush; };
  if (a.quiet) set_progress_stream(nullptr);  // no lines from long projections either (icobrdf/core/support/progress.hpp)
#ifdef ICOBRDF_WITH_MPI
  BankBuildResult r;
  if (cluster) {
    if (cluster->rank() != 0) set_progress_stream(nullptr);  // progress lines from rank 0 only
    auto d = build_bank_distributed(scene, o, *cluster);
    if (d.worker) return kExitOk;  // rank 0 reports and writes
    r = std::move(d.build);
  } else {
    r = build_bank(scene, o);
  }
#else
  const auto r = build_bank(scene, o);
#endif
  if (a.json) {
    std::cout << bank_build_json(r, a.scene, a.output).dump(2) << "\n";
  } else {
    std::cout << bank_build_table(r, a.output);
  }
  if (r.interrupted) {
    std::cerr << fmt::format("icobrdf: interrupted; {}\n", kept_for_resume(r));
    return stop_signal.load() == SIGTERM ? kExitTerminated : kExitInterrupted;
  }
  if (!r.written) throw UnsupportedError(bank_not_written_message(r));
  if (const std::size_t missed = targets_missed(r); missed > 0) {
    std::cerr << fmt::format("icobrdf: {}; exit {}\n", targets_missed_message(missed), kExitTargetsMissed);
    return kExitTargetsMissed;
  }
  return kExitOk;
}

int run_build(const BuildArgs& a) {
#ifdef ICOBRDF_WITH_MPI
  std::unique_ptr<Cluster> cluster;
  if (started_by_mpirun()) cluster = start_cluster();
  try {
    return build_and_report(a, cluster.get());
  } catch (...) {
    if (!cluster) throw;
    // Printed while `cluster` lives: its destructor waits for every rank, so this line is out before any
    // rank ends (mpirun stops the whole job when one rank exits non-zero; cli/error_report.hpp).
    print_now(std::current_exception());
  }
#else
  return build_and_report(a, nullptr);
#endif
}

void run_info(const std::string& path, bool json) {
  const BankContents b = read_bank(path, ReadOptions{.read_luts = false});
  std::cout << (json ? bank_summary_json(b, path).dump(2) + "\n" : bank_summary_text(b, path));
}

void add_bank_command(CLI::App& app) {
  auto* bank = app.add_subcommand("bank", "Build, inspect and extract LUT banks (HDF5)");
  bank->require_subcommand(1);
  auto a = std::make_shared<BuildArgs>();
  auto* build = bank->add_subcommand("build", "Build a bank from a scene: per material the smallest level and order meeting its target");
  build->add_option("scene", a->scene, "SCENE.toml (see examples/default-scene.toml)")->required()->check(CLI::ExistingFile);
  build->add_option("-o,--output", a->output, "Output bank (.h5)")->required();
  build->add_flag("--resume", a->resume, "Keep the materials finished by an interrupted build");
  build->add_flag("--strict", a->strict, "A material with negative reflectance fails (default: a warning)");
  build->add_flag("--json", a->json, "Print the per-material choices as JSON");
  build->add_flag("--quiet,-q", a->quiet, "No progress lines on stderr");
  build->add_option("--materials-at-once", a->materials_at_once,
                    "Small materials fitted at once, each on its share of the threads (0: chosen from the threads and memory; 1: one at a time)")
      ->check(CLI::Range(0, 4096));
  build->callback([a] {
    const int code = run_build(*a);
    if (code != kExitOk) throw CLI::RuntimeError(code);
  });
  auto info_path = std::make_shared<std::string>();
  auto info_json = std::make_shared<bool>(false);
  auto* info = bank->add_subcommand("info", "Describe a bank: grid, operators and materials");
  info->add_option("bank", *info_path, "BANK.h5")->required();
  info->add_flag("--json", *info_json, "JSON output");
  info->callback([info_path, info_json] { run_info(*info_path, *info_json); });
  auto ex_spec = std::make_shared<std::string>(), ex_out = std::make_shared<std::string>();
  auto* ex = bank->add_subcommand("extract", "Copy one material of a bank into a file of its own");
  ex->add_option("material", *ex_spec, "BANK.h5#MATERIAL")->required();
  ex->add_option("-o,--output", *ex_out, "Output file (.h5)")->required();
  ex->callback([ex_spec, ex_out] { extract_bank_material(*ex_spec, *ex_out); });
}

const CommandRegistrar kCmdBankRegistrar("bank", add_bank_command);

}  // namespace
}  // namespace icobrdf::cli
