#pragma once
// The pictures of `icobrdf plot`: basis functions, slices, spectra and lit spheres, written as PNG
// (atomically: a failed plot leaves no file). Every picture has a title, axis labels and a colour bar
// with its unit. The returned layouts say where the disk / sphere rasters are (for checks by pixel).
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "icobrdf/core/grid/grid.hpp"
#include "icobrdf/core/basis/lowpass_filter.hpp"
#include "icobrdf/core/spectrum/spectrum.hpp"

namespace icobrdf::plot {

// A square raster of `size` pixels placed with its top-left pixel at (x, y).
struct PanelRect {
  int x = 0, y = 0, size = 0;
};

// The BRDF itself: f [1/sr] at direction pairs (rows x 3 each), rows x channels (for example
// BrdfSource::eval of a model without delta parts).
using PairFunction = std::function<Eigen::MatrixXd(const RowMatrix3d& wi, const RowMatrix3d& wr)>;

// Argument checks here throw ArgumentError with neutral wording; `icobrdf plot` checks its flags first
// and words the same conditions after them (cli/cmd_plot.cpp).

// `out` is a folder (DIR/basis.png, and the --separate files there) or a FILE.png (the pyramid; separate
// files beside it). ArgumentError naming both forms when it is neither an existing folder nor a .png name.
// Every K_n^l with n <= order on the Lambert disk (density in the diverging map + contours at multiples
// of 0.2 max|K|, zero contour bold), as a pyramid: row n, l = -n..n step 2 left to right. Writes
// DIR/basis.png and, when `separate`, DIR/K_<n>_<l>.png per function (with its colour bar in 1/sqrt(sr)).
// Returns the files written. `order` in [0, kMaxBasisOrder]; `panel` = disk diameter in pixels, in
// [kMinBasisPanel, kMaxBasisPanel] (0: from the order).
// The pyramid's row n holds n + 1 disks: at order 16, 17 across (153 in all), about 1,600 pixels wide at the
// default panel of 60 pixels (plot_basis: 30 + 17 x (60 + 24) + 150).
inline constexpr int kMaxBasisOrder = 16;
// Disk diameters (pixels): 32 leaves 2 pixels per radial zero of K_16 (its radial polynomial R_16^0 has 8 zeros
// on a radius of 16 pixels); 800 keeps the order-16 picture within 30 + 17 x (800 + 24) + 150 = 14,188 pixels wide.
inline constexpr int kMinBasisPanel = 32, kMaxBasisPanel = 800;
std::vector<std::string> plot_basis(int order, const std::string& dir, bool separate, int panel = 0);

struct SliceRequest {
  double theta_i = 0.785398163397448;  // radians
  double phi_i = 0.0;
  std::vector<int> orders{0, 1, 2, 4, 6, 8};
  LowPassFilter filter;
  int panel = 200;
  bool exact = true;  // add the values themselves as a last column (when SliceSource::exact is set)
  bool log = false;   // logarithmic colour and polar scale (icobrdf/plot/value_scale.hpp), kDefaultDecades
};
// What a slice is drawn from, already loaded: a spectrum of order >= every requested order (truncated per
// column; drawn as g = f cos(theta_i) when spectrum.cosine) and/or the BRDF itself (a model, or measured
// data evaluated directly: then no order needs to be asked for).
struct SliceSource {
  std::string label;   // the title (the SOURCE as the user named it)
  std::optional<Spectrum> spectrum;
  PairFunction exact;  // empty: no column of the values themselves
  std::string exact_kind = "model";  // that column's title
};
struct SliceFigure {
  std::vector<PanelRect> disks;  // one per column (orders, then the values themselves when drawn)
  double scale = 0.0;            // largest |value| in 1/sr: the colour bar's top
  bool signed_map = false;       // diverging map over [-scale, scale]; else sequential over [0, scale]
  bool g_form = false;           // g = f cos(theta_i) is drawn instead of f
  int width = 0, height = 0;
};
// Orders in [0, 32], at most 9 of them, none beyond the spectrum's (none at all is allowed when the source
// has its values: one column of them); theta_i in [0, pi/2). Disks carry theta rings at 30 and 60 degrees
// and phi labels; the polar plots' rings are labelled with their values.
SliceFigure plot_slice(const SliceSource& source, const SliceRequest& request, const std::string& path);

struct SpectrumFigure {
  int width = 0, height = 0;
  bool matrix_drawn = false;
  double scale = 0.0;  // the colour scale's top: the largest |coefficient| but the DC one
};
// The IBSSS layout of the paper's Fig. 3 (of the channel mean) and, for spectra not marked isotropic,
// the coefficient matrix C as an image, on a diverging scale (linear, or signed log with `log`) set by every
// coefficient but the DC one, whose value is written out (it would otherwise dwarf the rest).
SpectrumFigure plot_spectrum(const Spectrum& spectrum, const std::string& label, const std::string& path, bool log = false);

struct SphereRequest {
  double light_theta = 0.785398163397448, light_phi = 2.35619449019234;  // radians, camera frame
  double sky = 0.0;        // sky radiance (0: none)
  double exposure = 1.0;   // radiance shown as white
  int size = 256;          // sphere diameter in pixels
  // Auto: from the model when the material has one, else from its spectrum.
  enum class Shading { Auto, Model, Spectrum } shading = Shading::Auto;
};
// One material of a sphere picture: its spectrum and/or the BRDF itself (a model without delta parts).
struct SphereMaterial {
  std::string name;
  std::optional<Spectrum> spectrum;
  PairFunction model;
  int model_channels = 1;  // columns of model(wi, wr)
};
struct SphereFigure {
  std::vector<PanelRect> spheres;
  std::vector<std::string> names;
  int width = 0, height = 0;
};
// One sphere titled `title`, or, for several materials, a grid of spheres titled "Materials of <title>" and
// labelled with their names (captioned as shaded from stored spectra: meant for a bank's spectra). Each is
// shaded as request.shading says: Model needs the material's `model`, Spectrum its `spectrum`, Auto takes
// the model when there is one.
SphereFigure plot_sphere(const std::string& title, const std::vector<SphereMaterial>& materials, const SphereRequest& request,
                         const std::string& path);

}  // namespace icobrdf::plot
