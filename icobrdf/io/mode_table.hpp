#pragma once
// Values of every mode up to a total order at the directions of a CSV file (`icobrdf modes`): the Helmholtz
// modes H (indices [n, l, m, l'], icobrdf/core/basis/helmholtz_modes.hpp) or the isotropic modes I ([n, m, l],
// icobrdf/core/basis/isotropic_modes.hpp) at direction pairs (columns theta_i,phi_i,theta_r,phi_r), or the
// hemisphere basis K ([n, l] in ANSI order, icobrdf/core/basis/hemisphere_basis.hpp) at directions (theta,phi);
// angles in degrees (icobrdf/io/direction_csv.hpp). Values in 1/sr for the modes, 1/sqrt(sr) for K.
#include <nlohmann/json.hpp>

#include <Eigen/Core>
#include <string>
#include <vector>

namespace icobrdf {

// Largest table evaluated (rows x modes): the general modes grow as N^4 (35 million per row at order 128).
inline constexpr long long kMaxModeTableValues = 20'000'000;

enum class ModeFamily { Helmholtz, Isotropic, Hemisphere };

struct ModeTable {
  Eigen::MatrixXd values;                // rows (directions or pairs) x modes
  std::vector<std::vector<int>> indices; // one index list per mode (column)
};

// ArgumentError for an order outside [0, kMaxZernikeOrder] (messages start with "modes: "), UnsupportedError
// for a table of more than kMaxModeTableValues values, InputError for a bad CSV file.
ModeTable mode_table(ModeFamily family, int order, const std::string& csv_path);

// {"order", "isotropic", "hemisphere", "indices": one list per mode, "values": one list per row, one number per mode}.
nlohmann::json mode_table_json(const ModeTable& table, ModeFamily family, int order);

}  // namespace icobrdf
