#include "icobrdf/plot/bytes_plot.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "icobrdf/core/support/error.hpp"

namespace icobrdf::plot {

std::vector<CandidatePoint> lower_envelope(std::vector<CandidatePoint> points) {
  std::sort(points.begin(), points.end(), [](const CandidatePoint& a, const CandidatePoint& b) {
    return a.bytes != b.bytes ? a.bytes < b.bytes : a.error_l2 < b.error_l2;
  });
  std::vector<CandidatePoint> out;
  for (const auto& p : points)
    if (out.empty() || p.error_l2 < out.back().error_l2) out.push_back(p);
  return out;
}

BytesFigure plot_bytes(const std::string& label, const BankMaterialCandidates& m, const std::string& path) {
  if (m.points.empty())
    throw InputError("'" + quoted_text(label) + "': material '" + m.name +
                     "' stores no candidates (a delta BRDF has no pointwise error; a bank built before they were kept: build it again)");
  std::map<std::string, std::vector<CandidatePoint>> by;
  for (const auto& p : m.points) by[p.representation].push_back(p);
  BytesFigure out;
  std::vector<Series> series;
  long long lo = m.points.front().bytes, hi = lo;
  for (const auto& p : m.points) lo = std::min(lo, p.bytes), hi = std::max(hi, p.bytes);
  int k = 0;
  for (const auto& [name, pts] : by) {
    Series line, dots;
    line.label = fmt::format("{} ({} points)", name, pts.size());
    line.colour = dots.colour = series_colour(k);
    line.marker = Marker::None;
    for (const auto& p : lower_envelope(pts)) line.x.push_back(static_cast<double>(p.bytes)), line.y.push_back(p.error_l2);
    dots.line = false;
    dots.marker = Marker::Circle;
    for (const auto& p : pts) dots.x.push_back(static_cast<double>(p.bytes)), dots.y.push_back(p.error_l2);
    series.push_back(std::move(line));
    series.push_back(std::move(dots));
    out.representations.push_back(name);
    ++k;
  }
  out.points = static_cast<int>(m.points.size());
  if (std::isfinite(m.target) && m.target > 0)
    series.push_back(Series{fmt::format("target {}", format_number(m.target)), {lo / 2.0, hi * 2.0}, {m.target, m.target}, {0.3, 0.3, 0.3},
                            Marker::None, true, true, 1.2});
  series.push_back(Series{fmt::format("stored: {}, {} bytes, {}", m.chosen.representation, m.chosen.bytes, format_number(m.chosen.error_l2)),
                          {static_cast<double>(m.chosen.bytes)}, {m.chosen.error_l2}, {0.0, 0.0, 0.0}, Marker::Diamond, false});
  ChartOptions co;
  co.title = "Error against bytes of " + (label.size() > 60 ? "..." + label.substr(label.size() - 57) : label);
  co.x_label = "bytes stored";
  co.y_label = "relative L2 error (held-out pairs)";
  co.log_x = co.log_y = true;
  // Whole decades with room around the points: none sits on the frame.
  double e_lo = m.points.front().error_l2, e_hi = e_lo;
  for (const auto& p : m.points)
    if (p.error_l2 > 0) e_lo = std::min(e_lo, p.error_l2), e_hi = std::max(e_hi, p.error_l2);
  if (std::isfinite(m.target) && m.target > 0) e_lo = std::min(e_lo, m.target), e_hi = std::max(e_hi, m.target);
  co.x_min = std::pow(10.0, std::floor(std::log10(lo / 2.0)));
  co.x_max = std::pow(10.0, std::ceil(std::log10(hi * 2.0)));
  if (e_lo > 0) co.y_min = std::pow(10.0, std::floor(std::log10(e_lo / 2.0))), co.y_max = std::pow(10.0, std::ceil(std::log10(e_hi * 2.0)));
  co.width = 860;
  co.height = 520;
  co.note = "dots: every point the build reached; lines: lowest error at each size; diamond: stored";
  out.frame = draw_line_chart(series, co, path);
  out.width = co.width;
  out.height = co.height;
  return out;
}

}  // namespace icobrdf::plot
