#include "icobrdf/lab/projection_benchmark.hpp"

#include <cblas.h>
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <functional>
#include <limits>
#include <random>
#include <thread>

#include "icobrdf/core/projection/discrete_basis.hpp"
#include "icobrdf/core/support/huge_pages.hpp"
#include "icobrdf/core/projection/projection.hpp"
#include "icobrdf/lab/timing.hpp"
#include "icobrdf/mesh/tessellation.hpp"
#include "icobrdf/pipeline/resource_estimate.hpp"

namespace icobrdf::lab {

Eigen::MatrixXd random_lut(Eigen::Index cells, unsigned seed) {
  Eigen::MatrixXd f = huge_page_matrix(cells, cells);  // as the library's own LUTs (icobrdf/core/support/huge_pages.hpp)
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (Eigen::Index k = 0; k < f.size(); ++k) f.data()[k] = u(rng);
  return f;
}

Eigen::MatrixXd random_symmetric_lut(Eigen::Index cells, unsigned seed) {
  Eigen::MatrixXd f = random_lut(cells, seed);
  for (Eigen::Index j = 0; j < cells; ++j)
    for (Eigen::Index k = j + 1; k < cells; ++k) f(j, k) = f(k, j) = 0.5 * (f(k, j) + f(j, k));
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

std::string blas_core_name() {
  const char* name = openblas_get_corename();
  return name != nullptr ? name : "unknown";
}

std::string blas_config() {
  const char* config = openblas_get_config();
  return config != nullptr ? config : "unknown";
}

double relative_difference(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return (a - b).cwiseAbs().maxCoeff() / std::max(1e-300, a.cwiseAbs().maxCoeff());
}

namespace {

struct Problem {
  ProjectionOperator proj;
  Eigen::MatrixXd lut;
};

Problem problem_at(int level, int order, int threads, bool symmetric) {
  require_projection_bench_memory(level, order);  // before the grid: the LUT alone is 13.8 GB at level 6
  omp_set_num_threads(threads);
  Eigen::setNbThreads(threads);
  set_blas_threads(threads);
  const Grid g = with_centre_cubature(build_equal_area_grid(level));
  const auto basis = build_discrete_basis(g, order);
  check_supported(basis);
  return {make_projection(basis), symmetric ? random_symmetric_lut(g.cells()) : random_lut(g.cells())};
}

// Rest before each timed call: the worker threads of the call before (OpenBLAS's spin, yielding, for up to
// 2^28 cycles, about 70 ms at 3.7 GHz, after a call; OpenMP's for its spin count) are asleep by then and do
// not take a core from it. Without it (Zen 4, 2 threads, level 5, order 8, 2026-11-28) each path ran 2-6%
// slower after the other: icobrdf 0.1046-0.1058 s against 0.1019-0.1038 s, OpenBLAS 0.130-0.137 s against
// 0.122 s.
constexpr auto kRestBeforeEachCall = std::chrono::milliseconds(100);

// Times OpenBLAS in both orders and, when `ours` is given, the library's call too, `repeat` rounds of one
// call each, interleaved (ours, P^T (F P), (P^T F) P, ours, ...) so that a change of the machine's load
// during the run reaches every path alike, each after kRestBeforeEachCall; the best of each is kept.
BlasProjection time_paths(const Problem& p, int repeat, const std::function<void()>& ours, CpuWall* ours_best) {
  const Eigen::Index c = p.lut.rows(), m = p.proj.P.cols();
  Eigen::MatrixXd fp(c, m), pf(m, c), out_fp(m, m), out_pf(m, m);
  constexpr double kInf = std::numeric_limits<double>::infinity();
  CpuWall best_fp{kInf, kInf}, best_pf{kInf, kInf};
  if (ours_best != nullptr) *ours_best = {kInf, kInf};
  const auto keep = [](CpuWall& best, const CpuWall& t) {
    best.cpu = std::min(best.cpu, t.cpu);
    best.wall = std::min(best.wall, t.wall);
  };
  const auto rest = [] { std::this_thread::sleep_for(kRestBeforeEachCall); };
  for (int k = 0; k < repeat; ++k) {
    if (ours_best != nullptr) rest(), keep(*ours_best, cpu_and_wall_of(ours));
    rest();
    keep(best_fp, cpu_and_wall_of([&] { blas_project(p.proj.P, p.lut, false, fp, out_fp); }));
    rest();
    keep(best_pf, cpu_and_wall_of([&] { blas_project(p.proj.P, p.lut, true, pf, out_pf); }));
  }
  BlasProjection b;
  b.seconds_fp_first = best_fp.wall;
  b.seconds_pf_first = best_pf.wall;
  b.seconds = std::min(b.seconds_fp_first, b.seconds_pf_first);
  b.cpu_seconds = std::min(best_fp.cpu, best_pf.cpu);
  b.coefficients = b.seconds_fp_first <= b.seconds_pf_first ? out_fp : out_pf;
  b.core = blas_core_name();
  b.config = blas_config();
  return b;
}

}  // namespace

BlasProjection measure_blas_projection(int level, int order, int threads, int repeat, bool symmetric) {
  return time_paths(problem_at(level, order, threads, symmetric), repeat, {}, nullptr);
}

ProjectionBenchmark measure_projection(int level, int order, int threads, int repeat, bool symmetric) {
  const Problem p = problem_at(level, order, threads, symmetric);
  const LutSymmetry symmetry = symmetric ? LutSymmetry::Symmetric : LutSymmetry::General;
  ProjectionBenchmark b;
  b.cells = p.lut.rows();
  b.modes = p.proj.P.cols();
  const std::size_t lut_bytes = sizeof(double) * static_cast<std::size_t>(p.lut.size());
  b.lut_huge_page_fraction = static_cast<double>(huge_page_bytes(p.lut.data(), lut_bytes)) / static_cast<double>(lut_bytes);
  CpuWall best;
  b.blas = time_paths(p, repeat, [&] { b.coefficients = project_lut(p.proj, p.lut, symmetry); }, &best);
  b.seconds = best.wall;
  b.cpu_seconds = best.cpu;
  b.relative_difference_to_blas = relative_difference(b.coefficients, b.blas.coefficients);
  const double c = static_cast<double>(b.cells), m = static_cast<double>(b.modes);
  b.flops = 2.0 * c * c * m + 2.0 * c * m * m;
  b.performed_flops = b.flops;
  if (symmetric) {  // per column block J at c0 of width w: P^T F over the cells from c0 down, then two modes x w x modes products
    b.performed_flops = 0.0;
    for (Eigen::Index c0 = 0; c0 < b.cells; c0 += kProjectBlockColumns) {
      const double w = static_cast<double>(std::min(kProjectBlockColumns, b.cells - c0));
      b.performed_flops += 2.0 * m * w * (c - static_cast<double>(c0)) + 2.0 * 2.0 * m * w * m;
    }
  }
  return b;
}

}  // namespace icobrdf::lab
