#pragma once
// The option forms of `icobrdf plot`, read and checked here so that the command stays a thin adapter:
// light directions, shading names, and what a picture of a SOURCE evaluates (its values, or a spectrum).
// Errors are ArgumentError, one line naming the flag.
#include <string>
#include <utility>
#include <vector>

#include "icobrdf/pipeline/picture_source.hpp"
#include "icobrdf/plot/plots.hpp"
#include "icobrdf/plot/sample_plot.hpp"

namespace icobrdf::plot {

// "THETA,PHI" in degrees, 0 <= THETA <= 180, PHI finite.
std::pair<double, double> parse_light(const std::string& text);
// auto | model | spectrum.
SphereRequest::Shading parse_shading(const std::string& text);
// A sphere picture's request from the option forms: light "THETA,PHI" [deg] (parse_light), sky radiance
// (0: none), exposure, size [pixels] and shading name (parse_shading).
SphereRequest sphere_request(const std::string& light, double sky, double exposure, int size, const std::string& shading);
// A slice picture's request: incidence [deg], low-pass filter name (parse_lowpass_filter), panel [pixels],
// the exact values as a last column, logarithmic scale. Its orders are set by load_slice_source.
SliceRequest slice_request(double theta_i_deg, double phi_i_deg, const std::string& filter, int panel, bool exact, bool log);
// The spectrum a spectrum picture draws: SPECTRUM.h5[#material] `text` (Zernike modes only); ArgumentError
// for any other form, UnsupportedError for a material of another representation.
Spectrum load_spectrum_picture(const std::string& text);

// The source of a slice picture of SOURCE `text` at truncation `orders`. A source with values of its own
// (a measured file, a model without delta parts) is not fitted when `orders_given` is false: one column of its
// values (seconds, where a fit of a measured file takes a minute); otherwise it is fitted once at the largest
// order, on the equal-area grid of `level`. `orders` is cleared when nothing was fitted. Without `orders_given`, a
// stored material with a lobe is drawn from its values alone, and a stored spectrum at the default orders up to
// its own order and at its own.
SliceSource load_slice_source(const std::string& text, std::vector<int>& orders, bool orders_given, int level);

// What curve and albedo pictures evaluate: the values of SOURCE `text` when known everywhere (unfitted), else
// its spectrum (stored, or fitted at `order` on the equal-area grid of `level`) evaluated pair by pair.
struct PictureValues {
  PairFunction values;
  int channels = 1;
  std::string quantity = "f";  // "g = f cos(theta_i)" for a spectrum of g
};
PictureValues load_picture_values(const std::string& text, int order, int level);

// What a sample picture draws: the scattered samples of SOURCE `text` (CSV samples, a CURET sample:
// icobrdf/io/measured_sources.hpp samples_of; channel mean) and their fit as `icobrdf fit` makes it: at `order`, or
// with -1 at the order and modes the source chooses by cross-validation (icobrdf/pipeline/fit_order.hpp), on the
// equal-area grid of `level` (its albedo figure only). `fit_label` says what was fitted. ArgumentError naming the
// SOURCE for any other source (it has no samples of its own).
struct SamplePicture {
  SampleSet samples;
  PairFunction fit;
  std::string fit_label;
};
SamplePicture load_sample_picture(const std::string& text, int order, int level);

}  // namespace icobrdf::plot
