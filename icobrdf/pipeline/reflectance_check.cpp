#include "icobrdf/pipeline/reflectance_check.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <ostream>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/support/finite_values.hpp"
#include "icobrdf/core/projection/reflection.hpp"
#include "icobrdf/core/fit/spectral_fit.hpp"
#include "icobrdf/core/spectrum/spectrum_ops.hpp"

namespace icobrdf {

void check_reflectance(const Eigen::Ref<const Eigen::MatrixXd>& values, const std::string& where, const std::string& step,
                       const std::string& quantity, const ReflectanceCheck& check) {
  require_finite(values, where, step);
  if (values.size() == 0) return;
  Eigen::Index r = 0, c = 0;
  const double lowest = values.minCoeff(&r, &c);
  const double largest = values.cwiseAbs().maxCoeff();
  if (!(lowest < -kNegativeReflectanceTolerance * largest)) return;
  const std::string at = values.cols() == 1 ? fmt::format("[{}]", r) : fmt::format("[{}, {}]", r, c);
  const std::string message =
      fmt::format("{}: {} gave a negative {} of {:.6g} at {} (largest magnitude {:.6g}, tolerance {:g} of it): non-physical reflectance",
                  where, step, quantity, lowest, at, largest, kNegativeReflectanceTolerance);
  if (check.strict) throw InputError(message + " (--strict)");
  // One write of the whole line: under mpirun the ranks' streams are merged, and a line written in pieces
  // could take another rank's line into its middle.
  if (check.warnings) *check.warnings << ("icobrdf: warning: " + message + "\n") << std::flush;
}

void check_fitted_albedo(const Spectrum& s, const Grid& grid, const std::string& where, const ReflectanceCheck& check) {
  std::vector<Eigen::Index> cells;
  for (Eigen::Index i = 0; i < grid.directions.rows(); ++i)
    if (!s.cosine || grid.directions(i, 2) >= kGrazingCellCos) cells.push_back(i);
  Eigen::MatrixXd albedo(static_cast<Eigen::Index>(cells.size()), s.channel_count());
  for (int c = 0; c < s.channel_count(); ++c) {
    const Eigen::VectorXd a = spectral_albedo(s.channels[static_cast<size_t>(c)], s.order, grid.directions);
    for (size_t k = 0; k < cells.size(); ++k)
      albedo(static_cast<Eigen::Index>(k), c) = s.cosine ? a[cells[k]] / grid.directions(cells[k], 2) : a[cells[k]];
  }
  check_reflectance(albedo, where, "the fitted spectrum's albedo at the cell directions", "directional albedo", check);
}

void check_lut(const std::vector<Eigen::MatrixXd>& lut, bool cosine, const Grid& grid, const std::string& where,
               const ReflectanceCheck& check) {
  for (size_t c = 0; c < lut.size(); ++c) {
    const std::string channel = where + " channel " + std::to_string(c);
    check_reflectance(lut[c], channel, "the LUT (cell pairs)", cosine ? "g = f cos(theta_i)" : "f", check);
    check_reflectance(directional_albedo(lut[c], cosine, grid), channel, "the LUT's directional albedo per incident cell",
                      "directional albedo", check);
  }
}

void check_sampled_reflectance(const MaterialSampler& sampler, const Eigen::Vector3d& wi, const ReflectanceCheck& check) {
  const RowMatrix3d& wr = sampler.directions().grid().directions;
  RowMatrix3d wis(wr.rows(), 3);
  wis.rowwise() = wi.transpose();
  check_reflectance(sampler.source().eval(wis, wr), "sample " + quoted_text(sampler.source().spec()),
                    fmt::format("f(w_i, .) at the {} cell centres of level {}", wr.rows(), sampler.level()), "f", check);
}

}  // namespace icobrdf
