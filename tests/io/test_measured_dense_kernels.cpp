// The sample fits of io's measured SOURCEs (icobrdf/io/measured_sources.hpp) run on core's default dense kernels
// (default_dense_kernels, icobrdf/core/fit/dense_kernels.hpp): whichever set a program installed, Eigen's when
// none. A counting set that forwards to Eigen's kernels shows which set the fits were handed.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <random>

#include "icobrdf/core/fit/dense_kernels.hpp"
#include "icobrdf/core/fit/spectral_fit.hpp"
#include "icobrdf/core/models/model_registry.hpp"
#include "icobrdf/io/brdf_source.hpp"
#include "icobrdf/io/merl.hpp"
#include "io_test_support.hpp"
#include "tests/support/unity_id.hpp"

namespace icobrdf {
namespace ICOBRDF_UNITY_ID {

using test::ScratchDir;

std::atomic<int> g_rank_updates{0}, g_factorizations{0};

void counting_rank_update(double* g, Eigen::Index k, const double* a, Eigen::Index rows, Eigen::Index lda) {
  ++g_rank_updates;
  eigen_dense_kernels().rank_update(g, k, a, rows, lda);
}

bool counting_cholesky(double* g, Eigen::Index k) {
  ++g_factorizations;
  return eigen_dense_kernels().cholesky_lower(g, k);
}

const DenseKernels kCounting{"counting", &counting_rank_update, &counting_cholesky, false};

// Installs the counting set as the default for one test, and restores Eigen's after it.
struct CountingDefault {
  CountingDefault() {
    g_rank_updates = 0;
    g_factorizations = 0;
    set_default_dense_kernels(&kCounting);
  }
  ~CountingDefault() { set_default_dense_kernels(nullptr); }
};

// Lambert (0.3 / pi 1/sr at every pair) at n pairs uniform in solid angle, in degrees.
void write_lambert_samples(const std::string& path, int n) {
  std::mt19937 g(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::ofstream o(path);
  o << "theta_i,phi_i,theta_r,phi_r,value\n";
  char line[200];
  for (int k = 0; k < n; ++k) {
    std::snprintf(line, sizeof line, "%.12f,%.12f,%.12f,%.12f,%.17g\n", std::acos(u(g)) * 180 / M_PI, 360 * u(g),
                  std::acos(u(g)) * 180 / M_PI, 360 * u(g), 0.3 / M_PI);
    o << line;
  }
}

TEST(MeasuredDenseKernels, CsvSampleFitsTakeTheDefaultKernels) {
  ScratchDir d;
  write_lambert_samples(d / "lambert.csv", 400);
  const std::unique_ptr<BrdfSource> source = open_source(d / "lambert.csv");
  FitOptions o;
  o.order = 2;
  {
    CountingDefault counting;
    source->fit(ProjectionContext{}, o);
    EXPECT_GT(g_rank_updates.load(), 0) << "the normal equations were not assembled by the default kernels";
    EXPECT_GT(g_factorizations.load(), 0) << "the normal equations were not factored by the default kernels";
  }
  g_rank_updates = 0;
  source->fit(ProjectionContext{}, o);  // Eigen's again: the counting set is no longer the default
  EXPECT_EQ(g_rank_updates.load(), 0);
}

TEST(MeasuredDenseKernels, MerlTableFitsTakeTheDefaultKernels) {
  ScratchDir d;
  write_merl(d / "lambert.binary", *parse_model("lambert:albedo=0.3"));
  const std::unique_ptr<BrdfSource> source = open_source("merl:" + (d / "lambert.binary"));
  FitOptions o;
  o.order = 2;
  CountingDefault counting;
  source->fit(ProjectionContext{}, o);
  EXPECT_GT(g_rank_updates.load(), 0);
  EXPECT_GT(g_factorizations.load(), 0);
}

}  // namespace
}  // namespace icobrdf
