#pragma once
// The MERL BRDF database binary format (Matusik, Pfister, Brand, McMillan, "A data-driven reflectance
// model", SIGGRAPH 2003): reader, writer (used by the tests, which generate MERL files from analytic
// models) and a BrdfModel over the table.
//
// File layout (little-endian):
//   3 x int32      dims = 90, 90, 180 (theta_h, theta_d, phi_d resolutions); anything else is refused
//   3 x N doubles  N = 90 * 90 * 180, channel-major (R block, then G, then B); within a channel the sample
//                  (i_h, i_d, i_p) is at i_p + 180 * (i_d + 90 * i_h)
// so the file has exactly 12 + 3 * 8 * N = 34,992,012 bytes (checked before anything is allocated).
// A stored value v becomes f = v * scale_c [1/sr] with scale = 1/1500, 1.15/1500, 1.66/1500 (R, G, B).
// Negative stored values (the database uses -1) mark missing samples: they become NaN (never clamped)
// and are counted; NaN or Inf stored values and a file with every sample missing are refused.
//
// Half/difference parameterization (Rusinkiewicz 1998), both vectors pointing away from the surface:
//   h = (w_i + w_r)/|w_i + w_r|, theta_h = acos(h_z), phi_h = atan2(h_y, h_x);
//   d = R_y(-theta_h) R_z(-phi_h) w_i,  theta_d = acos(d_z), phi_d = atan2(d_y, d_x).
// Swapping w_i and w_r (Helmholtz reciprocity) maps phi_d to phi_d + pi, so phi_d is folded to [0, pi).
// Bins (floor lookup, as in the database's published reference reader):
//   i_h = floor(90 sqrt(theta_h / (pi/2)))   (square-root mapping: fine bins near the specular peak)
//   i_d = floor(90 theta_d / (pi/2)),  i_p = floor(180 phi_d / pi),  each clamped to its range.
// Table nodes (where write_merl samples a model) are the bin centres in index space:
//   theta_h = (pi/2) ((i_h + 1/2)/90)^2,  theta_d = (pi/2)(i_d + 1/2)/90,  phi_d = pi (i_p + 1/2)/180,
// so a lookup at a node returns exactly that node's value. Between nodes the table is piecewise
// constant (no interpolation): accuracy is that of the bins (1 deg in theta_d and phi_d).
#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "icobrdf/core/models/brdf_model.hpp"
#include "icobrdf/core/grid/grid.hpp"

namespace icobrdf {

inline constexpr int kMerlThetaHalfRes = 90;
inline constexpr int kMerlThetaDiffRes = 90;
inline constexpr int kMerlPhiDiffRes = 180;
inline constexpr std::int64_t kMerlSamplesPerChannel =
    static_cast<std::int64_t>(kMerlThetaHalfRes) * kMerlThetaDiffRes * kMerlPhiDiffRes;  // 1,458,000
inline constexpr std::int64_t kMerlFileBytes = 12 + 3 * 8 * kMerlSamplesPerChannel;   // 34,992,012
// Stored value -> f [1/sr] per channel (R, G, B).
inline constexpr std::array<double, 3> kMerlChannelScale = {1.0 / 1500.0, 1.15 / 1500.0, 1.66 / 1500.0};

struct HalfDiffAngles {
  double theta_h, phi_h, theta_d, phi_d;  // radians; phi_d in (-pi, pi] (not folded)
};
// Unit vectors with z >= 0 expected; w_i = -w_r (not on one hemisphere) cannot occur there.
HalfDiffAngles half_diff_from_directions(const Eigen::Vector3d& wi, const Eigen::Vector3d& wr);
// Inverse: w_i = R_z(phi_h) R_y(theta_h) d, w_r = 2 (w_i . h) h - w_i. May give z < 0 (below the horizon).
void directions_from_half_diff(const HalfDiffAngles& a, Eigen::Vector3d& wi, Eigen::Vector3d& wr);

struct MerlBin {
  int theta_h, theta_d, phi_d;
  std::int64_t flat() const { return phi_d + kMerlPhiDiffRes * (theta_d + static_cast<std::int64_t>(kMerlThetaDiffRes) * theta_h); }
};
// Bin of a direction pair (floor lookup with the phi_d fold, see above).
MerlBin merl_bin(const Eigen::Vector3d& wi, const Eigen::Vector3d& wr);
// Node (bin centre) angles of a bin, phi_h = 0.
HalfDiffAngles merl_node(const MerlBin& bin);

struct MerlTable {
  std::string path;
  std::vector<double> f;                  // 3 * N values [1/sr], channel-major; NaN where missing
  std::array<std::int64_t, 3> missing{};  // missing samples per channel
  std::int64_t missing_total() const { return missing[0] + missing[1] + missing[2]; }
  double at(int channel, const MerlBin& b) const { return f[static_cast<size_t>(channel * kMerlSamplesPerChannel + b.flat())]; }
};

// Reads and validates a MERL file. InputError (one line: path, what, expected vs actual) for: a missing or
// unreadable file, fewer than 12 bytes, a byte-swapped header, zero or negative dims, dims whose product
// overflows int32, permuted or other non-standard dims, a size other than 34,992,012 bytes (truncation
// and trailing bytes reported in bytes), NaN/Inf samples, every sample missing.
MerlTable read_merl(const std::string& path);

// Writes `model` (1 channel broadcast to R, G, B, or 3 channels) sampled at the table nodes, divided by the
// channel scales; nodes below the horizon store the model's value there (0 by the BrdfModel convention).
// `missing(bin)` true stores -1 (a missing sample). Atomic (icobrdf/io/atomic_write.hpp). ArgumentError for a
// model with another channel count or a negative or non-finite value at a node above the horizon.
void write_merl(const std::string& path, const BrdfModel& model,
                const std::function<bool(const MerlBin&)>& missing = nullptr);

// f looked up in a MERL table: 3 channels, NaN at missing samples, 0 below the horizon (z < -kHorizonSlack).
class MerlModel final : public BrdfModel {
 public:
  explicit MerlModel(std::shared_ptr<const MerlTable> table) : table_(std::move(table)) {}
  using BrdfModel::eval;
  int channels() const override { return 3; }
  void eval(const RowMatrix3d& wi, const RowMatrix3d& wr, Eigen::Ref<Eigen::MatrixXd> out) const override;
  std::string spec() const override { return "merl:" + table_->path; }  // a SOURCE, not a parse_model spec
  const MerlTable& table() const { return *table_; }

 private:
  std::shared_ptr<const MerlTable> table_;
};

// The table's valid nodes as scattered samples for core/sample_fit: nodes with both directions above the
// horizon (z > 0) and no missing channel. Weight of a node = the solid-angle measure of its bin,
//   dOmega_i dOmega_r = 4 cos(theta_d) sin(theta_h) sin(theta_d) dtheta_h dtheta_d dphi_d dphi_h,
// integrated exactly over the bin in theta_h, theta_d and phi_d, times 2 pi (phi_h) and 2 (the phi_d fold).
struct MerlSamples {
  RowMatrix3d wi, wr;          // S x 3 at the nodes, phi_h = 0
  Eigen::MatrixXd values;      // S x 3 [1/sr]
  Eigen::VectorXd weights;     // S [sr^2]
  std::vector<std::int64_t> bins;  // S: the node's bin (MerlBin::flat)
  std::int64_t below_horizon = 0;  // nodes skipped because a direction is below the horizon
  std::int64_t missing = 0;        // nodes skipped because a channel is missing
};
MerlSamples merl_samples(const MerlTable& table);

}  // namespace icobrdf
