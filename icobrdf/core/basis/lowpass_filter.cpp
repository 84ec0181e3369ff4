#include "icobrdf/core/basis/lowpass_filter.hpp"

#include <cmath>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/basis/hemisphere_basis.hpp"

namespace icobrdf {

Eigen::VectorXd LowPassFilter::order_weights(int order) const {
  if (order < 0) throw ArgumentError("low-pass filter: order must be >= 0, got " + std::to_string(order));
  Eigen::VectorXd w(order + 1);
  const double scale = order + 1.0;
  for (int n = 0; n <= order; ++n) {
    const double x = n / scale;
    switch (kind) {
      case Kind::None: w[n] = 1.0; break;
      case Kind::Fejer: w[n] = 1.0 - x; break;
      case Kind::Lanczos: w[n] = n == 0 ? 1.0 : std::sin(M_PI * x) / (M_PI * x); break;
      case Kind::Hann: w[n] = 0.5 * (1.0 + std::cos(M_PI * x)); break;
      case Kind::Gaussian: w[n] = std::exp(-x * x / (2.0 * width * width)); break;
    }
  }
  return w;
}

std::string LowPassFilter::name() const {
  switch (kind) {
    case Kind::None: return "none";
    case Kind::Fejer: return "fejer";
    case Kind::Lanczos: return "lanczos";
    case Kind::Hann: return "hann";
    case Kind::Gaussian: {
      char buf[64];
      std::snprintf(buf, sizeof buf, "gaussian:width=%.17g", width);
      return buf;
    }
  }
  return "none";
}

const std::vector<std::string>& lowpass_filter_names() {
  static const std::vector<std::string> names{"none", "fejer", "lanczos", "hann", "gaussian"};
  return names;
}

LowPassFilter parse_lowpass_filter(const std::string& text) {
  LowPassFilter f;
  if (text == "none" || text.empty()) return f;
  if (text == "fejer") { f.kind = LowPassFilter::Kind::Fejer; return f; }
  if (text == "lanczos") { f.kind = LowPassFilter::Kind::Lanczos; return f; }
  if (text == "hann") { f.kind = LowPassFilter::Kind::Hann; return f; }
  if (text == "gaussian") { f.kind = LowPassFilter::Kind::Gaussian; return f; }
  const std::string prefix = "gaussian:width=";
  if (text.rfind(prefix, 0) == 0) {
    f.kind = LowPassFilter::Kind::Gaussian;
    char* end = nullptr;
    const std::string v = text.substr(prefix.size());
    f.width = std::strtod(v.c_str(), &end);
    if (v.empty() || *end != '\0' || !(f.width > 0.0) || !std::isfinite(f.width))
      throw ArgumentError("filter '" + quoted_text(text) + "': width expected a positive number, found '" + quoted_text(v) + "'");
    return f;
  }
  throw ArgumentError("unknown filter '" + quoted_text(text) + "', expected one of none, fejer, lanczos, hann, gaussian[:width=W]");
}

Eigen::VectorXd mode_weights(const LowPassFilter& filter, int order) {
  const Eigen::VectorXd w = filter.order_weights(order);
  const int m = hemisphere_basis_count(order);
  Eigen::VectorXd out(m);
  for (int j = 0; j < m; ++j) out[j] = w[ansi_to_nl(j).n];
  return out;
}

}  // namespace icobrdf
