// A model whose evaluation throws partway through a projection or a LUT (a source's lookup failing on some
// directions): the error reaches the caller as it was thrown, instead of ending the process inside an OpenMP
// region (icobrdf/core/support/in_order_sums.hpp), on every path that samples a model in parallel: the streaming
// projection (reciprocal triangle and the full path), the row-split projection and the materialized LUT.
#include <gtest/gtest.h>

#include <omp.h>

#include <functional>
#include <string>

#include "icobrdf/core/projection/discrete_basis.hpp"
#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/models/function_model.hpp"
#include "icobrdf/core/projection/lut.hpp"
#include "icobrdf/core/projection/projection.hpp"
#include "icobrdf/core/grid/reference_grids.hpp"
#include "icobrdf/core/projection/row_split_projection.hpp"
#include "icobrdf/core/projection/streaming_projection.hpp"
#include "tests/support/unity_id.hpp"

namespace icobrdf {
namespace ICOBRDF_UNITY_ID {

// Lambertian, except that a batch holding a pair with both directions within 25 degrees of the horizon
// throws: a few of the blocks fail, the others do not.
FunctionModel failing_model(bool reciprocal) {
  return FunctionModel(
      1,
      [](const RowMatrix3d& wi, const RowMatrix3d& wr, Eigen::Ref<Eigen::MatrixXd> out) {
        for (Eigen::Index k = 0; k < wi.rows(); ++k)
          if (wi(k, 2) < 0.42 && wr(k, 2) < 0.42) throw InputError("lookup failed near the horizon");
        out.setConstant(1.0 / M_PI);
      },
      "failing", false, reciprocal);
}

void expect_lookup_error(const std::function<void()>& run, const std::string& what) {
  try {
    run();
    ADD_FAILURE() << what << ": no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "lookup failed near the horizon") << what;
  }
}

TEST(ModelFailures, AnErrorInsideTheParallelSamplingReachesTheCaller) {
  const Grid g = build_lat_long_grid(16, 32, 2);
  const auto p = make_projection(build_discrete_basis(g, 4));
  const int all_threads = omp_get_max_threads();
  for (int threads : {1, 2}) {
    omp_set_num_threads(threads);
    const std::string on = " on " + std::to_string(threads) + " thread(s)";
    const FunctionModel reciprocal = failing_model(true), general = failing_model(false);
    expect_lookup_error([&] { streaming_projection(reciprocal, g, p, false, LutSampling::CellAverage); }, "reciprocal streaming" + on);
    expect_lookup_error([&] { streaming_projection(general, g, p, true, LutSampling::CellAverage); }, "full streaming" + on);
    expect_lookup_error([&] { row_split_projection_serial(general, g, 4, 2, true, LutSampling::CellAverage); }, "row split" + on);
    expect_lookup_error([&] { build_lut(general, g, false, LutSampling::CellCentre); }, "LUT" + on);
  }
  omp_set_num_threads(all_threads);
}

}  // namespace ICOBRDF_UNITY_ID
}  // namespace icobrdf
