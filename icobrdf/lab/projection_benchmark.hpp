#pragma once
// One projection C = P^T F P of a dense cells x cells LUT (the large GEMM dominates: 2 cells^2 modes +
// 2 cells modes^2 flops) timed with the library's call (icobrdf/core/projection/projection.hpp, Eigen) and with raw OpenBLAS
// doing the same products in the same run, in both association orders (the faster is the baseline).
// The LUT holds uniform random values in [0, 1) and is written before timing (its pages are resident).
#include <Eigen/Core>
#include <string>

namespace icobrdf::lab {

// A cells x cells matrix of uniform values in [0, 1) from std::mt19937_64(seed), written in storage order.
Eigen::MatrixXd random_lut(Eigen::Index cells, unsigned seed = 1);
// The same made symmetric: F = (R + R^T) / 2 (the shape of the f-form LUT of a reciprocal BRDF).
Eigen::MatrixXd random_symmetric_lut(Eigen::Index cells, unsigned seed = 1);

// Raw OpenBLAS (cblas_dgemm, column-major as Eigen stores) computes out = P^T F P; P is cells x modes,
// F cells x cells. pf_first: (P^T F) P, else P^T (F P). `tmp` is the intermediate product: modes x cells
// when pf_first, cells x modes otherwise; `out` modes x modes; both sized by the caller.
void blas_project(const Eigen::MatrixXd& P, const Eigen::MatrixXd& F, bool pf_first, Eigen::MatrixXd& tmp, Eigen::MatrixXd& out);

// Threads OpenBLAS uses.
void set_blas_threads(int threads);

// The kernel OpenBLAS chose when it loaded ("Haswell", "SkylakeX", "Zen", ...) and its build configuration
// (openblas_get_corename / openblas_get_config). OPENBLAS_CORETYPE, read at load time, overrides the choice.
std::string blas_core_name();
std::string blas_config();

// Raw OpenBLAS timing of one projection, both association orders.
struct BlasProjection {
  double seconds_fp_first = 0.0;  // best of `repeat`, P^T (F P)
  double seconds_pf_first = 0.0;  // best of `repeat`, (P^T F) P
  double seconds = 0.0;           // the faster of the two
  double cpu_seconds = 0.0;       // least CPU time of a call of either order (all threads; icobrdf/lab/timing.hpp)
  Eigen::MatrixXd coefficients;   // C from the faster order
  std::string core, config;       // blas_core_name(), blas_config()
};

struct ProjectionBenchmark {
  Eigen::Index cells = 0, modes = 0;
  double seconds = 0.0;                            // best of `repeat`, the library's project_lut
  double cpu_seconds = 0.0;                        // least CPU time of its calls (all threads)
  Eigen::MatrixXd coefficients;                    // its C
  BlasProjection blas;                             // raw OpenBLAS in this process
  double relative_difference_to_blas = 0.0;        // max|C - C_blas| / max|C|
  double flops = 0.0;                              // 2 cells^2 modes + 2 cells modes^2 (the general product)
  double performed_flops = 0.0;                    // what the library's call does: `flops`, or about half for a symmetric F
  double lut_huge_page_fraction = 0.0;             // of F's bytes in transparent huge pages (icobrdf/core/support/huge_pages.hpp)
};

// max|a - b| / max|a|: how well two coefficient matrices of the same product agree.
double relative_difference(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b);

// Times raw OpenBLAS alone at (level, order) with `threads` threads, on the LUT of measure_projection.
// Throws when the grid does not support the order.
BlasProjection measure_blas_projection(int level, int order, int threads, int repeat, bool symmetric = false);

// Times the projection at (level, order) on the centre-sampled equal-area grid with `threads` threads
// (OpenMP, Eigen and OpenBLAS are set to it), the paths interleaved call by call (a drift of the machine's
// load reaches all of them alike), best of `repeat` each. symmetric: the LUT is random_symmetric_lut and the library is
// told so (LutSymmetry::Symmetric), while OpenBLAS does the general product, which cannot use it.
// Throws when the grid does not support the order.
ProjectionBenchmark measure_projection(int level, int order, int threads, int repeat, bool symmetric = false);

}  // namespace icobrdf::lab
