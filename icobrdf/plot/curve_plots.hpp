#pragma once
// One-dimensional pictures of a BRDF, as BRDF explorers draw them: in-plane curves (Cartesian and polar,
// linear or log) and the directional albedo against the angle of incidence. Both evaluate the function they
// are given directly at their directions (a model, measured data, or a spectrum's values): nothing is fitted.
//
// In-plane curves: for each theta_i, the values (channel mean) at remitted directions in the plane of
// incidence, signed theta_r in [-90, 90] degrees: > 0 on the forward side (azimuth phi_i + 180, where the
// mirror direction lies), < 0 on the backward side (icobrdf/plot/slice_data.hpp, plane_of_incidence_directions).
// Left: Cartesian, value against signed theta_r; right: polar, radius = value on the scale (linear, or log over
// kDefaultDecades decades, icobrdf/plot/value_scale.hpp), angle = theta_r from the normal, forward side left.
//
// Directional albedo: a(theta_i) = integral f(w_i, w) cos(theta) dOmega_w per channel, by the midpoint rule over
// the cells of the level-kCurveAlbedoLevel equal-area tessellation (cells of about 2.8 degrees); a lobe
// narrower than a cell is integrated only to the accuracy of that rule. A passive material
// has a <= 1 (drawn as a dashed line).
#include <string>
#include <vector>

#include "icobrdf/plot/line_chart.hpp"
#include "icobrdf/plot/plots.hpp"
#include "icobrdf/plot/value_scale.hpp"

namespace icobrdf::plot {

inline constexpr int kCurveAlbedoLevel = 4;
inline constexpr std::size_t kMaxCurves = 9;  // incidence angles in one picture (the palette's distinct colours)

struct CurveRequest {
  std::vector<double> theta_i{0.0, 0.523598775598299, 1.047197551195966};  // radians, each in [0, pi/2)
  double phi_i = 0.0;                                                        // radians
  bool log = false;
};
struct CurveFigure {
  ChartFrame cartesian;           // where the Cartesian chart's data lie (pixels)
  double polar_cx = 0, polar_cy = 0, polar_radius = 0;  // the polar chart's origin and outer ring
  ValueScale scale;               // the polar chart's radial scale (from the largest value drawn)
  int width = 0, height = 0;
};
// One polar curve centred at (cx, cy): the point at angle t[m] from the vertical (positive to the left, the
// forward side) and radius R |scale.unit(v[m])|, for the values whose sign is `negative` (< 0) or not (>= 0);
// the line breaks at the others and at non-finite values.
void draw_polar_curve(Figure& fig, const Eigen::MatrixXd& v, const Eigen::VectorXd& t, double cx, double cy, double R,
                      const ValueScale& scale, const Rgb& colour, bool negative);

// `quantity`: the name of the values ("f", or "g = f cos(theta_i)" for a spectrum of g).
CurveFigure plot_curves(const std::string& label, const PairFunction& values, const std::string& quantity, const CurveRequest& request,
                        const std::string& path);

struct AlbedoFigure {
  ChartFrame frame;
  std::vector<double> theta_i_deg;          // the x values
  std::vector<std::vector<double>> albedo;  // per channel, per theta_i
  int width = 0, height = 0;
};
// a(theta_i) for theta_i = 0, 2, ..., 88 degrees at azimuth `phi_i` (radians), one curve per channel
// (`channel_names` label them; empty: "mean" for one channel, "channel k" otherwise).
AlbedoFigure plot_albedo(const std::string& label, const PairFunction& values, int channels, const std::vector<std::string>& channel_names,
                         double phi_i, const std::string& path);

}  // namespace icobrdf::plot
