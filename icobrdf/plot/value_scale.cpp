#include "icobrdf/plot/value_scale.hpp"

#include <cairo.h>

#include <algorithm>
#include <cmath>

#include "icobrdf/plot/line_chart.hpp"

namespace icobrdf::plot {

double ValueScale::unit(double v) const {
  if (!std::isfinite(v)) return 0.0;
  if (!log) return is_signed ? std::clamp(v / top, -1.0, 1.0) : std::clamp(v / top, 0.0, 1.0);
  if (is_signed) {
    const double u = std::log10(1.0 + std::fabs(v) / bottom) / std::log10(1.0 + top / bottom);
    return std::copysign(std::min(u, 1.0), v);
  }
  if (!(v > bottom)) return 0.0;
  return std::clamp((std::log10(v) - std::log10(bottom)) / (std::log10(top) - std::log10(bottom)), 0.0, 1.0);
}

double ValueScale::value_at(double u) const {
  if (!log) return u * top;
  if (is_signed) return std::copysign(bottom * (std::pow(1.0 + top / bottom, std::fabs(u)) - 1.0), u);
  return bottom * std::pow(top / bottom, u);
}

Rgb ValueScale::colour(double v) const { return is_signed ? diverging(unit(v)) : sequential(unit(v)); }

std::vector<double> ValueScale::ticks() const {
  std::vector<double> t;
  if (!log) {
    for (double v : axis_ticks(0.0, top, false, 4))
      if (v <= top * (1 + 1e-12)) t.push_back(v);
    if (is_signed) {
      std::vector<double> neg;
      for (double v : t)
        if (v > 0) neg.push_back(-v);
      t.insert(t.begin(), neg.rbegin(), neg.rend());
    }
    return t;
  }
  std::vector<double> pos;
  for (double v : axis_ticks(bottom, top, true, 5))
    if (v >= bottom * (1 - 1e-12) && v <= top * (1 + 1e-12)) pos.push_back(v);
  if (is_signed) {
    for (auto it = pos.rbegin(); it != pos.rend(); ++it) t.push_back(-*it);
    t.push_back(0.0);
  }
  t.insert(t.end(), pos.begin(), pos.end());
  return t;
}

ValueScale value_scale(const std::vector<const Eigen::MatrixXd*>& values, bool log, double decades, bool force_signed) {
  double top = 0.0, lowest = 0.0;
  for (const Eigen::MatrixXd* m : values)
    for (Eigen::Index k = 0; k < m->size(); ++k) {
      const double v = (*m)(k);
      if (!std::isfinite(v)) continue;
      top = std::max(top, std::fabs(v));
      lowest = std::min(lowest, v);
    }
  ValueScale s;
  s.top = top > 0.0 ? top : 1.0;
  s.is_signed = force_signed || lowest < -kSignedShare * s.top;
  s.log = log;
  s.bottom = s.top * std::pow(10.0, -std::max(decades, 0.5));
  return s;
}

Raster colorize(const Eigen::MatrixXd& values, const ValueScale& scale) {
  Raster r(static_cast<int>(values.cols()), static_cast<int>(values.rows()));
  for (int i = 0; i < values.rows(); ++i)
    for (int j = 0; j < values.cols(); ++j)
      if (std::isfinite(values(i, j))) r.set(i, j, scale.colour(values(i, j)));
  return r;
}

void draw_scale_bar(Figure& fig, int x, int y, int w, int h, const ValueScale& s, const std::string& label, int channels) {
  Raster bar(w, h);
  const double lo = s.is_signed ? -1.0 : 0.0;
  for (int i = 0; i < h; ++i) {
    const double u = 1.0 - (i + 0.5) / h * (1.0 - lo);  // top row = 1, bottom row = lo
    for (int j = 0; j < w; ++j) {
      Rgb c = s.colour(s.value_at(u));
      if (channels == 3) {  // three strips: the channel's own display ramp (sRGB), black to full colour
        const int strip = std::min(2, j * 3 / w);
        c = {0.0, 0.0, 0.0};
        c[static_cast<std::size_t>(strip)] = srgb_encode(std::clamp(u, 0.0, 1.0));
      }
      bar.set(i, j, c);
    }
  }
  fig.image(bar, x, y);
  cairo_t* cr = fig.context();
  cairo_save(cr);
  cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
  cairo_set_line_width(cr, 1.0);
  cairo_rectangle(cr, x + 0.5, y + 0.5, w - 1.0, h - 1.0);
  cairo_stroke(cr);
  std::size_t widest = 0;
  for (double v : s.ticks()) {
    const double u = s.unit(v);
    const double ty = y + h * (1.0 - u) / (1.0 - lo);
    cairo_move_to(cr, x + w, ty);
    cairo_line_to(cr, x + w + 5, ty);
    cairo_stroke(cr);
    const std::string t = format_number(v);
    widest = std::max(widest, t.size());
    fig.text(x + w + 8, ty + 4.5, t, 11.5);
  }
  cairo_restore(cr);
  fig.text(x + w + 18 + 7.0 * static_cast<double>(widest), y + h / 2.0, label, 13.0, Align::Centre, false, M_PI / 2);
}

}  // namespace icobrdf::plot
