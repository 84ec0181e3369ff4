#include "icobrdf/plot/half_diff_plot.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "icobrdf/core/support/error.hpp"

namespace icobrdf::plot {

std::pair<Eigen::Vector3d, Eigen::Vector3d> half_diff_directions(int size, int i, int j, double phi_d) {
  const double th = (M_PI / 2) * (j + 0.5) / size, td = (M_PI / 2) * (i + 0.5) / size;
  const Eigen::Vector3d d(std::sin(td) * std::cos(phi_d), std::sin(td) * std::sin(phi_d), std::cos(td));
  const Eigen::Vector3d wi(d.x() * std::cos(th) + d.z() * std::sin(th), d.y(), -d.x() * std::sin(th) + d.z() * std::cos(th));
  const Eigen::Vector3d h(std::sin(th), 0.0, std::cos(th));
  return {wi, 2.0 * wi.dot(h) * h - wi};
}

HalfDiffFigure plot_half_diff(const std::string& label, const PairFunction& values, bool log, const std::string& path, int size,
                              double phi_d) {
  if (!values) throw ArgumentError("half/difference plot: no values to draw");
  if (!std::isfinite(phi_d)) throw ArgumentError("half/difference plot: phi_d is not finite");
  if (size < 32 || size > 1024) throw ArgumentError(fmt::format("half/difference plot: size {} outside 32..1024 pixels", size));
  std::vector<int> pixel;
  std::vector<Eigen::Vector3d> wis, wos;
  for (int i = 0; i < size; ++i)
    for (int j = 0; j < size; ++j) {
      const auto [wi, wo] = half_diff_directions(size, i, j, phi_d);
      if (wi.z() <= 0.0 || wo.z() <= 0.0) continue;
      pixel.push_back(i * size + j);
      wis.push_back(wi);
      wos.push_back(wo);
    }
  RowMatrix3d a(static_cast<Eigen::Index>(wis.size()), 3), b(static_cast<Eigen::Index>(wos.size()), 3);
  for (std::size_t k = 0; k < wis.size(); ++k) {
    a.row(static_cast<Eigen::Index>(k)) = wis[k].transpose();
    b.row(static_cast<Eigen::Index>(k)) = wos[k].transpose();
  }
  Eigen::MatrixXd img = Eigen::MatrixXd::Constant(size, size, std::numeric_limits<double>::quiet_NaN());
  if (!pixel.empty()) {
    const Eigen::VectorXd v = values(a, b).rowwise().mean();
    for (std::size_t k = 0; k < pixel.size(); ++k) img(pixel[k] / size, pixel[k] % size) = v(static_cast<Eigen::Index>(k));
  }
  HalfDiffFigure out;
  out.scale = value_scale({&img}, log);
  // The scale's top at the kTopQuantile of the values: near theta_d = 90 degrees f grows without bound
  // (1 / (cos theta_i cos theta_o) in most models and measurements) and would leave the rest dark.
  std::vector<double> finite;
  for (Eigen::Index k = 0; k < img.size(); ++k)
    if (std::isfinite(img(k))) finite.push_back(std::fabs(img(k)));
  if (!finite.empty()) {
    constexpr double kTopQuantile = 0.95;
    const auto q = finite.begin() + static_cast<std::ptrdiff_t>(kTopQuantile * static_cast<double>(finite.size() - 1));
    std::nth_element(finite.begin(), q, finite.end());
    if (*q > 0.0) {
      out.scale.bottom *= *q / out.scale.top;
      out.scale.top = *q;
    }
  }
  const int left = 70, top = 80;
  out.image = {left, top, size};
  out.width = left + size + 170;
  out.height = top + size + 70;
  Figure fig(out.width, out.height);
  // The title fits the picture's width (about 8 pixels a character at 16 points): long paths keep their end.
  const std::size_t room = static_cast<std::size_t>(out.width / 9) - 22;
  fig.title("f(theta_h, theta_d) of " + (label.size() > room ? "..." + label.substr(label.size() - room + 3) : label), 16.0);
  fig.text(out.width / 2.0, 48, fmt::format("phi_d = {}\u00b0, channel mean{}", format_number(std::round(phi_d * 180.0 / M_PI * 100) / 100), log ? ", log scale" : ""), 12.0, Align::Centre);
  fig.image(colorize(img, out.scale), left, top);
  for (int deg = 0; deg <= 90; deg += 15) {
    const double p = size * deg / 90.0;
    fig.line(left + p, top + size, left + p, top + size + 5, 1.0, {0.1, 0.1, 0.1});
    fig.text(left + p, top + size + 18, std::to_string(deg) + "\u00b0", 10.5, Align::Centre);
    fig.line(left - 5, top + p, left, top + p, 1.0, {0.1, 0.1, 0.1});
    fig.text(left - 8, top + p + 4, std::to_string(deg) + "\u00b0", 10.5, Align::Right);
  }
  fig.text(left + size / 2.0, top + size + 40, "theta_h (half vector from the normal) \u2192", 12.0, Align::Centre);
  fig.text(18, top + size / 2.0, "theta_d (difference angle), 0\u00b0 at the top", 12.0, Align::Centre, false, M_PI / 2);
  draw_scale_bar(fig, left + size + 30, top, 20, size, out.scale, "f [1/sr]");
  fig.save_png(path);
  return out;
}

}  // namespace icobrdf::plot
