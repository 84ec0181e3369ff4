// icobrdf modes: values of the hemisphere basis K_j, the general Helmholtz modes or the isotropic modes
// up to a total order, at directions or direction pairs read from CSV (degrees, header row).
//
//   icobrdf modes --order N [--isotropic] --at PAIRS.csv [--json]     rows theta_i,phi_i,theta_r,phi_r
//   icobrdf modes --order N --hemisphere --at DIRS.csv [--json]       rows theta,phi
//
// Text output: a comment line, then CSV in long form, one line per (row, mode):
//   row,n,l,m,lp,value (general) | row,n,m,l,value (isotropic) | row,n,l,value (hemisphere)
// with row the 0-based data row of the input. JSON output:
//   {"order": N, "isotropic": bool, "hemisphere": bool, "indices": [[...], ...], "values": [[...], ...]}
// indices [n,l,m,l'] (general, library order), [n,m,l] (isotropic, Table 2 order) or [n,l] (ANSI order);
// values: one list per input row, one number per mode [1/sr for modes, 1/sqrt(sr) for K].
#include <fmt/core.h>

#include <iostream>
#include <memory>
#include <string>

#include "cli/commands.hpp"
#include "icobrdf/io/mode_table.hpp"

namespace icobrdf::cli {

namespace {

struct ModesOptions {
  int order = -1;
  bool isotropic = false;
  bool hemisphere = false;
  bool json = false;
  std::string at;
};

void run_modes(const ModesOptions& o) {
  const ModeFamily family = o.hemisphere ? ModeFamily::Hemisphere : o.isotropic ? ModeFamily::Isotropic : ModeFamily::Helmholtz;
  const ModeTable table = mode_table(family, o.order, o.at);
  const Eigen::MatrixXd& values = table.values;
  const std::vector<std::vector<int>>& idx = table.indices;
  if (o.json) {
    std::cout << mode_table_json(table, family, o.order).dump() << "\n";
    return;
  }
  const char* kind = o.hemisphere ? "hemisphere basis K" : (o.isotropic ? "isotropic modes I" : "Helmholtz modes H");
  const char* header = o.hemisphere ? "row,n,l,value" : (o.isotropic ? "row,n,m,l,value" : "row,n,l,m,lp,value");
  std::string out = fmt::format("# icobrdf modes: {} up to order {}, {} per row, {} rows\n{}\n", kind, o.order,
                                values.cols(), values.rows(), header);
  for (Eigen::Index r = 0; r < values.rows(); ++r)
    for (Eigen::Index c = 0; c < values.cols(); ++c) {
      out += std::to_string(r);
      for (int v : idx[static_cast<size_t>(c)]) out += "," + std::to_string(v);
      out += fmt::format(",{:.17g}\n", values(r, c));
      if (out.size() > (1u << 20)) {
        std::cout << out;
        out.clear();
      }
    }
  std::cout << out;
}

void add_modes_command(CLI::App& app) {
  auto opts = std::make_shared<ModesOptions>();
  auto* cmd = app.add_subcommand(
      "modes", "Values of every mode up to a total order at direction pairs (or of K_j at directions)");
  cmd->add_option("--order", opts->order, "Total order N, 0..128")->required()->check(CLI::Range(0, 128));
  auto* iso = cmd->add_flag("--isotropic", opts->isotropic, "Isotropic modes I_nm^l (Table 2 order)");
  auto* hemi = cmd->add_flag("--hemisphere", opts->hemisphere,
                             "Hemisphere basis K_n^l at directions theta,phi (ANSI order)");
  iso->excludes(hemi);
  cmd->add_option("--at", opts->at,
                  "CSV with header: theta_i,phi_i,theta_r,phi_r (or theta,phi with --hemisphere), degrees")
      ->required();
  cmd->add_flag("--json", opts->json, "Machine-readable output");
  cmd->callback([opts] { run_modes(*opts); });
}

const CommandRegistrar kCmdModesRegistrar("modes", add_modes_command);

}  // namespace
}  // namespace icobrdf::cli
