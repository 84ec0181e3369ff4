#pragma once
// Non-finite values (Inf, NaN) are stopped where they would leave icobrdf: every file writer (banks, spectrum
// and LUT files, SCATMECH exports) checks what it is about to write, and every evaluator whose result is
// printed or drawn (eval, lut, albedo, plot) checks its result, before anything is written or shown.
// Finite inputs can still overflow: coefficients of 1e308 summed, model weights whose sum exceeds the double
// range (about 1.8e308), so the check is on the output, not only on the input.
//
// Message (one line): "<where>: <step> gave <value> at <index>, expected finite values (the result leaves the
// double range); nothing written". UnsupportedError: the request is valid but beyond what doubles represent
// (exit 4 in the CLI).
#include <Eigen/Core>

#include <string>

namespace icobrdf {

// where: the file being written or the SOURCE evaluated, with the material / dataset; step: what computed the
// values ("conversion of C to SCATMECH coefficients", "evaluation of f at the pairs"). Index: "[row, col]"
// for a matrix, "[i]" for a vector or a scalar.
void require_finite(const Eigen::Ref<const Eigen::MatrixXd>& values, const std::string& where, const std::string& step);
void require_finite(double value, const std::string& where, const std::string& step);

}  // namespace icobrdf
