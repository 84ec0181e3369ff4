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
#include <nlohmann/json.hpp>

#include <iostream>
#include <memory>
#include <string>

#include "cli/commands.hpp"
#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/basis/helmholtz_modes.hpp"
#include "icobrdf/core/basis/hemisphere_basis.hpp"
#include "icobrdf/core/basis/isotropic_modes.hpp"
#include "icobrdf/core/basis/zernike.hpp"
#include "icobrdf/io/direction_csv.hpp"

namespace icobrdf::cli {

namespace {

// Output larger than this many numbers (rows x modes) is refused: the general modes grow as N^4
// (35 million per row at order 128).
constexpr long long kMaxOutputValues = 20'000'000;

struct ModesOptions {
  int order = -1;
  bool isotropic = false;
  bool hemisphere = false;
  bool json = false;
  std::string at;
};

void check_size(long long rows, long long modes, int order) {
  if (rows * modes > kMaxOutputValues)
    throw UnsupportedError(fmt::format("modes: {} rows x {} modes at order {} = {} values exceeds the supported {}",
                                       rows, modes, order, rows * modes, kMaxOutputValues));
}

void run_modes(const ModesOptions& o) {
  if (o.order < 0 || o.order > kMaxZernikeOrder)
    throw ArgumentError(fmt::format("modes: --order must be in [0, {}], got {}", kMaxZernikeOrder, o.order));
  Eigen::MatrixXd values;
  nlohmann::json indices = nlohmann::json::array();
  std::vector<std::vector<int>> idx;
  if (o.hemisphere) {
    const RowMatrix3d dirs = read_directions_csv(o.at);
    check_size(dirs.rows(), hemisphere_basis_count(o.order), o.order);
    values = hemisphere_basis_matrix(o.order, dirs);
    for (int j = 0; j < values.cols(); ++j) {
      const auto k = ansi_to_nl(j);
      idx.push_back({k.n, k.l});
    }
  } else {
    const DirectionPairs pairs = read_direction_pairs_csv(o.at);
    if (o.isotropic) {
      check_size(pairs.wi.rows(), isotropic_mode_count(o.order), o.order);
      values = isotropic_modes_eval(o.order, pairs.wi, pairs.wr);
      for (const auto& k : isotropic_modes(o.order)) idx.push_back({k.n, k.m, k.l});
    } else {
      check_size(pairs.wi.rows(), helmholtz_mode_count(o.order), o.order);
      values = helmholtz_modes_eval(o.order, pairs.wi, pairs.wr);
      for (const auto& k : helmholtz_modes(o.order)) idx.push_back({k.n, k.l, k.m, k.lp});
    }
  }
  if (o.json) {
    nlohmann::json j;
    j["order"] = o.order;
    j["isotropic"] = o.isotropic;
    j["hemisphere"] = o.hemisphere;
    j["indices"] = idx;
    nlohmann::json rows = nlohmann::json::array();
    for (Eigen::Index r = 0; r < values.rows(); ++r) {
      nlohmann::json row = nlohmann::json::array();
      for (Eigen::Index c = 0; c < values.cols(); ++c) row.push_back(values(r, c));
      rows.push_back(std::move(row));
    }
    j["values"] = std::move(rows);
    std::cout << j.dump() << "\n";
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
