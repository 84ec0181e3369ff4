#pragma once
// A Neural-BRDF network (Sztrajman, Rainer, Ritschel, Weyrich 2021, "Neural BRDF Representation and Importance
// Sampling"): the released pre-trained weights of a material, read from the Keras HDF5 file
// (model.save_weights) and evaluated in float64.
//
// Network: x[6] -> Dense(21, ReLU) -> Dense(21, ReLU) -> Dense(3, linear) -> exp(y) - 1 = RGB f [1/sr]
// (not f cos; no input or output scaling; Keras does not clamp, so values in (-1, 0) are possible).
// File layout (read here, each a float32 dataset, kernels (in, out) applied as x * kernel + bias):
//   dense_k/dense_k/kernel:0  (6, 21), (21, 21), (21, 3) for k = 1, 2, 3;   dense_k/dense_k/bias:0  (21,), (21,), (3,)
// 675 float32 numbers: kNbrdfBytes = 2,700 bytes per material as stored by the authors.
//
// Input x = [sin theta_h, 0, cos theta_h, d_x, d_y, d_z]: h = normalize(a + b), theta_h = acos(h_z),
// phi_h = atan2(h_y, h_x) (both 0 when h_z > kNbrdfPoleZ, as the authors' coordinate code), and
// d = R_y(-theta_h) R_z(-phi_h) a normalized: the direction `a` rotated into the half-vector frame. The
// network's `a` slot is its illumination direction in the authors' renderer; fitted to RGL files it carries
// RGL's w_r (measured at 3,000 random pairs of 11 RGL materials: the swapped assignment agrees 1.4-2x better, docs/readers.md "NBRDF"), so icobrdf's f(w_i, w_r) of an
// RGL material is NbrdfNetwork::eval(w_i, w_r), which puts w_r in the `a` slot. Both directions unit vectors
// in the local frame (z = normal); f = 0 when either is at or below the horizon.
// Accuracy: float64 arithmetic on the float32 weights; agrees with the authors' NumPy forward pass to
// rounding (~1e-15 relative).
#include <Eigen/Core>

#include <string>

#include "icobrdf/core/grid/grid.hpp"

namespace icobrdf::lab {

inline constexpr int kNbrdfHidden = 21;
inline constexpr long long kNbrdfBytes = 4LL * (6 * kNbrdfHidden + kNbrdfHidden + kNbrdfHidden * kNbrdfHidden + kNbrdfHidden +
                                                kNbrdfHidden * 3 + 3);
// h_z above which the authors' coordinate code sets theta_h = phi_h = 0.
inline constexpr double kNbrdfPoleZ = 0.99999;

struct NbrdfNetwork {
  std::string path;
  Eigen::MatrixXd w1, w2, w3;  // (in, out): 6 x 21, 21 x 21, 21 x 3
  Eigen::RowVectorXd b1, b2, b3;
  // f [1/sr] at pairs (rows x 3 each): rows x 3 (R, G, B), with icobrdf's slots (header).
  Eigen::MatrixXd eval(const RowMatrix3d& wi, const RowMatrix3d& wr) const;
};

// InputError (one line naming the file and the dataset) when the file is not such a network.
NbrdfNetwork read_nbrdf_network(const std::string& path);

}  // namespace icobrdf::lab
