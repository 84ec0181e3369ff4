#pragma once
// The hot tile of evaluate_coefficients (icobrdf/core/spectrum/spectrum_ops.hpp): f[p] = K_i[p, :] C K_r[p, :]^T for a block
// of direction pairs, given the basis rows of both sides (block x M, column-major, by hemisphere_basis_block),
// at the widest vectors the CPU has (run-time dispatch, icobrdf/core/support/simd_target.hpp).
//
// General C (dense path): GEMM-shaped. For a register tile of V vectors of pairs x Cols columns of C,
// A = K_i C(:, panel) is accumulated over k = 0..M-1 (V loads of K_i and Cols broadcasts of C per k, V Cols
// FMAs), then dotted with the tile's K_r columns; A is never stored. AVX-512 (32 registers): V = 3 (24
// pairs), Cols in 4..9 (27 accumulators at most); 16-register targets: V = 2, Cols in 4..6. Cols is the
// width that pads M least (9 at order 8, M = 45: no padding). C is packed once per call (pack_spectrum),
// panel after panel, row-major inside a panel. 2 M^2 flops per pair, plus 2 M for the dot.
//
// Azimuthally block-diagonal C (sparse path): C_ab = 0 whenever the azimuthal indices l_a != l_b. Every
// isotropic spectrum is such a C (icobrdf/core/basis/isotropic_modes.hpp: an isotropic f is invariant under rotation about
// the normal, which rotates (K_n^l, K_n^-l) by l alpha, so only blocks with |l_a| = |l_b| survive, and
// under the mirror phi -> -phi, which flips the sign of K_n^-l and so kills the l_a = -l_b couplings).
// Then f = sum_l K_i[p, S_l] C(S_l, S_l) K_r[p, S_l]^T over the 2 N + 1 index sets S_l of equal l, which at
// order 8 is 145 of the 2025 entries of C. pack_spectrum detects the structure exactly (every coupling
// entry == 0.0), so skipping them changes the sum only by the order of its terms. When moreover every block of
// -l equals that of l (exactly), C is isotropic and evaluate_coefficients skips the basis altogether
// (icobrdf/core/basis/isotropic_evaluation.hpp: radial rows and cos(l dphi) only).
//
// Rounding (both paths): each value is a sum of at most M^2 products K_i[k] C_kj K_r[j] formed by FMA, in
// an order fixed by the target and path (not by the thread count or the position of the pair in a block):
// |f - exact| <= (2 M + 4) u sum_kj |K_i[k]| |C_kj| |K_r[j]|, u = 2^-53, for the given K rows; the K rows
// themselves carry the basis kernel's rounding (tests/core/spectrum/test_spectrum_tile.cpp checks both together
// against the plain definition, on every compiled target).
#include <Eigen/Core>
#include <cstddef>
#include <vector>

namespace icobrdf {

// C packed for the tile of the SIMD target dispatched when it was packed.
struct PackedSpectrum {
  std::vector<double> storage;  // the packed values
  int m = 0;                    // modes (rows and columns of C)
  bool sparse = false;          // azimuthally block-diagonal: the sparse path
  bool isotropic = false;       // also equal blocks of l and -l: isotropic_form_block with radial_blocks
  std::vector<double> radial_blocks;  // D^0 .. D^N of icobrdf/core/basis/isotropic_evaluation.hpp
  Eigen::Index lanes = 0;       // vector lanes of the target it was packed for
  int cols = 0;                 // dense path: columns per panel
  int panels = 0;               // dense path: panels of `cols` columns (the last one zero-padded)
  Eigen::Index tile_pairs = 0;  // pairs per register tile: np is rounded up to a multiple of it
  std::vector<int> group_start; // sparse path: S_l = group_index[group_start[g] .. group_start[g + 1])
  std::vector<int> group_index; // sparse path: ANSI indices, grouped by l
};

// Packs C (M x M of hemisphere_basis_count(order) modes) for the dispatched target; `allow_sparse` false
// forces the dense path (tests compare the two).
PackedSpectrum pack_spectrum(const Eigen::MatrixXd& c, int order, bool allow_sparse = true);

// Columns of K_r the dense tile reads: panels x cols >= M (columns past M must be finite; their C is 0).
Eigen::Index spectrum_tile_columns(const PackedSpectrum& packed);

// f[p] = sum_kj ki[p + k ld] C(k, j) kr[p + j ld] for p < np. ki and kr: column-major with leading dimension
// ld, M columns (kr: spectrum_tile_columns), rows up to np rounded up to packed.tile_pairs, all finite
// (rows past np are computed too). f: room for np rounded up to packed.tile_pairs values. ArgumentError when `packed` was packed for another vector width
// than the one dispatched now, or ld is shorter than the rounded np.
void spectrum_tile(const PackedSpectrum& packed, Eigen::Index np, const double* ki, const double* kr, Eigen::Index ld, double* f);

}  // namespace icobrdf
