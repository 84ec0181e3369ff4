#include "lab/projection_benchmark.hpp"

#include <cblas.h>
#include <omp.h>

#include <algorithm>
#include <random>

#include "core/discrete_basis.hpp"
#include "core/projection.hpp"
#include "lab/timing.hpp"
#include "mesh/tessellation.hpp"

namespace icobrdf::lab {

Eigen::MatrixXd random_lut(Eigen::Index cells, unsigned seed) {
  Eigen::MatrixXd f(cells, cells);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (Eigen::Index k = 0; k < f.size(); ++k) f.data()[k] = u(rng);
  return f;
}

void blas_project(const Eigen::MatrixXd& P, const Eigen::MatrixXd& F, bool pf_first, Eigen::MatrixXd& tmp, Eigen::MatrixXd& out) {
  const int c = static_cast<int>(F.rows()), m = static_cast<int>(P.cols());
  const double* p = P.data();
  if (pf_first) {
    cblas_dgemm(CblasColMajor, CblasTrans, CblasNoTrans, m, c, c, 1.0, p, c, F.data(), c, 0.0, tmp.data(), m);
    cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, m, m, c, 1.0, tmp.data(), m, p, c, 0.0, out.data(), m);
  } else {
    cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, c, m, c, 1.0, F.data(), c, p, c, 0.0, tmp.data(), c);
    cblas_dgemm(CblasColMajor, CblasTrans, CblasNoTrans, m, m, c, 1.0, p, c, tmp.data(), c, 0.0, out.data(), m);
  }
}

void set_blas_threads(int threads) { openblas_set_num_threads(threads); }

ProjectionBenchmark measure_projection(int level, int order, int threads, int repeat) {
  omp_set_num_threads(threads);
  Eigen::setNbThreads(threads);
  set_blas_threads(threads);
  const Grid g = with_centre_cubature(build_equal_area_grid(level));
  const auto basis = build_discrete_basis(g, order);
  check_supported(basis);
  const auto proj = make_projection(basis);
  ProjectionBenchmark b;
  b.cells = g.cells();
  b.modes = proj.P.cols();
  const Eigen::Index c = b.cells, m = b.modes;
  const Eigen::MatrixXd f = random_lut(c);
  Eigen::MatrixXd out(m, m), fp_blas(c, m), pf_blas(m, c), out_blas(m, m);
  b.seconds = best_seconds(repeat, [&] { out = project_lut(proj, f); });
  b.blas_seconds_fp_first = best_seconds(repeat, [&] { blas_project(proj.P, f, false, fp_blas, out_blas); });
  b.blas_seconds_pf_first = best_seconds(repeat, [&] { blas_project(proj.P, f, true, pf_blas, out_blas); });
  b.blas_seconds = std::min(b.blas_seconds_fp_first, b.blas_seconds_pf_first);
  b.relative_difference_to_blas = (out - out_blas).cwiseAbs().maxCoeff() / std::max(1e-300, out.cwiseAbs().maxCoeff());
  b.flops = 2.0 * c * c * m + 2.0 * c * m * m;
  return b;
}

}  // namespace icobrdf::lab
