// icobrdf bank build SCENE.toml -o BANK.h5 [--resume] [--json]
// icobrdf bank info BANK.h5 [--json]
// icobrdf bank extract BANK.h5#MATERIAL -o SPECTRUM.h5
#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <atomic>
#include <cmath>
#include <csignal>
#include <iostream>
#include <memory>
#include <optional>

#include "cli/commands.hpp"
#include "cli/distributed_run.hpp"
#include "cli/error_report.hpp"
#include "cli/exit_codes.hpp"
#include "icobrdf/cluster/launcher.hpp"
#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/support/progress.hpp"
#include "icobrdf/io/bank_file.hpp"
#include "icobrdf/io/half_angle_file.hpp"
#include "icobrdf/io/scene.hpp"
#include "icobrdf/pipeline/bank_builder.hpp"
#ifdef ICOBRDF_WITH_MPI
#include "icobrdf/cluster/distributed_bank.hpp"
#else
namespace icobrdf {
class Cluster;  // the ranks of an mpirun job: only in a build with MPI
}
#endif

namespace icobrdf::cli {
namespace {

// Share of the reference's squared norm from grazing pairs above which the report notes that they decide a
// material's "f" error (more than half of it).
constexpr double kGrazingDominates = 0.5;

std::atomic<int> g_stop_signal{0};
extern "C" void on_stop_signal(int sig) { g_stop_signal.store(sig); }

struct BuildArgs {
  std::string scene, output;
  bool resume = false, json = false, quiet = false, strict = false;
  int materials_at_once = 0;
};

#ifdef ICOBRDF_WITH_MPI
// Under mpirun: the scene is read on every rank; a rank that cannot read it ends the job on every rank
// (nullopt: another rank failed, this one ends quietly).
std::optional<Scene> read_scene_on_every_rank(const std::string& path, Cluster& cluster) {
  Scene scene;
  std::exception_ptr error;
  try {
    scene = read_scene(path);
  } catch (...) {
    error = std::current_exception();
  }
  const int failed = cluster.first_failed(!error);
  if (error) std::rethrow_exception(error);
  if (failed >= 0 && cluster.rank() == 0)
    throw InputError(fmt::format("{}: rank {} could not read the scene (see its message)", path, failed));
  if (failed >= 0) return std::nullopt;
  return scene;
}
#endif

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
  struct sigaction sa {};
  sa.sa_handler = on_stop_signal;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
  BankBuildOptions o;
  o.output = a.output;
  o.resume = a.resume;
  o.stop = &g_stop_signal;
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
  nlohmann::json mats = nlohmann::json::array();
  for (const auto& m : r.materials) {
    nlohmann::json j{{"name", m.name}, {"source", m.source}, {"ok", m.ok}, {"resumed", m.resumed}};
    if (m.rank >= 0) j["rank"] = m.rank;  // under mpirun: the rank that fitted it
    if (!m.ok) {
      j["error"] = m.error;
    } else {
      j.update({{"representation", m.representation}, {"isotropic", m.isotropic}, {"level", m.level}, {"order", m.order}, {"target", m.target},
                {"error_measured", m.measured}, {"error_l2", m.measured ? nlohmann::json(m.error_l2) : nlohmann::json()},
                {"error_max", m.measured ? nlohmann::json(m.error_max) : nlohmann::json()}, {"metric", m.metric},
                {"asymmetry", m.measured && std::isfinite(m.asymmetry) ? nlohmann::json(m.asymmetry) : nlohmann::json()},
                {"judged_against", m.reciprocal_reference ? "reciprocal part" : "data"},
                {"grazing_share", m.measured ? nlohmann::json(m.grazing_share) : nlohmann::json()}, {"anisotropy", m.anisotropy},
                {"kept_coefficients", m.kept}, {"total_coefficients", m.total}, {"bytes", m.bytes}, {"seconds", m.seconds},
                {"target_met", m.target_met}, {"max_bytes", m.max_bytes >= 0 ? nlohmann::json(m.max_bytes) : nlohmann::json()}});
    }
    mats.push_back(j);
  }
  if (a.json) {
    std::cout << nlohmann::json{{"scene", a.scene}, {"output", a.output}, {"written", r.written}, {"interrupted", r.interrupted},
                                {"resume_file", r.resume_file}, {"materials", mats}}
                     .dump(2)
              << "\n";
  } else {
    std::cout << fmt::format("{:<18} {:<10} {:>4} {:>5} {:>5} {:>9} {:>4} {:>9} {:>9} {:>9} {:>11} {:>8} {:>7}\n", "material", "repr", "iso",
                             "level", "order", "target", "met", "rel L2", "rel max", "asym", "kept/total", "bytes", "seconds");
    for (const auto& m : r.materials) {
      if (!m.ok) {
        std::cout << fmt::format("{:<18} FAILED{}: {}\n", m.name, m.rank >= 0 ? fmt::format(" on rank {}", m.rank) : "", m.error);
        continue;
      }
      const std::string l2 = m.measured ? fmt::format("{:.3g}", m.error_l2) : "n/a", mx = m.measured ? fmt::format("{:.3g}", m.error_max) : "n/a";
      const std::string asym = m.measured && std::isfinite(m.asymmetry) ? fmt::format("{:.3g}", m.asymmetry) : "n/a";
      const auto dash = [](int v) { return v < 0 ? std::string("-") : std::to_string(v); };  // no modes: a lobe alone
      const char* met = !m.measured ? "n/a" : m.target_met ? "yes" : "NO";
      std::cout << fmt::format("{:<18} {:<10} {:>4} {:>5} {:>5} {:>9.3g} {:>4} {:>9} {:>9} {:>9} {:>11} {:>8} {:>7.2f}{}\n", m.name,
                               m.representation, m.isotropic ? "yes" : "no", dash(m.level), dash(m.order), m.target, met, l2, mx, asym, fmt::format("{}/{}", m.kept, m.total), m.bytes, m.seconds,
                               m.resumed ? " (resumed)" : "");
    }
    for (const auto& m : r.materials)
      if (m.ok && m.measured && m.reciprocal_reference && m.target < m.asymmetry)
        std::cout << fmt::format("note: {}: target {:.3g} is below the data's own asymmetry {:.3g}: the error is against their reciprocal part "
                                 "(f + f^T)/2; against the raw data no reciprocal BRDF comes closer than {:.3g}\n",
                                 m.name, m.target, m.asymmetry, m.asymmetry);
    for (const auto& m : r.materials)
      if (m.ok && m.measured && m.metric == "f" && m.grazing_share > kGrazingDominates)
        std::cout << fmt::format("note: {}: {:.0f}% of the reference's norm is from pairs beyond 80 deg, which metric \"f\" weighs fully "
                                 "and a renderer scales by cos theta < 0.17 (metric \"cosine\" is the default)\n",
                                 m.name, 100 * m.grazing_share);
    if (r.written) std::cout << fmt::format("wrote {}\n", a.output);
  }
  if (r.interrupted) {
    std::cerr << fmt::format("icobrdf: interrupted; {}\n", kept_for_resume(r));
    return g_stop_signal.load() == SIGTERM ? kExitTerminated : kExitInterrupted;
  }
  if (!r.written) {
    size_t failed = 0;
    const MaterialReport* first = nullptr;
    for (const auto& m : r.materials) {
      failed += !m.ok;
      if (!m.ok && !first) first = &m;
    }
    // Under mpirun the line names the first failed material and its rank (a long build's table is far above).
    const std::string which = first && first->rank >= 0 ? fmt::format("material '{}' failed on rank {}: {}; ", first->name, first->rank, message_line(first->error)) : "";
    throw UnsupportedError(fmt::format("bank not written: {}{} material(s) failed (see above); {}", which, failed, kept_for_resume(r)));
  }
  std::size_t missed = 0;
  for (const auto& m : r.materials) missed += m.ok && !m.target_met;
  if (missed > 0) {
    std::cerr << fmt::format("icobrdf: {} material(s) missed their target and were written with the lowest error within their "
                             "max_bytes (on_miss = \"keep-best\"); exit {}\n", missed, kExitTargetsMissed);
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
  nlohmann::json mats = nlohmann::json::array();
  for (const auto& m : b.materials) {
    nlohmann::json j{{"name", m.name}, {"source", m.spectrum.source}, {"order", m.spectrum.order}, {"isotropic", m.spectrum.isotropic},
                     {"cosine", m.spectrum.cosine}, {"channels", m.spectrum.channel_count()}, {"level", m.spectrum.level},
                     {"grid", m.spectrum.grid_kind}, {"has_lut", !m.lut.empty() || m.lut_float32},
                     {"representation", representation_name(m)}};
    if (m.lobe) j["half_angle"] = half_angle_summary(*m.lobe);
    for (const auto& [k, v] : m.figures) j[k] = v;
    for (const auto& [k, v] : m.labels) j[k] = v;
    mats.push_back(j);
  }
  nlohmann::json j{{"file", path}, {"format_version", b.format_version}, {"creator", b.creator}, {"created", b.created},
                   {"grid", b.grid ? nlohmann::json{{"kind", to_string(b.grid->kind)}, {"level", b.grid->level}, {"cells", b.grid->cells()}} : nlohmann::json()},
                   {"materials", mats}};
  nlohmann::json basis = nlohmann::json::array();
  for (const auto& a : b.basis) basis.push_back(a.path);
  j["basis"] = basis;
  if (json) {
    std::cout << j.dump(2) << "\n";
    return;
  }
  std::cout << fmt::format("{}: icobrdf bank {} by {}, created {}\n", path, b.format_version, b.creator, b.created);
  if (b.grid) std::cout << fmt::format("  grid: {} level {} ({} cells)\n", to_string(b.grid->kind), b.grid->level, b.grid->cells());
  std::cout << fmt::format("  basis arrays: {}\n", b.basis.size());
  for (const auto& m : b.materials) {
    std::cout << fmt::format("  {:<18} order {:>2} {:<11} {} channel(s)  {}\n", m.name, m.spectrum.order, m.spectrum.isotropic ? "isotropic" : "anisotropic",
                             m.spectrum.channel_count(), m.spectrum.source);
    if (m.lobe) std::cout << fmt::format("  {:<18} {}: {}\n", "", representation_name(m), half_angle_summary_line(*m.lobe));
  }
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
