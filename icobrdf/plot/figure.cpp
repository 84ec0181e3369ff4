#include "icobrdf/plot/figure.hpp"

#include <cairo.h>
#include <fmt/core.h>

#include <cmath>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/io/atomic_write.hpp"

namespace icobrdf::plot {
namespace {


std::uint32_t pack(const Rgb& c) {
  auto byte = [](double v) { return static_cast<std::uint32_t>(std::lround(std::clamp(v, 0.0, 1.0) * 255.0)); };
  return 0xFF000000u | (byte(c[0]) << 16) | (byte(c[1]) << 8) | byte(c[2]);
}

}  // namespace

Raster colorize(const Eigen::MatrixXd& values, double scale, Rgb (*map)(double)) {
  Raster r(static_cast<int>(values.cols()), static_cast<int>(values.rows()));
  const double s = scale > 0.0 && std::isfinite(scale) ? scale : 1.0;
  for (int i = 0; i < values.rows(); ++i)
    for (int j = 0; j < values.cols(); ++j)
      if (std::isfinite(values(i, j))) r.set(i, j, map(values(i, j) / s));
  return r;
}

Figure::Figure(int width, int height) : width_(width), height_(height) {
  if (width <= 0 || height <= 0 || width > 16384 || height > 16384)
    throw ArgumentError(fmt::format("image size {}x{}: expected 1..16384 pixels each way", width, height));
  surface_ = cairo_image_surface_create(CAIRO_FORMAT_RGB24, width, height);
  cr_ = cairo_create(surface_);
  if (cairo_status(cr_) != CAIRO_STATUS_SUCCESS)
    throw IoError(std::string("cairo: cannot create the image: ") + cairo_status_to_string(cairo_status(cr_)));
  cairo_set_source_rgb(cr_, 1, 1, 1);
  cairo_paint(cr_);
}

Figure::~Figure() {
  cairo_destroy(cr_);
  cairo_surface_destroy(surface_);
}

void Figure::text(double x, double y, const std::string& s, double size, Align align, bool bold, double angle) {
  cairo_save(cr_);
  cairo_select_font_face(cr_, kFontFace, CAIRO_FONT_SLANT_NORMAL, bold ? CAIRO_FONT_WEIGHT_BOLD : CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr_, size);
  cairo_text_extents_t e;
  cairo_text_extents(cr_, s.c_str(), &e);
  const double dx = align == Align::Left ? 0.0 : align == Align::Centre ? -e.x_advance / 2 : -e.x_advance;
  cairo_translate(cr_, x, y);
  cairo_rotate(cr_, -angle);
  cairo_move_to(cr_, dx, 0.0);
  cairo_set_source_rgb(cr_, 0.08, 0.08, 0.08);
  cairo_show_text(cr_, s.c_str());
  cairo_restore(cr_);
}

void Figure::title(const std::string& s, double size) { text(width_ / 2.0, 8.0 + size, s, size, Align::Centre, true); }

void Figure::image(const Raster& r, int x, int y) {
  cairo_surface_flush(surface_);
  unsigned char* data = cairo_image_surface_get_data(surface_);
  const int stride = cairo_image_surface_get_stride(surface_);
  for (int i = 0; i < r.height; ++i) {
    const int py = y + i;
    if (py < 0 || py >= height_) continue;
    auto* row = reinterpret_cast<std::uint32_t*>(data + static_cast<std::ptrdiff_t>(py) * stride);
    for (int j = 0; j < r.width; ++j) {
      const int px = x + j;
      const std::size_t k = static_cast<std::size_t>(i) * r.width + j;
      if (px < 0 || px >= width_ || !r.mask[k]) continue;
      row[px] = pack(r.pixels[k]);
    }
  }
  cairo_surface_mark_dirty(surface_);
}

void Figure::colorbar(int x, int y, int w, int h, double scale, Rgb (*map)(double), const std::string& label,
                      bool signed_range) {
  Raster bar(w, h);
  for (int i = 0; i < h; ++i) {
    const double t = signed_range ? 1.0 - 2.0 * (i + 0.5) / h : 1.0 - (i + 0.5) / h;
    for (int j = 0; j < w; ++j) bar.set(i, j, map(t));
  }
  image(bar, x, y);
  cairo_save(cr_);
  cairo_set_source_rgb(cr_, 0.1, 0.1, 0.1);
  cairo_set_line_width(cr_, 1.0);
  cairo_rectangle(cr_, x + 0.5, y + 0.5, w - 1.0, h - 1.0);
  cairo_stroke(cr_);
  double widest = 0.0;
  for (int k = 0; k <= 4; ++k) {
    const double v = signed_range ? scale * (1.0 - 0.5 * k) : scale * (1.0 - 0.25 * k);
    const double ty = y + h * (0.25 * k);
    cairo_move_to(cr_, x + w, ty);
    cairo_line_to(cr_, x + w + 5, ty);
    cairo_stroke(cr_);
    const std::string s = format_number(v);
    text(x + w + 8, ty + 4.5, s, 12.0);
    cairo_select_font_face(cr_, kFontFace, CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
    cairo_set_font_size(cr_, 12.0);
    cairo_text_extents_t e;
    cairo_text_extents(cr_, s.c_str(), &e);
    widest = std::max(widest, e.x_advance);
  }
  cairo_restore(cr_);
  text(x + w + 14 + widest + 12, y + h / 2.0, label, 13.0, Align::Centre, false, M_PI / 2);
}

void Figure::contours(const Eigen::MatrixXd& v, int x, int y, const std::vector<double>& levels) {
  cairo_save(cr_);
  for (double level : levels) {
    const bool zero = level == 0.0;
    cairo_set_line_width(cr_, zero ? 1.3 : 0.7);
    if (zero) cairo_set_source_rgba(cr_, 0.0, 0.0, 0.0, 0.85);
    else cairo_set_source_rgba(cr_, 0.1, 0.1, 0.1, 0.45);
    for (int i = 0; i + 1 < v.rows(); ++i) {
      for (int j = 0; j + 1 < v.cols(); ++j) {
        // Corners in order: (i,j), (i,j+1), (i+1,j+1), (i+1,j); pixel centres at +0.5.
        const double c[4] = {v(i, j), v(i, j + 1), v(i + 1, j + 1), v(i + 1, j)};
        if (!(std::isfinite(c[0]) && std::isfinite(c[1]) && std::isfinite(c[2]) && std::isfinite(c[3]))) continue;
        const double px[4] = {j + 0.5, j + 1.5, j + 1.5, j + 0.5};
        const double py[4] = {i + 0.5, i + 0.5, i + 1.5, i + 1.5};
        double ex[4], ey[4];
        int found = 0;
        for (int e = 0; e < 4; ++e) {
          const int a = e, b = (e + 1) % 4;
          const double da = c[a] - level, db = c[b] - level;
          if ((da < 0.0) != (db < 0.0)) {
            const double u = da / (da - db);
            ex[found] = x + px[a] + u * (px[b] - px[a]);
            ey[found] = y + py[a] + u * (py[b] - py[a]);
            ++found;
          }
        }
        for (int s = 0; s + 1 < found; s += 2) {
          cairo_move_to(cr_, ex[s], ey[s]);
          cairo_line_to(cr_, ex[s + 1], ey[s + 1]);
        }
      }
    }
    cairo_stroke(cr_);
  }
  cairo_restore(cr_);
}

void Figure::circle(double cx, double cy, double r, double line_width, double g) {
  cairo_save(cr_);
  cairo_set_source_rgb(cr_, g, g, g);
  cairo_set_line_width(cr_, line_width);
  cairo_new_path(cr_);
  cairo_arc(cr_, cx, cy, r, 0, 2 * M_PI);
  cairo_stroke(cr_);
  cairo_restore(cr_);
}

void Figure::line(double x0, double y0, double x1, double y1, double line_width, const Rgb& c, bool dashed) {
  cairo_save(cr_);
  cairo_set_source_rgb(cr_, c[0], c[1], c[2]);
  cairo_set_line_width(cr_, line_width);
  if (dashed) {
    const double d[2] = {4.0, 3.0};
    cairo_set_dash(cr_, d, 2, 0.0);
  }
  cairo_move_to(cr_, x0, y0);
  cairo_line_to(cr_, x1, y1);
  cairo_stroke(cr_);
  cairo_restore(cr_);
}

std::array<int, 3> Figure::pixel(int x, int y) {
  cairo_surface_flush(surface_);
  const unsigned char* data = cairo_image_surface_get_data(surface_);
  const int stride = cairo_image_surface_get_stride(surface_);
  const std::uint32_t p = reinterpret_cast<const std::uint32_t*>(data + static_cast<std::ptrdiff_t>(y) * stride)[x];
  return {static_cast<int>((p >> 16) & 0xFF), static_cast<int>((p >> 8) & 0xFF), static_cast<int>(p & 0xFF)};
}

void Figure::save_png(const std::string& path) {
  cairo_surface_flush(surface_);
  atomic_write(path, [&](const std::string& temp) {
    const cairo_status_t st = cairo_surface_write_to_png(surface_, temp.c_str());
    if (st != CAIRO_STATUS_SUCCESS)
      throw IoError(path + ": cannot write the PNG: " + cairo_status_to_string(st));
  });
}

PngImage read_png(const std::string& path) {
  cairo_surface_t* s = cairo_image_surface_create_from_png(path.c_str());
  if (cairo_surface_status(s) != CAIRO_STATUS_SUCCESS) {
    const std::string why = cairo_status_to_string(cairo_surface_status(s));
    cairo_surface_destroy(s);
    throw IoError(path + ": cannot read as PNG: " + why);
  }
  PngImage img;
  img.width = cairo_image_surface_get_width(s);
  img.height = cairo_image_surface_get_height(s);
  const unsigned char* data = cairo_image_surface_get_data(s);
  const int stride = cairo_image_surface_get_stride(s);
  img.rgb.resize(static_cast<std::size_t>(img.width) * img.height);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const std::uint32_t p = reinterpret_cast<const std::uint32_t*>(data + static_cast<std::ptrdiff_t>(y) * stride)[x];
      img.rgb[static_cast<std::size_t>(y) * img.width + x] = {static_cast<int>((p >> 16) & 0xFF), static_cast<int>((p >> 8) & 0xFF),
                                                            static_cast<int>(p & 0xFF)};
    }
  cairo_surface_destroy(s);
  return img;
}

std::string format_number(double v) {
  if (v == 0.0) return "0";
  const double a = std::fabs(v);
  if (a >= 1e-3 && a < 1e4) {
    std::string s = fmt::format("{:.3g}", v);
    return s;
  }
  return fmt::format("{:.2g}", v);
}

}  // namespace icobrdf::plot
