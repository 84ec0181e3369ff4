#include "icobrdf/plot/sample_plot.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/plot/slice_data.hpp"

namespace icobrdf::plot {
namespace {

constexpr double kSamplePlotDegPerRad = 180.0 / M_PI;
constexpr int kFitCurveSamples = 359;                        // points per fitted curve: every half degree
constexpr double kFitCurveReach = (90.0 - 0.5) / kSamplePlotDegPerRad;  // as the in-plane curves: the horizon itself is not drawn
const Rgb kZeroLine{0.35, 0.35, 0.35};

// A sample's place in its plane of incidence: signed theta_r [deg] and its incidence, or nothing off the planes.
struct InPlane {
  bool in = false;
  double x_deg = 0.0, theta_i = 0.0, phi_i = 0.0;
};

InPlane in_plane(const Eigen::RowVector3d& wi, const Eigen::RowVector3d& wr) {
  InPlane p;
  p.theta_i = std::acos(std::clamp(wi(2), -1.0, 1.0));
  p.phi_i = std::atan2(wi(1), wi(0));
  const double tr = std::acos(std::clamp(wr(2), -1.0, 1.0));
  if (tr < kNormalTolerance) {
    p.in = true;
    return p;
  }
  const double d = std::remainder(std::atan2(wr(1), wr(0)) - p.phi_i, 2 * M_PI);  // in [-pi, pi]
  if (std::fabs(d) <= kPlaneTolerance) p.in = true, p.x_deg = -tr * kSamplePlotDegPerRad;  // backward (incident) side
  else if (std::fabs(d) >= M_PI - kPlaneTolerance) p.in = true, p.x_deg = tr * kSamplePlotDegPerRad;
  return p;
}

// The default groups: the incidence angles (whole degrees) with the most in-plane samples.
std::vector<double> populated_angles(const std::vector<InPlane>& places) {
  std::map<long, int> count;
  for (const auto& p : places)
    if (p.in) ++count[std::lround(p.theta_i * kSamplePlotDegPerRad)];
  std::vector<std::pair<long, int>> by_count(count.begin(), count.end());
  std::stable_sort(by_count.begin(), by_count.end(), [](const auto& a, const auto& b) { return a.second > b.second; });
  std::vector<double> angles;
  for (std::size_t k = 0; k < by_count.size() && k < kMaxSampleGroups; ++k) angles.push_back(by_count[k].first / kSamplePlotDegPerRad);
  std::sort(angles.begin(), angles.end());
  return angles;
}

Eigen::VectorXd mean_fit(const PairFunction& fit, const RowMatrix3d& wi, const RowMatrix3d& wr) {
  const Eigen::MatrixXd v = fit(wi, wr);
  if (v.rows() != wi.rows() || v.cols() < 1) throw ArgumentError("sample plot: the fit's values have the wrong shape");
  return v.rowwise().mean();
}

}  // namespace

Rgb sample_group_colour(int group) { return series_colour(group); }

SamplePlotFigure plot_samples(const std::string& label, const SampleSet& s, const PairFunction& fit, const std::string& fit_label,
                              const SamplePlotRequest& q, const std::string& path) {
  if (!fit) throw ArgumentError("sample plot: no fit to draw");
  const Eigen::Index n = s.wi.rows();
  if (n < 1 || s.wr.rows() != n || s.values.size() != n)
    throw ArgumentError(fmt::format("sample plot: {} incident, {} remitted directions and {} values, expected as many (>= 1)", n, s.wr.rows(),
                                    s.values.size()));
  if (q.theta_i.size() > kMaxSampleGroups)
    throw ArgumentError(fmt::format("sample plot: at most {} incidence angles, found {}", kMaxSampleGroups, q.theta_i.size()));
  for (double t : q.theta_i)
    if (!(t >= 0.0 && t < M_PI / 2)) throw ArgumentError(fmt::format("sample plot: theta_i {} degrees outside [0, 90)", t * kSamplePlotDegPerRad));
  std::vector<InPlane> places(static_cast<std::size_t>(n));
  for (Eigen::Index k = 0; k < n; ++k) places[static_cast<std::size_t>(k)] = in_plane(s.wi.row(k), s.wr.row(k));
  const std::vector<double> angles = q.theta_i.empty() ? populated_angles(places) : q.theta_i;
  if (angles.empty())
    throw ArgumentError(fmt::format("sample plot '{}': none of the {} samples lies within {} degrees of its plane of incidence", label, n,
                                    format_number(kPlaneTolerance * kSamplePlotDegPerRad)));

  SamplePlotFigure out;
  out.total = n;
  const Eigen::VectorXd fitted = mean_fit(fit, s.wi, s.wr);
  double sum2 = 0.0;
  long long finite = 0;
  for (Eigen::Index k = 0; k < n; ++k)
    if (std::isfinite(s.values(k) - fitted(k))) sum2 += (s.values(k) - fitted(k)) * (s.values(k) - fitted(k)), ++finite;
  out.residual_rms = finite ? std::sqrt(sum2 / static_cast<double>(finite)) : std::nan("");

  // Each in-plane sample joins the nearest group within kIncidenceTolerance.
  const int groups = static_cast<int>(angles.size());
  std::vector<double> sum_t(angles.size(), 0.0), sum_c(angles.size(), 0.0), sum_s(angles.size(), 0.0);
  std::vector<int> members(angles.size(), 0);
  for (Eigen::Index k = 0; k < n; ++k) {
    const InPlane& p = places[static_cast<std::size_t>(k)];
    if (!p.in) continue;
    int best = -1;
    for (int g = 0; g < groups; ++g)
      if (std::fabs(p.theta_i - angles[g]) <= kIncidenceTolerance && (best < 0 || std::fabs(p.theta_i - angles[g]) < std::fabs(p.theta_i - angles[best])))
        best = g;
    if (best < 0) continue;
    out.points.push_back({k, best, p.x_deg, fitted(k)});
    sum_t[best] += p.theta_i, ++members[best];
    // The sample's own azimuth of incidence (atan2 of w_i, also near the normal) set the sign of its x: the curve follows it.
    sum_c[best] += std::cos(p.phi_i), sum_s[best] += std::sin(p.phi_i);
  }
  if (out.points.empty())
    throw ArgumentError(fmt::format("sample plot '{}': no sample within {} degree of the incidence angles asked lies within {} degrees of its plane of incidence",
                                    label, format_number(kIncidenceTolerance * kSamplePlotDegPerRad), format_number(kPlaneTolerance * kSamplePlotDegPerRad)));

  // Series: the groups' fitted curves, then their samples (markers on top), then the residuals.
  const Eigen::VectorXd t = Eigen::VectorXd::LinSpaced(kFitCurveSamples, -kFitCurveReach, kFitCurveReach);
  std::vector<Series> top, bottom;
  for (int g = 0; g < groups; ++g) {
    const double theta = members[g] ? sum_t[g] / members[g] : angles[g];
    const double phi = sum_c[g] != 0.0 || sum_s[g] != 0.0 ? std::atan2(sum_s[g], sum_c[g]) : 0.0;
    out.group_theta_deg.push_back(theta * kSamplePlotDegPerRad);
    const RowMatrix3d plane = plane_of_incidence_directions(phi, t);
    RowMatrix3d wis(plane.rows(), 3);
    wis.rowwise() = Eigen::RowVector3d(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
    const Eigen::VectorXd curve = mean_fit(fit, wis, plane);
    Series c;
    c.label = fmt::format("theta_i = {}\u00b0 ({} samples)", format_number(std::round(theta * kSamplePlotDegPerRad * 10) / 10), members[g]);
    c.colour = sample_group_colour(g);
    c.marker = Marker::None;
    for (Eigen::Index m = 0; m < t.size(); ++m) c.x.push_back(t(m) * kSamplePlotDegPerRad), c.y.push_back(curve(m));
    top.push_back(std::move(c));
  }
  for (int g = 0; g < groups; ++g) {
    Series v, r;
    v.colour = r.colour = sample_group_colour(g);
    v.marker = r.marker = Marker::Circle;
    v.line = r.line = false;
    for (const auto& p : out.points)
      if (p.group == g) v.x.push_back(p.x_deg), v.y.push_back(s.values(p.sample)), r.x.push_back(p.x_deg), r.y.push_back(s.values(p.sample) - p.fit);
    top.push_back(std::move(v));
    bottom.push_back(std::move(r));
  }
  bottom.push_back(Series{"", {-90.0, 90.0}, {0.0, 0.0}, kZeroLine, Marker::None, true, true, 1.0});

  out.width = 940;
  out.height = 760;
  Figure fig(out.width, out.height);
  fig.title("Samples and fit of " + (label.size() > 70 ? "..." + label.substr(label.size() - 67) : label), 17.0);
  fig.text(out.width / 2.0, 50,
           fmt::format("{} of {} samples lie within {}\u00b0 of their plane of incidence (drawn); residual RMS over all {}: {} 1/sr", out.points.size(), n,
                       format_number(kPlaneTolerance * kSamplePlotDegPerRad), n, format_number(out.residual_rms)),
           12.0, Align::Centre);
  ChartOptions co;
  co.x_label = "signed theta_r [deg] (forward side > 0)";
  co.y_label = "f [1/sr] (channel mean)";
  co.log_y = q.log;
  co.x_min = -90;
  co.x_max = 90;
  co.legend = LegendPlace::Right;
  ChartOptions ro = co;
  ro.log_y = false;
  ro.y_label = "sample - fit [1/sr]";
  ro.legend = LegendPlace::None;
  ro.note = "fit: " + fit_label;
  // Symmetric about zero, with room beyond the largest residual drawn (no point on the frame).
  double largest = 0.0;
  for (const auto& p : out.points)
    if (std::isfinite(s.values(p.sample) - p.fit)) largest = std::max(largest, std::fabs(s.values(p.sample) - p.fit));
  if (largest > 0) ro.y_min = -1.15 * largest, ro.y_max = 1.15 * largest;
  ChartBox tb{0, 60, out.width, 430}, rb{0, 500, out.width, out.height - 500};
  // The residual panel's plot area starts where the values' does: one x axis for both.
  const ChartFrame ft = chart_frame(fig, tb, top, co), fr = chart_frame(fig, rb, bottom, ro);
  const int shift = static_cast<int>(std::lround(ft.left - fr.left));
  ChartBox& narrowed = shift > 0 ? rb : tb;
  narrowed.x += std::abs(shift);
  narrowed.width -= std::abs(shift);
  rb.width -= static_cast<int>(std::lround(fr.right - ft.right));  // the values' legend is at their right
  out.values = draw_line_chart(fig, tb, top, co);
  out.residuals = draw_line_chart(fig, rb, bottom, ro);
  for (auto& p : out.points) {
    p.value_px = out.values.px(p.x_deg), p.value_py = out.values.py(s.values(p.sample));
    p.residual_px = out.residuals.px(p.x_deg), p.residual_py = out.residuals.py(s.values(p.sample) - p.fit);
  }
  fig.save_png(path);
  return out;
}

}  // namespace icobrdf::plot
