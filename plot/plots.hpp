#pragma once
// The pictures of `icobrdf plot`: basis functions, slices, spectra and lit spheres, written as PNG
// (atomically: a failed plot leaves no file). Every picture has a title, axis labels and a colour bar
// with its unit. The returned layouts say where the disk / sphere rasters are (for checks by pixel).
#include <string>
#include <vector>

#include "core/lowpass_filter.hpp"
#include "core/spectrum.hpp"

namespace icobrdf::plot {

// A square raster of `size` pixels placed with its top-left pixel at (x, y).
struct PanelRect {
  int x = 0, y = 0, size = 0;
};

// Every K_n^l with n <= order on the Lambert disk (density in the diverging map + contours at multiples
// of 0.2 max|K|, zero contour bold), as a pyramid: row n, l = -n..n step 2 left to right. Writes
// DIR/basis.png and, when `separate`, DIR/K_<n>_<l>.png per function (with its colour bar in 1/sqrt(sr)).
// Returns the files written. `order` in [0, 16]; `panel` = disk diameter in pixels (0: from the order).
std::vector<std::string> plot_basis(int order, const std::string& dir, bool separate, int panel = 0);

struct SliceRequest {
  double theta_i = 0.785398163397448;  // radians
  double phi_i = 0.0;
  std::vector<int> orders{0, 1, 2, 4, 6, 8};
  LowPassFilter filter;
  int level = 4;  // grid level of the fit of a model source
  int panel = 200;
  bool exact = true;  // add the model itself as a last column (models without delta parts)
};
struct SliceFigure {
  std::vector<PanelRect> disks;  // one per column (orders, then the exact model when drawn)
  double scale = 0.0;            // colour bar range [-scale, scale] in 1/sr
  bool g_form = false;           // g = f cos(theta_i) is drawn instead of f
  int width = 0, height = 0;
};
// SOURCE: a model (fitted once at the largest requested order on the equal-area grid of `level`, in g form
// when it has delta parts), or a spectrum file FILE.h5[#material] (truncated; orders beyond its own refused).
SliceFigure plot_slice(const std::string& source, const SliceRequest& request, const std::string& path);

struct SpectrumFigure {
  int width = 0, height = 0;
  bool matrix_drawn = false;
};
// The IBSSS layout of the paper's Fig. 3 (of the channel mean) and, for spectra not marked isotropic,
// the coefficient matrix C as an image.
SpectrumFigure plot_spectrum(const Spectrum& spectrum, const std::string& label, const std::string& path);

struct SphereRequest {
  double light_theta = 0.785398163397448, light_phi = 2.35619449019234;  // radians, camera frame
  double sky = 0.0;        // sky radiance (0: none)
  double exposure = 1.0;   // radiance shown as white
  int size = 256;          // sphere diameter in pixels
  int order = 8, level = 4;  // fit of model sources with delta parts / spectrum shading
  std::string shading = "auto";  // auto | model | spectrum
};
struct SphereFigure {
  std::vector<PanelRect> spheres;
  std::vector<std::string> names;
  int width = 0, height = 0;
};
// SOURCE: a model, a spectrum file, FILE.h5#material, or a bank with several materials (a grid of spheres).
SphereFigure plot_sphere(const std::string& source, const SphereRequest& request, const std::string& path);

}  // namespace icobrdf::plot
