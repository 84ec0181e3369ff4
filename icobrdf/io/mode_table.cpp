#include "icobrdf/io/mode_table.hpp"

#include <fmt/core.h>

#include "icobrdf/core/basis/helmholtz_modes.hpp"
#include "icobrdf/core/basis/hemisphere_basis.hpp"
#include "icobrdf/core/basis/isotropic_modes.hpp"
#include "icobrdf/core/basis/zernike.hpp"
#include "icobrdf/core/support/error.hpp"
#include "icobrdf/io/direction_csv.hpp"

namespace icobrdf {
namespace {

void check_size(long long rows, long long modes, int order) {
  if (rows * modes > kMaxModeTableValues)
    throw UnsupportedError(fmt::format("modes: {} rows x {} modes at order {} = {} values exceeds the supported {}", rows, modes, order,
                                       rows * modes, kMaxModeTableValues));
}

}  // namespace

ModeTable mode_table(ModeFamily family, int order, const std::string& csv_path) {
  if (order < 0 || order > kMaxZernikeOrder)
    throw ArgumentError(fmt::format("modes: --order must be in [0, {}], got {}", kMaxZernikeOrder, order));
  ModeTable t;
  if (family == ModeFamily::Hemisphere) {
    const RowMatrix3d dirs = read_directions_csv(csv_path);
    check_size(dirs.rows(), hemisphere_basis_count(order), order);
    t.values = hemisphere_basis_matrix(order, dirs);
    for (int j = 0; j < t.values.cols(); ++j) {
      const auto k = ansi_to_nl(j);
      t.indices.push_back({k.n, k.l});
    }
    return t;
  }
  const DirectionPairs pairs = read_direction_pairs_csv(csv_path);
  if (family == ModeFamily::Isotropic) {
    check_size(pairs.wi.rows(), isotropic_mode_count(order), order);
    t.values = isotropic_modes_eval(order, pairs.wi, pairs.wr);
    for (const auto& k : isotropic_modes(order)) t.indices.push_back({k.n, k.m, k.l});
  } else {
    check_size(pairs.wi.rows(), helmholtz_mode_count(order), order);
    t.values = helmholtz_modes_eval(order, pairs.wi, pairs.wr);
    for (const auto& k : helmholtz_modes(order)) t.indices.push_back({k.n, k.l, k.m, k.lp});
  }
  return t;
}

nlohmann::json mode_table_json(const ModeTable& table, ModeFamily family, int order) {
  nlohmann::json j;
  j["order"] = order;
  j["isotropic"] = family == ModeFamily::Isotropic;
  j["hemisphere"] = family == ModeFamily::Hemisphere;
  j["indices"] = table.indices;
  nlohmann::json rows = nlohmann::json::array();
  for (Eigen::Index r = 0; r < table.values.rows(); ++r) {
    nlohmann::json row = nlohmann::json::array();
    for (Eigen::Index c = 0; c < table.values.cols(); ++c) row.push_back(table.values(r, c));
    rows.push_back(std::move(row));
  }
  j["values"] = std::move(rows);
  return j;
}

}  // namespace icobrdf
