#pragma once
// The half-angle factorized lobe of a material (icobrdf/core/models/half_angle_factors.hpp) <-> the subgroup
// /materials/<name>/half_angle of a bank (docs/file-format.md, formats 2.0-4.0).
//
//   attributes  quantity ("f" | "cosine"), isotropic (uint8), h_warp (float64), n_t, n_phi_h, n_theta_d,
//               n_phi_d, rank (int32), cosine_floor (float64), coordinates (text: the grids, the node
//               order and the interpolation, enough to evaluate the lobe without icobrdf)
//   u           sets x (n_t n_phi_h) x rank       precision  [1/sr]   h factors at the h nodes
//   v           sets x (n_theta_d n_phi_d) x rank precision  [1]      d factors at the d nodes
//   (4.0) precision "float64" (absent) | "float32" | "int16" | "int8": integers carry u_scale, v_scale (sets x
//   rank float64, value = scale k); factor_sets "channels" (absent; sets = channels) | "shared" (sets = 1,
//   channel_scales: channels x rank float64, term weights per channel). A lobe is written rounded to its
//   precision (HalfAngleFactors::quantize), so a quantized lobe reads back bitwise.
//
// q(h, d) = sum_r u[c, h node, r] v[c, d node, r], interpolated linearly in (t, phi_h) and (theta_d, phi_d);
// f = q (quantity f) or q / (max(cos theta_i, cosine_floor) max(cos theta_r, cosine_floor)) (quantity cosine),
// cosine_floor = sin((pi/2) / (n_theta_d - 1)).
#include <nlohmann/json.hpp>

#include <string>

#include "icobrdf/core/models/half_angle_factors.hpp"
#include "icobrdf/io/h5_file.hpp"

namespace icobrdf {

inline constexpr const char* kHalfAngleGroup = "half_angle";

// Writes `lobe` as the subgroup half_angle of `material`. ArgumentError naming `material_name` when the lobe
// is inconsistent (sizes, channels other than `channels`, non-finite values, rank < 1).
void write_half_angle(h5::Group& material, const HalfAngleFactors& lobe, int channels, const std::string& material_name);

// Reads and validates the subgroup half_angle of `material` (InputError "<file>: <object>: <what>").
HalfAngleFactors read_half_angle(const h5::Group& material, int channels, const h5::ReadLimits& limits);

// What `spectrum` and `bank info` show of a lobe: quantity, isotropy, rank, node counts, h warp, bytes, and per
// channel the norm products |u_r| |v_r| of its terms (their weights; the fit orders them by weighted energy).
nlohmann::json half_angle_summary(const HalfAngleFactors& lobe);
// One line of text: "half-angle lobe of q = f cos_i cos_r (isotropic), rank 2, h nodes 64 x 1 (theta_h = (pi/2) t^2),
// d nodes 64 x 32, 33792 bytes"; with `norms`, a line per channel with the norm products of its terms follows.
std::string half_angle_summary_line(const HalfAngleFactors& lobe, bool norms = false);

}  // namespace icobrdf
