#pragma once
// Low-pass filters on spectra: one weight per radial order n = 0..N, applied to every K_n^l.
// A coefficient C_ab is multiplied by w[n(a)] * w[n(b)], so a filtered spectrum stays symmetric (reciprocal)
// and, when isotropic, isotropic. Weights are 1 at n = 0 (albedo-like DC term untouched) and decay to
// damp the ringing of plain truncation (Gibbs), as in Fourier synthesis.
//   none      w_n = 1                                   (plain truncation)
//   fejer     w_n = 1 - n / (N + 1)                     (Cesaro mean)
//   lanczos   w_n = sinc(pi n / (N + 1))                (Lanczos sigma factors)
//   hann      w_n = (1 + cos(pi n / (N + 1))) / 2
//   gaussian  w_n = exp(-(n / (N + 1))^2 / (2 s^2)),    s = `width` (default 0.4)
#include <Eigen/Core>

#include <string>
#include <vector>

namespace icobrdf {

struct LowPassFilter {
  enum class Kind { None, Fejer, Lanczos, Hann, Gaussian };
  Kind kind = Kind::None;
  double width = 0.4;  // Gaussian only, relative to N + 1

  // Weights w_0..w_N for truncation order N.
  Eigen::VectorXd order_weights(int order) const;
  std::string name() const;  // "none", "fejer", "lanczos", "hann", "gaussian:width=0.4"
};

// Parses "none", "fejer", "lanczos", "hann", "gaussian" or "gaussian:width=W"; ArgumentError otherwise.
LowPassFilter parse_lowpass_filter(const std::string& text);
const std::vector<std::string>& lowpass_filter_names();

// Per-mode weights (length (N+1)(N+2)/2, ANSI order): w[n(j)].
Eigen::VectorXd mode_weights(const LowPassFilter& filter, int order);

}  // namespace icobrdf
