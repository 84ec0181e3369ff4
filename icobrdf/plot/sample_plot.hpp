#pragma once
// Measured samples over their fit: scattered samples (a CSV file, a CURET sample) drawn as points over the
// fitted in-plane curve, and below them their residuals (sample - fit) on a linear scale of their own.
//
// Which samples are drawn: those whose remitted direction lies within kPlaneTolerance of the plane of incidence
// of their own incident direction (|phi_r - phi_i| or |phi_r - phi_i - 180 deg| <= kPlaneTolerance, or
// theta_r < kNormalTolerance), grouped by incidence: each group holds the samples with theta_i within
// kIncidenceTolerance of one angle. Without a request, the groups are the kMaxSampleGroups incidence angles
// (rounded to whole degrees) with the most such samples, ascending. A sample's abscissa is its signed theta_r in
// degrees (> 0 on the forward (mirror) side, azimuth phi_i + 180), as in the in-plane curves
// (icobrdf/plot/curve_plots.hpp); the group's curve is the fit along the plane of incidence at the group's mean
// theta_i and mean azimuth. A point's residual is the sample minus the fit at the sample's own direction pair,
// so it is exact even where the sample sits a few degrees off the plane the curve is drawn in.
// Values: the channel mean, f in 1/sr. Every residual of every sample (drawn or not) enters the RMS reported.
#include <cmath>
#include <string>
#include <vector>

#include "icobrdf/plot/line_chart.hpp"
#include "icobrdf/plot/plots.hpp"

namespace icobrdf::plot {

// NIST's PTFE set and CURET put their in-plane geometries within 2 degrees of the plane; 5 degrees keeps them
// and leaves out the next azimuths of a 4-D set (10 degrees and more away), whose values the in-plane curve
// does not show.
inline constexpr double kPlaneTolerance = 5.0 * M_PI / 180.0;
// Below this theta_r a remitted direction lies in every plane (its azimuth is meaningless).
inline constexpr double kNormalTolerance = 0.5 * M_PI / 180.0;
// Incidence angles of one group: measured set-ups repeat an angle to well within a degree.
inline constexpr double kIncidenceTolerance = 1.0 * M_PI / 180.0;
inline constexpr std::size_t kMaxSampleGroups = 6;

// Samples: pairs of unit directions (w_i towards the light) and their value (channel mean) [1/sr].
struct SampleSet {
  RowMatrix3d wi, wr;
  Eigen::VectorXd values;
};

struct SamplePlotRequest {
  std::vector<double> theta_i;  // radians, each in [0, pi/2); empty: the most populated incidence angles
  bool log = false;             // logarithmic value axis (the residual axis stays linear)
};

struct SamplePoint {
  Eigen::Index sample = 0;  // row of the SampleSet
  int group = 0;
  double x_deg = 0.0;        // signed theta_r
  double fit = 0.0;          // the fit at the sample's own pair
  double value_px = 0, value_py = 0, residual_px = 0, residual_py = 0;  // centres of its markers
};

struct SamplePlotFigure {
  ChartFrame values, residuals;    // the two panels (residuals below)
  std::vector<double> group_theta_deg;
  std::vector<SamplePoint> points;  // the samples drawn
  Eigen::Index total = 0;           // samples in the set
  double residual_rms = 0.0;        // over every sample [1/sr]
  int width = 0, height = 0;
};

// The colour of group k's curve, points and residuals.
Rgb sample_group_colour(int group);

// `fit` evaluates the fit at direction pairs (rows x channels; the channel mean is drawn); `fit_label` says what
// it is (a caption line). ArgumentError when no sample lies in a plane of incidence of a requested group.
SamplePlotFigure plot_samples(const std::string& label, const SampleSet& samples, const PairFunction& fit, const std::string& fit_label,
                              const SamplePlotRequest& request, const std::string& path);

}  // namespace icobrdf::plot
