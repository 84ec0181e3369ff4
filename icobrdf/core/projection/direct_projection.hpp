#pragma once
// Direct quadrature of a model's spectrum without matrices: the baseline against which the matrix path
// C = P^T F P (icobrdf/core/projection/projection.hpp, icobrdf/core/projection/streaming_projection.hpp) is measured.
//
//   C_ab = sum_q sum_q' w_q w_q' f(x_q, x_q') K_a(x_q) K_b(x_q')     (M x M, K in ANSI order)
//
// over every pair of cubature points (x_q, w_q) of the grid (all cells' rules concatenated): the plain
// product-rule discretization of C_ab = integral integral f K_a K_b dOmega_i dOmega_r. No LUT, no B, no P
// is formed; f is evaluated one incident point at a time against all remitted points.
//
// Relation to the matrix path: when every cell has a one-point rule (with_centre_cubature, polar-Gauss
// grid), B_ca = K_a(x_c) and the centre-sampled LUT is F_ir = f(x_i, x_r), so the plain projection
// (P = W B) gives exactly this sum and the least-squares one (P = W B G^-1) gives G^-1 C G^-1: the two
// paths then agree to rounding. With multi-point rules the matrix path averages f over cell pairs first
// and the two differ by the discretization.
//
// Modes:
//   PerPair  K_b(x_q') is evaluated afresh for every pair (q, q'): O(Q^2 (M + cost of f)) work, O(M^2)
//            memory per thread; the literal per-pair mode evaluation.
//   Cached   K at every point is evaluated once (Q x M table): O(Q^2 M) multiply-adds, O(Q M) memory.
// Cosine: the spectrum of g = f cos(theta_i). Channels: one M x M matrix per model channel.
// Threads over blocks of incident points; partial sums are added in block order, so the result does not
// depend on the number of threads. Delta parts have no pointwise values: ArgumentError.
#include <Eigen/Core>

#include <vector>

#include "icobrdf/core/models/brdf_model.hpp"
#include "icobrdf/core/grid/grid.hpp"

namespace icobrdf {

enum class DirectModes { PerPair, Cached };

std::vector<Eigen::MatrixXd> direct_projection(const BrdfModel& model, const Grid& grid, int order, bool cosine,
                                               DirectModes modes = DirectModes::PerPair);

}  // namespace icobrdf
