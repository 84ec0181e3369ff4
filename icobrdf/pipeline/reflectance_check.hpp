#pragma once
// What an evaluating command (eval, lut, albedo, fit) checks before it prints or writes a reflectance:
//   1. finite: Inf or NaN (an overflow: weights or coefficients near 1e308) is refused with an
//      UnsupportedError (icobrdf/core/support/finite_values.hpp), whatever the flags;
//   2. physical: a reflectance (f, g = f cos(theta_i), or a directional albedo) below
//      -kNegativeReflectanceTolerance x its largest magnitude is non-physical. It is reported as one line on
//      `warnings` ("icobrdf: warning: ...") by default, and refused with an InputError under --strict.
// Negative values that truncation rings into an expansion of a non-negative BRDF are reported too: they
// are negative f all the same (a low-pass filter, `--filter`, reduces them).
#include <Eigen/Core>

#include <iosfwd>
#include <string>
#include <vector>

#include "icobrdf/core/grid/grid.hpp"
#include "icobrdf/core/spectrum/spectrum.hpp"
#include "icobrdf/io/material_sampler.hpp"

namespace icobrdf {

// Relative to the largest |value|: values are sums of up to ~1e5 rounded products (modes x modes, cells),
// whose rounding stays below 1e5 x 2^-53 ~ 1e-11 of the largest term; anything more negative is real.
inline constexpr double kNegativeReflectanceTolerance = 1e-10;

struct ReflectanceCheck {
  bool strict = false;       // negative values are errors (InputError) instead of warnings
  std::ostream* warnings;    // where warnings go (std::cerr in the CLI)
};

// values: rows x channels (or a vector). where: the SOURCE or file; step: what computed the values;
// quantity: "f", "g = f cos(theta_i)" or "directional albedo". Throws as above; prints at most one warning.
void check_reflectance(const Eigen::Ref<const Eigen::MatrixXd>& values, const std::string& where, const std::string& step,
                       const std::string& quantity, const ReflectanceCheck& check);

// The directional albedo of a fitted spectrum at the grid's cell directions (g spectra divided by cos(theta_i),
// grazing cells skipped), checked as above: a fit of negative data, or of a SCATMECH file whose constant
// term is negative, gives a negative albedo.
void check_fitted_albedo(const Spectrum& spectrum, const Grid& grid, const std::string& where, const ReflectanceCheck& check);

// Every channel of a LUT (cells x cells, f or g = f cos(theta_i) when `cosine`), then its directional albedo
// (icobrdf/core/projection/reflection.hpp), checked as above.
void check_lut(const std::vector<Eigen::MatrixXd>& lut, bool cosine, const Grid& grid, const std::string& where,
               const ReflectanceCheck& check);

// f(w_i, .) at the cell centres of the sampler's level (`sample`: the values its distribution is built from;
// it samples max(f, 0)), checked as above before any draw.
void check_sampled_reflectance(const MaterialSampler& sampler, const Eigen::Vector3d& wi, const ReflectanceCheck& check);

}  // namespace icobrdf
