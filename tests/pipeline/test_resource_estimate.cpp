// The memory estimates of icobrdf/pipeline/resource_estimate.hpp against the peak resident memory of the program
// doing that work (measured by the kernel for a child process), at several sizes; and the refusal that
// follows from them. Not a timing test: only bytes are compared.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/basis/hemisphere_basis.hpp"
#include "icobrdf/core/support/memory_budget.hpp"
#include "icobrdf/io/spectrum_file.hpp"
#include "icobrdf/pipeline/resource_estimate.hpp"
#include "tests/cli/measured_run.hpp"
#include "tests/support/unity_id.hpp"

namespace icobrdf {
namespace ICOBRDF_UNITY_ID {

using test::kSanitizedBuild;
using test::run_measured;

// An estimate may exceed the measured peak by this factor: it counts the largest arrays at their peak
// together, while some are freed before others are allocated (the weighted basis before the LUT rows).
constexpr double kEstimateFactor = 2.0;
// The measured peak may exceed the estimate by this much: the program's fixed footprint (shared libraries,
// OpenMP and OpenBLAS thread stacks, HDF5 buffers, the mesh), which the estimates leave out. The smallest
// run here (a level-3 LUT) measures 26 MB in all.
constexpr double kFixedFootprintBytes = 64e6;

// Relative room for the LUT estimate's level-to-level ratio against (C6/C5)^2: the grid and fit terms, linear
// in C, dilute the C^2 ratio by a couple of percent.
constexpr double kLinearTermsDilution = 0.05;

std::string scratch(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / ("icobrdf_estimate_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  return (dir / name).string();
}

void expect_estimate_matches(const std::vector<std::string>& args, double estimate) {
  const auto r = run_measured(args);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_LE(r.peak_bytes, estimate + kFixedFootprintBytes) << "estimate " << estimate << " B, measured " << r.peak_bytes << " B";
  EXPECT_LE(estimate, kEstimateFactor * r.peak_bytes) << "estimate " << estimate << " B, measured " << r.peak_bytes << " B";
}

TEST(ResourceEstimate, CellAndModeCountsFollowTheirFormulas) {  // the counts the estimates are built on
  EXPECT_EQ(equal_area_cells(0), 12);       // 10 + 2
  EXPECT_EQ(equal_area_cells(5), 10304);    // 10240 + 64
  EXPECT_EQ(equal_area_cells(8), 655872);   // 655360 + 512
  EXPECT_EQ(hemisphere_basis_count(0), 1);
  EXPECT_EQ(hemisphere_basis_count(8), 45);
  EXPECT_EQ(hemisphere_basis_count(64), 2145);
}

TEST(ResourceEstimate, LutEstimatesBoundTheMeasuredPeak) {
  if (kSanitizedBuild) GTEST_SKIP() << "resident memory of a sanitized build is not the program's";
  const int t = estimate_threads();
  // Level 4 (2,562 cells, 52 MB per LUT) and level 5 (10,304 cells, 850 MB): the LUT and its copy dominate.
  for (const int level : {4, 5})
    expect_estimate_matches({"lut", "model:lambert", "--level", std::to_string(level), "--sampling", "centre", "--order", "8",
                             "-o", scratch("lut" + std::to_string(level) + ".h5")},
                            lut_bytes(level, 8, 1, false, t));
  expect_estimate_matches({"lut", "model:lambert", "--level", "4", "--sampling", "centre", "--float32", "-o", scratch("lut4f.h5")},
                          lut_bytes(4, 8, 1, true, t));
}

TEST(ResourceEstimate, ModelFitEstimatesBoundTheMeasuredPeak) {
  if (kSanitizedBuild) GTEST_SKIP() << "resident memory of a sanitized build is not the program's";
  const int t = estimate_threads();
  // Order 20 at level 5 (231 modes: the C x M matrices are 19 MB each) and order 16 at level 4.
  expect_estimate_matches({"fit", "model:ggx:alpha=0.3", "--level", "5", "--order", "20", "--sampling", "centre", "-o", scratch("f5.h5")},
                          model_fit_bytes(5, 20, 1, t));
  expect_estimate_matches({"fit", "model:ggx:alpha=0.3", "--level", "4", "--order", "16", "--sampling", "centre", "-o", scratch("f4.h5")},
                          model_fit_bytes(4, 16, 1, t));
}

TEST(ResourceEstimate, EstimatesGrowWithTheirSizes) {
  // The quantities that decide what fits: C^2 for LUTs, C M for fits; doubling nothing else.
  const double l5 = lut_bytes(5, 8, 1, false, 2), l6 = lut_bytes(6, 8, 1, false, 2);
  const double c2 = std::pow(static_cast<double>(equal_area_cells(6)) / static_cast<double>(equal_area_cells(5)), 2);
  EXPECT_NEAR(l6 / l5, c2, kLinearTermsDilution * c2);
  EXPECT_GT(model_fit_bytes(7, 64, 1, 2), 3 * 8 * static_cast<double>(equal_area_cells(7)) * hemisphere_basis_count(64));  // at least B, P and a third C x M
  EXPECT_LT(lut_bytes(5, 8, 1, true, 2), lut_bytes(5, 8, 1, false, 2));
}

TEST(ResourceEstimate, RefusalNamesNeedAvailableAndWhatFits) {
  set_memory_budget(1e9);
  try {
    require_model_fit_memory(7, 64, 1, "a fit");
    FAIL() << "a level-7, order-64 fit (3 x 2.8 GB of C x M matrices) was not refused under a 1 GB budget";
  } catch (const ResourceError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("a fit at level 7, order 64 needs about"), std::string::npos) << m;
    EXPECT_NE(m.find("1.00 GB is available (memory budget)"), std::string::npos) << m;
    // The largest order that fits must itself fit, and the next one must not.
    const int n = largest_order_in_memory(7, 64, 1);
    ASSERT_GE(n, 0);
    EXPECT_NE(m.find("order " + std::to_string(n) + " fits at level 7"), std::string::npos) << m;
    EXPECT_LE(model_fit_bytes(7, n, 1, estimate_threads()), 1e9);
    EXPECT_GT(model_fit_bytes(7, n + 1, 1, estimate_threads()), 1e9);
  }
  EXPECT_NO_THROW(require_model_fit_memory(3, 8, 1, "a fit"));
  set_memory_budget(0);
}

}  // namespace
}  // namespace icobrdf
