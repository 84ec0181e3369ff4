#pragma once
// Figure: a white RGB canvas drawn with cairo, with the pieces every picture uses (titles, labels, raster
// images placed pixel for pixel, colour bars, contour lines) and an atomic PNG writer.
// Coordinates are in pixels, origin at the top-left corner, y down. Text uses DejaVu Sans (any sans face
// fontconfig finds).
#include <Eigen/Core>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "icobrdf/plot/colormap.hpp"

typedef struct _cairo cairo_t;
typedef struct _cairo_surface cairo_surface_t;

namespace icobrdf::plot {

// The typeface of every picture's text (fontconfig picks the nearest installed face).
inline constexpr const char* kFontFace = "DejaVu Sans";

// A raster of colours, row-major, row 0 at the top. Pixels with `mask` 0 are left transparent when placed.
struct Raster {
  int width = 0, height = 0;
  std::vector<Rgb> pixels;
  std::vector<std::uint8_t> mask;
  Raster(int w, int h) : width(w), height(h), pixels(static_cast<std::size_t>(w) * h), mask(static_cast<std::size_t>(w) * h, 0) {}
  void set(int row, int col, const Rgb& c) {
    pixels[static_cast<std::size_t>(row) * width + col] = c;
    mask[static_cast<std::size_t>(row) * width + col] = 1;
  }
};

// values (rows x cols, NaN = no data) -> Raster through a colour map of value / scale.
Raster colorize(const Eigen::MatrixXd& values, double scale, Rgb (*map)(double));

enum class Align { Left, Centre, Right };

class Figure {
 public:
  Figure(int width, int height);
  ~Figure();
  Figure(const Figure&) = delete;
  Figure& operator=(const Figure&) = delete;

  int width() const { return width_; }
  int height() const { return height_; }
  cairo_t* context() { return cr_; }

  // Text with its baseline at y; `angle` in radians (counter-clockwise on screen).
  void text(double x, double y, const std::string& s, double size, Align align = Align::Left, bool bold = false,
            double angle = 0.0);
  void title(const std::string& s, double size = 18.0);  // centred, near the top
  // Places a raster with its top-left pixel at integer (x, y): one raster pixel = one image pixel.
  void image(const Raster& r, int x, int y);
  // Vertical colour bar at (x, y, w, h) for values in [-scale, scale] (map of value / scale), ticks at
  // -scale, -scale/2, 0, scale/2, scale, and a label (the unit) written vertically at its right.
  // With `signed_range` false the bar covers [0, scale] (map of value / scale in [0, 1]).
  void colorbar(int x, int y, int w, int h, double scale, Rgb (*map)(double), const std::string& label,
                bool signed_range = true);
  // Contour lines of `values` (NaN = no data) at the given levels, in the raster placed at (x, y):
  // marching squares through pixel centres. Zero gets a solid dark line, other levels thin lines.
  void contours(const Eigen::MatrixXd& values, int x, int y, const std::vector<double>& levels);
  void circle(double cx, double cy, double r, double line_width, double grey = 0.0);
  void line(double x0, double y0, double x1, double y1, double line_width, const Rgb& c, bool dashed = false);

  // sRGB bytes of the pixel (x, y) as drawn so far.
  std::array<int, 3> pixel(int x, int y);
  // Writes the PNG atomically (temporary file + rename); IoError when cairo or the file system fails.
  void save_png(const std::string& path);

 private:
  int width_, height_;
  cairo_surface_t* surface_;
  cairo_t* cr_;
};

// Reads a PNG back: width, height and a pixel accessor (for tests and checks); IoError when unreadable.
struct PngImage {
  int width = 0, height = 0;
  std::vector<std::array<int, 3>> rgb;  // row-major
  const std::array<int, 3>& at(int x, int y) const { return rgb[static_cast<std::size_t>(y) * width + x]; }
};
PngImage read_png(const std::string& path);

// Numbers for labels: "0.318", "-1.2e-05", "12".
std::string format_number(double v);

}  // namespace icobrdf::plot
