#include "icobrdf/plot/plots.hpp"

#include <cairo.h>
#include <fmt/core.h>
#include <sys/stat.h>

#include <algorithm>
#include <cmath>
#include <memory>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/support/finite_values.hpp"
#include "icobrdf/core/basis/hemisphere_basis.hpp"
#include "icobrdf/core/basis/isotropic_modes.hpp"
#include "icobrdf/core/basis/lambert_map.hpp"
#include "icobrdf/core/spectrum/spectrum_ops.hpp"
#include "icobrdf/mesh/tessellation.hpp"
#include "icobrdf/plot/curve_plots.hpp"
#include "icobrdf/plot/disk_raster.hpp"
#include "icobrdf/plot/figure.hpp"
#include "icobrdf/plot/slice_data.hpp"
#include "icobrdf/plot/sphere_shading.hpp"
#include "icobrdf/plot/value_scale.hpp"

namespace icobrdf::plot {
namespace {

constexpr double kDeg = 180.0 / M_PI;  // degrees per radian (M_PI: the tree's one pi)
// Level of the cells used as a midpoint quadrature for the directional albedo of a model (sky light).
constexpr int kAlbedoQuadratureLevel = 3;
// Nodes of the table of that albedo over the view direction: every 4.45 degrees of theta_o from 0 to 89
// (the last degree, never measured, is held at its value), 12 azimuths averaged per node.
constexpr int kAlbedoThetaNodes = 21, kAlbedoPhiNodes = 12;
constexpr double kAlbedoLastTheta = 89.0 * M_PI / 180.0;
constexpr int kMinSphereSize = 16, kMaxSphereSize = 2048;  // pixels
// Samples per pixel side of a sphere: 2 x 2 smooths the outline and narrow highlights (no moire) at 4x the
// evaluations.
constexpr int kAntiAlias = 2;

const Rgb kPositiveCurve{0.70, 0.25, 0.05};
const Rgb kNegativeCurve{0.10, 0.30, 0.85};

bool is_directory(const std::string& p) {
  struct stat st{};
  return ::stat(p.c_str(), &st) == 0 && S_ISDIR(st.st_mode);
}

std::string deg(double rad) { return format_number(std::round(rad * kDeg * 100.0) / 100.0) + "\u00b0"; }

// Ends a long label with an ellipsis so that it fits in `max_chars`.
std::string shorten(const std::string& s, std::size_t max_chars) {
  return s.size() <= max_chars ? s : s.substr(0, max_chars - 3) + "...";
}

void check_output_path(const std::string& path) {
  if (path.empty()) throw ArgumentError("plot: an output file name is required");
  if (is_directory(path)) throw ArgumentError("plot: " + path + " is a directory, expected a PNG file name");
}

// ---------------------------------------------------------------------------------------------- basis

void draw_disk_frame(Figure& fig, const PanelRect& r) {
  fig.circle(r.x + r.size / 2.0, r.y + r.size / 2.0, r.size / 2.0, 1.0, 0.15);
}

}  // namespace

std::vector<std::string> plot_basis(int order, const std::string& out, bool separate, int panel_request) {
  if (order < 0 || order > kMaxBasisOrder)
    throw ArgumentError(fmt::format("basis plot: order {} outside 0..{}", order, kMaxBasisOrder));
  const bool to_file = out.size() > 4 && out.compare(out.size() - 4, 4, ".png") == 0 && !is_directory(out);
  const std::string dir = to_file ? (out.find('/') == std::string::npos ? "." : out.substr(0, out.rfind('/'))) : out;
  if (!is_directory(dir))
    throw ArgumentError("basis plot: -o " + out + ": expected an existing folder or FILE.png in one, found " +
                        (to_file ? "no folder " + dir : "neither"));
  if (panel_request != 0 && (panel_request < kMinBasisPanel || panel_request > kMaxBasisPanel))
    throw ArgumentError(fmt::format("basis plot: panel {} outside {}..{} pixels", panel_request, kMinBasisPanel, kMaxBasisPanel));
  const int panel = panel_request ? panel_request : std::clamp(1400 / (order + 1) - 24, 60, 170);
  const DiskSamples ds = disk_samples(panel);
  const Eigen::MatrixXd b = disk_basis(ds, order);
  std::vector<double> levels;
  for (int k = -4; k <= 4; ++k) levels.push_back(0.2 * k);
  const int cell = panel + 24, label_h = 22, top = 70, left = 30;
  const int width = left + (order + 1) * cell + 150, height = top + (order + 1) * (cell + label_h) + 30;
  Figure fig(width, height);
  fig.title(fmt::format("Hemisphere basis K_n^l, n = 0..{} (Lambert disk seen from above)", order));
  fig.text(width / 2.0, 52, "each panel scaled to its own max|K| = sqrt((n+1)/pi); colour bands of 0.1, contours every 0.2 max|K|, zero contour bold",
           12.5, Align::Centre);
  std::vector<std::string> written;
  for (int n = 0; n <= order; ++n) {
    const double kmax = std::sqrt((n + 1) / M_PI);
    const double x0 = left + (order - n) * cell / 2.0;
    for (int l = -n, k = 0; l <= n; l += 2, ++k) {
      const int j = ansi_index(n, l);
      Eigen::MatrixXd v = disk_raster(ds, b.col(j) / kmax);
      const PanelRect r{static_cast<int>(std::lround(x0 + k * cell + 12)), top + n * (cell + label_h), panel};
      // Filled contours (the paper's contour-density plots): the colour is constant within bands of 0.1 max|K|.
      const Eigen::MatrixXd banded = v.unaryExpr([](double x) { return std::isfinite(x) ? (std::floor(x * 10.0) + 0.5) / 10.0 : x; });
      fig.image(colorize(banded, 1.0, diverging), r.x, r.y);
      fig.contours(v, r.x, r.y, levels);
      draw_disk_frame(fig, r);
      fig.text(r.x + panel / 2.0, r.y + panel + 17, fmt::format("K_{}^{}", n, l), 13.0, Align::Centre);
      if (separate) {
        Figure one(panel * 2 + 170, panel * 2 + 110);
        const DiskSamples big = disk_samples(panel * 2);
        const Eigen::MatrixXd bv = disk_raster(big, disk_basis(big, n).col(j));
        one.title(fmt::format("K_{}^{} on the Lambert disk", n, l), 16.0);
        one.image(colorize(bv, kmax, diverging), 30, 50);
        one.contours(bv / kmax, 30, 50, levels);
        draw_disk_frame(one, {30, 50, panel * 2});
        one.text(30 + panel, 50 + 2 * panel + 22, "x = rho cos(phi)  \u2192", 12.0, Align::Centre);
        one.text(18, 50 + panel, "y = rho sin(phi)  \u2192", 12.0, Align::Centre, false, M_PI / 2);
        one.colorbar(panel * 2 + 50, 60, 20, panel * 2 - 20, kmax, diverging, "K [1/sqrt(sr)]");
        const std::string p = dir + fmt::format("/K_{}_{}.png", n, l);
        one.save_png(p);
        written.push_back(p);
      }
    }
  }
  fig.colorbar(width - 120, top + 10, 22, std::min(360, height - top - 60), 1.0, diverging, "K / max|K|");
  const std::string p = to_file ? out : dir + "/basis.png";
  fig.save_png(p);
  written.insert(written.begin(), p);
  return written;
}

// ---------------------------------------------------------------------------------------------- slice

namespace {

constexpr int kPolarSamples = 721;
// The polar curve stops half a degree above the horizon: measured data evaluated at theta_r = 90 exactly
// (a grazing direction no instrument measures) can be orders of magnitude off and would set the scale.
constexpr double kPolarReach = (90.0 - 0.5) * M_PI / 180.0;
constexpr int kMaxSliceOrder = 32;
constexpr std::size_t kMaxSliceColumns = 9;

void check_slice_request(const SliceSource& src, const SliceRequest& q) {
  if (q.orders.empty() && !(q.exact && src.exact))
    throw ArgumentError("slice plot: at least one truncation order is required (the source has no values of its own to draw)");
  for (int n : q.orders)
    if (n < 0 || n > kMaxSliceOrder) throw ArgumentError(fmt::format("slice plot: order {} outside 0..{}", n, kMaxSliceOrder));
  if (!(q.theta_i >= 0.0 && q.theta_i < M_PI / 2))
    throw ArgumentError(fmt::format("slice plot: theta_i {} degrees outside [0, 90)", q.theta_i * kDeg));
  if (q.orders.size() > kMaxSliceColumns)
    throw ArgumentError(fmt::format("slice plot: at most {} orders side by side, found {}", kMaxSliceColumns, q.orders.size()));
  if (q.orders.empty()) return;
  const int top_order = *std::max_element(q.orders.begin(), q.orders.end());
  if (!src.spectrum) throw ArgumentError(fmt::format("slice plot: order {} asked of a source without a spectrum", top_order));
  if (top_order > src.spectrum->order)
    throw ArgumentError(fmt::format("slice plot: order {} beyond the order {} of the spectrum", top_order, src.spectrum->order));
}

// One column of a slice picture: its values on the disk raster and along the plane of incidence.
struct SliceColumn {
  std::string label;
  Eigen::MatrixXd disk;
  Eigen::MatrixXd polar;  // samples x 1
};

std::vector<SliceColumn> slice_columns(const SliceSource& src, const SliceRequest& q, const Eigen::Vector3d& wi, const DiskSamples& ds,
                                       const RowMatrix3d& plane) {
  std::vector<SliceColumn> cols;
  if (!q.orders.empty()) {
    const Eigen::MatrixXd c = channel_mean(*src.spectrum);
    for (int n : q.orders) {
      const Eigen::MatrixXd cn = truncated_coefficients(c, n, q.filter);
      cols.push_back({fmt::format("order {}", n), disk_raster(ds, slice_values(cn, n, wi, ds.directions)), slice_values(cn, n, wi, plane)});
    }
  }
  if (q.exact && src.exact) {
    auto eval_mean = [&](const RowMatrix3d& wr) {
      RowMatrix3d wis(wr.rows(), 3);
      wis.rowwise() = wi.transpose();
      const Eigen::MatrixXd v = src.exact(wis, wr);
      return Eigen::VectorXd(v.rowwise().mean());
    };
    cols.push_back({src.exact_kind, disk_raster(ds, eval_mean(ds.directions)), eval_mean(plane)});
  }
  return cols;
}

// Lambert-disk radius (unit disk) of the polar angle theta.
double disk_radius(double theta) { return std::sqrt(2.0) * std::sin(theta / 2.0); }

// Theta rings at 30 and 60 degrees (thin, dashed) and their labels; phi labels at the rim.
void draw_disk_graticule(Figure& fig, const PanelRect& r) {
  const double cx = r.x + r.size / 2.0, cy = r.y + r.size / 2.0, R = r.size / 2.0;
  cairo_t* cr = fig.context();
  cairo_save(cr);
  const double dash[] = {2.0, 3.0};
  cairo_set_dash(cr, dash, 2, 0.0);
  cairo_set_line_width(cr, 0.6);
  cairo_set_source_rgba(cr, 0.5, 0.5, 0.5, 0.6);  // mid-grey: never the brightest nor the darkest pixel
  for (double t : {30.0, 60.0}) {
    cairo_new_path(cr);
    cairo_arc(cr, cx, cy, R * disk_radius(t / kDeg), 0, 2 * M_PI);
    cairo_stroke(cr);
  }
  cairo_restore(cr);
  for (double t : {30.0, 60.0}) fig.text(cx + R * disk_radius(t / kDeg) * 0.72 + 2, cy + R * disk_radius(t / kDeg) * 0.72 + 10, format_number(t) + "\u00b0", 9.0);
  fig.text(cx + R * 0.72 + 4, cy + R * 0.72 + 12, "\u03b8 90\u00b0", 9.0);
  fig.text(cx + R + 4, cy + 3, "0\u00b0", 9.5);
  fig.text(cx, r.y + r.size + 12, "270\u00b0", 9.5, Align::Centre);
  fig.text(cx - R - 4, cy + 3, "180\u00b0", 9.5, Align::Right);
}

// The disk of one column with the marks of the plane of incidence and the incident and mirror directions.
void draw_slice_disk(Figure& fig, const SliceColumn& col, const PanelRect& r, double phi_i, const ValueScale& scale, const Eigen::Vector3d& wi) {
  const int panel = r.size;
  fig.text(r.x + panel / 2.0, r.y - 18, col.label, 14.0, Align::Centre, true);
  fig.text(r.x + panel / 2.0, r.y - 4, "\u03c6 90\u00b0", 9.5, Align::Centre);
  fig.image(colorize(col.disk, scale), r.x, r.y);
  if (scale.is_signed) fig.contours(col.disk, r.x, r.y, {0.0});
  draw_disk_frame(fig, r);
  draw_disk_graticule(fig, r);
  const double cx = r.x + panel / 2.0, cy = r.y + panel / 2.0, R = panel / 2.0;
  const Eigen::Vector2d pi_disk = lambert_to_disk(wi);
  const Eigen::Vector2d pm_disk = lambert_to_disk(Eigen::Vector3d(-wi.x(), -wi.y(), wi.z()));
  // Plane of incidence: ticks outside the rim at both ends (the disk itself stays clean).
  for (double sgn : {-1.0, 1.0})
    fig.line(cx + sgn * (R + 2) * std::cos(phi_i), cy - sgn * (R + 2) * std::sin(phi_i), cx + sgn * (R + 10) * std::cos(phi_i),
             cy - sgn * (R + 10) * std::sin(phi_i), 1.5, {0.1, 0.1, 0.1});
  fig.circle(cx + R * pi_disk.x(), cy - R * pi_disk.y(), 5.0, 1.4, 0.0);
  const double mx = cx + R * pm_disk.x(), my = cy - R * pm_disk.y();
  // A reticle with an open centre, so the pixels at the mirror direction show the data.
  for (int sx : {-1, 1})
    for (int sy : {-1, 1}) fig.line(mx + 4 * sx, my + 4 * sy, mx + 8 * sx, my + 8 * sy, 1.3, {0, 0, 0});
}

// Polar plot in the plane of incidence centred at (pcx, pcy): radius PR |unit(value)| (linear or log, as the
// colour scale), angle t from the normal; rings at the scale's ticks, labelled with their values.
void draw_slice_polar(Figure& fig, const Eigen::MatrixXd& polar, const Eigen::VectorXd& t, double pcx, double pcy, double PR,
                      double theta_i, const ValueScale& scale) {
  fig.line(pcx - PR - 4, pcy, pcx + PR + 4, pcy, 1.0, {0.2, 0.2, 0.2});
  cairo_t* cr = fig.context();
  cairo_save(cr);
  double last_label = -1e9;  // x of the last ring label: labels closer than 30 pixels are left out
  for (double v : scale.ticks()) {
    const double u = std::fabs(scale.unit(v));
    if (v <= 0.0 || u <= 0.0) continue;
    cairo_set_source_rgb(cr, 0.75, 0.75, 0.75);
    cairo_set_line_width(cr, 0.7);
    cairo_new_path(cr);
    cairo_arc(cr, pcx, pcy, PR * u, M_PI, 2 * M_PI);
    cairo_stroke(cr);
    if (PR * u - last_label < 30.0) continue;
    last_label = PR * u;
    fig.text(pcx - PR * u, pcy + 11, format_number(v), 8.5, Align::Centre);
  }
  cairo_restore(cr);
  for (double a : {-60.0, -30.0, 30.0, 60.0})
    fig.text(pcx - (PR + 9) * std::sin(a / kDeg), pcy - (PR + 9) * std::cos(a / kDeg) + 3, format_number(std::fabs(a)) + "\u00b0", 8.5,
             Align::Centre);
  fig.line(pcx, pcy, pcx, pcy - PR, 0.6, {0.6, 0.6, 0.6}, true);
  // The incident side is drawn to the right, the forward (mirror) side to the left: as on the disk for phi_i = 0.
  fig.line(pcx, pcy, pcx + PR * std::sin(theta_i), pcy - PR * std::cos(theta_i), 1.0, {0.35, 0.35, 0.35}, true);
  fig.text(pcx + (PR + 20) * std::sin(theta_i), pcy - (PR + 20) * std::cos(theta_i) + 4, "in", 10.0, Align::Centre);
  draw_polar_curve(fig, polar, t, pcx, pcy, PR, scale, kPositiveCurve, false);
  draw_polar_curve(fig, polar, t, pcx, pcy, PR, scale, kNegativeCurve, true);
}

}  // namespace

SliceFigure plot_slice(const SliceSource& src, const SliceRequest& q, const std::string& path) {
  check_output_path(path);
  check_slice_request(src, q);
  const Eigen::Vector3d wi(std::sin(q.theta_i) * std::cos(q.phi_i), std::sin(q.theta_i) * std::sin(q.phi_i), std::cos(q.theta_i));
  const int panel = q.panel;
  const DiskSamples ds = disk_samples(panel);
  const Eigen::VectorXd t = Eigen::VectorXd::LinSpaced(kPolarSamples, -kPolarReach, kPolarReach);
  const std::vector<SliceColumn> cols = slice_columns(src, q, wi, ds, plane_of_incidence_directions(q.phi_i, t));
  std::vector<const Eigen::MatrixXd*> all;
  for (const auto& col : cols) {
    if (col.label != "measured") require_finite(col.polar, path + ": plot slice of " + src.label, "the values in the plane of incidence");
    all.push_back(&col.disk);
    all.push_back(&col.polar);
  }
  const ValueScale scale = value_scale(all, q.log);
  const bool g_form = !q.orders.empty() && src.spectrum->cosine;
  const int channels = src.spectrum ? src.spectrum->channel_count() : 1;

  const int ncol = static_cast<int>(cols.size());
  const int gap = 44, left = 40, top = 110, polar_h = panel / 2 + 44;
  const int bar_x = left + ncol * (panel + gap) + 8;
  const int width = std::max(bar_x + 130, 860);  // wide enough for the caption lines
  const int height = top + panel + 34 + polar_h + 70;
  Figure fig(width, height);
  const std::string quantity = g_form ? "g = f cos(theta_i)" : "f";
  fig.title(shorten(src.label, 90), 17.0);
  fig.text(width / 2.0, 50,
           fmt::format("remitted {} for incidence theta_i = {}, phi_i = {}{}{}{}", quantity, deg(q.theta_i), deg(q.phi_i),
                       channels > 1 ? " (mean of the channels)" : "",
                       q.orders.empty() || q.filter.kind == LowPassFilter::Kind::None ? "" : ", filter " + q.filter.name(),
                       q.log ? fmt::format(", log scale over {} decades", format_number(kDefaultDecades)) : ""),
           13.0, Align::Centre);
  fig.text(width / 2.0, 70,
           std::string("top: hemisphere seen from above (Lambert disk, \u03b8 rings at 30\u00b0 and 60\u00b0); bottom: plane of incidence") +
               (scale.is_signed ? "; blue = negative (ringing)" : ""),
           11.5, Align::Centre);
  SliceFigure out;
  out.scale = scale.top;
  out.signed_map = scale.is_signed;
  out.g_form = g_form;
  for (int k = 0; k < ncol; ++k) {
    const PanelRect r{left + k * (panel + gap), top, panel};
    out.disks.push_back(r);
    draw_slice_disk(fig, cols[k], r, q.phi_i, scale, wi);
    draw_slice_polar(fig, cols[k].polar, t, r.x + panel / 2.0, top + panel + 34 + polar_h - 16, panel / 2.0 - 14, q.theta_i, scale);
  }
  const int py = top + panel + 34 + polar_h + 14;
  fig.text(left, py, fmt::format("polar plot: radius = {} {} (rings labelled in 1/sr), angle = theta_r from the normal; incident side right, mirror side left",
                                 q.log ? "log" : "", quantity),
           11.5);
  fig.text(left, py + 18, "disk: ring = incident direction, open cross = mirror direction, rim ticks = plane of incidence" +
                              std::string(scale.is_signed ? "; black contour = 0" : ""),
           11.5);
  if (src.spectrum && !q.orders.empty() && (src.spectrum->level >= 0 || !src.spectrum->grid_kind.empty()))
    fig.text(left, py + 36, fmt::format("spectrum of order {} ({} grid level {})", src.spectrum->order,
                                        src.spectrum->grid_kind.empty() ? "?" : src.spectrum->grid_kind, src.spectrum->level),
             11.5);
  draw_scale_bar(fig, bar_x, top, 20, panel, scale, quantity + " [1/sr]");
  out.width = width;
  out.height = height;
  fig.save_png(path);
  return out;
}

// ---------------------------------------------------------------------------------------------- spectrum

SpectrumFigure plot_spectrum(const Spectrum& s, const std::string& label, const std::string& path, bool log) {
  check_output_path(path);
  const Eigen::MatrixXd c = channel_mean(s);
  const int N = s.order;
  const auto modes = isotropic_modes(N);
  const Eigen::VectorXd a = ibsss_from_coefficients(c);
  require_finite(c, path + ": plot spectrum of " + label, "the channel mean of C");
  require_finite(a, path + ": plot spectrum of " + label, "the conversion of C to isotropic (IBSSS) coefficients");
  // Columns: for each n, one per l = n mod 2, ..., n step 2 (l <= m <= n).
  std::vector<int> col_start(N + 2, 0);
  for (int n = 0; n <= N; ++n) col_start[n + 1] = col_start[n] + n / 2 + 1;
  const int ncols = col_start[N + 1];
  const int cell = std::clamp(620 / std::max(ncols, 1), 8, 40);
  const int sep = std::max(2, cell / 4);  // gap between n blocks
  const bool matrix = !s.isotropic;
  const int M = s.modes();
  const int mcell = std::max(1, 440 / M);
  const int left = 40, top = 110;  // (the n numbers sit above the IBSSS, the m numbers at its right)
  const int ib_w = ncols * cell + N * sep, ib_h = (N + 1) * cell;
  const int width = std::max(left + ib_w + 40 + (matrix ? M * mcell + 90 : 0) + 160, 640);
  const int height = std::max(top + ib_h, top + (matrix ? M * mcell + 40 : 0)) + 80;
  Figure fig(width, height);
  // The DC coefficient (mode 0, the mean level) is shown apart: the scale is that of the others, so that
  // they do not all read as zero beside it; its cell saturates and its value is written out.
  Eigen::MatrixXd rest = a;
  if (rest.size() > 1) rest(0) = 0.0;
  Eigen::MatrixXd crest = c;
  if (matrix && crest.size() > 1) crest(0, 0) = 0.0;
  std::vector<const Eigen::MatrixXd*> parts{&rest};
  if (matrix) parts.push_back(&crest);
  ValueScale vs = value_scale(parts, log, kDefaultDecades, true);
  // Coefficients below kDcShare of the DC one are rounding of a flat material: they do not set the scale.
  constexpr double kDcShare = 1e-3;
  if (a.size() && vs.top < kDcShare * std::fabs(a[0])) {
    vs.top = kDcShare * std::fabs(a[0]);
    vs.bottom = vs.top * std::pow(10.0, -kDefaultDecades);
  }
  const double scale = vs.top;
  fig.title("Spectrum of " + shorten(label, 70), 17.0);
  fig.text(width / 2.0, 52,
           fmt::format("order {}, {}{}{}, filter {}", N, s.cosine ? "coefficients of g = f cos(theta_i)" : "coefficients of f",
                       s.isotropic ? ", isotropic" : "", s.channel_count() > 1 ? ", mean of the channels" : "", s.filter),
           13.0, Align::Centre);
  fig.text(left, top - 40, "IBSSS (paper Fig. 3): n across, m down, l within each n; grey = 0", 12.5, Align::Left, true);
  // Background mid-grey block per n (the valid m range), then the cells.
  Raster bg(ib_w, ib_h);
  for (int n = 0; n <= N; ++n)
    for (int i = 0; i < ib_h; ++i)
      for (int j = 0; j < (n / 2 + 1) * cell; ++j) bg.set(i, col_start[n] * cell + n * sep + j, {0.93, 0.93, 0.93});
  fig.image(bg, left, top);
  for (std::size_t k = 0; k < modes.size(); ++k) {
    const auto& md = modes[k];
    const int x = left + (col_start[md.n] + md.l / 2) * cell + md.n * sep, y = top + md.m * cell;
    Raster r(cell - 1, cell - 1);
    for (int i = 0; i < cell - 1; ++i)
      for (int j = 0; j < cell - 1; ++j) r.set(i, j, vs.colour(a[static_cast<Eigen::Index>(k)]));
    fig.image(r, x, y);
    cairo_t* cr = fig.context();
    cairo_save(cr);
    cairo_set_source_rgb(cr, 0.35, 0.35, 0.35);
    cairo_set_line_width(cr, 1.0);
    cairo_rectangle(cr, x - 0.5, y - 0.5, cell, cell);  // outline, so that cells near white stay visible
    cairo_stroke(cr);
    cairo_restore(cr);
  }
  const double fs = std::clamp(cell * 0.55, 9.0, 13.0);
  for (int n = 0; n <= N; ++n)
    fig.text(left + col_start[n] * cell + n * sep + (n / 2 + 1) * cell / 2.0, top - 8, std::to_string(n), fs, Align::Centre);
  for (int m = 0; m <= N; ++m) fig.text(left + ib_w + 6, top + m * cell + cell * 0.5 + fs * 0.35, std::to_string(m), fs);
  fig.text(left + ib_w / 2.0, top - 24, "n \u2192", 12.0, Align::Centre);
  fig.text(left + ib_w + 6, top - 8, "m \u2193", 12.0);
  fig.text(left, top + ib_h + 22,
           fmt::format("{} isotropic modes I_nm^l; colour scale \u00b1{}{} without the DC coefficient I_00^0 = {} (its cell saturates)",
                       modes.size(), format_number(scale), log ? " (signed log)" : "", a.size() ? format_number(a[0]) : "-"),
           11.5);
  int bar_x = left + ib_w + 50;
  if (matrix) {
    const int mx = left + ib_w + 80, my = top;
    fig.text(mx, top - 40, "coefficient matrix C (K_a incident, K_b remitted)", 12.5, Align::Left, true);
    Raster r(M * mcell, M * mcell);
    for (int i = 0; i < M; ++i)
      for (int j = 0; j < M; ++j)
        for (int u = 0; u < mcell; ++u)
          for (int v = 0; v < mcell; ++v) r.set(i * mcell + u, j * mcell + v, vs.colour(c(i, j)));
    fig.image(r, mx, my);
    // Order boundaries.
    for (int n = 1; n <= N; ++n) {
      const double p = hemisphere_basis_count(n - 1) * mcell;
      fig.line(mx + p, my, mx + p, my + M * mcell, 0.4, {0.6, 0.2, 0.2});
      fig.line(mx, my + p, mx + M * mcell, my + p, 0.4, {0.6, 0.2, 0.2});
    }
    fig.text(mx + M * mcell / 2.0, my + M * mcell + 20, "b (ANSI index of K_b, remitted) \u2192", 11.5, Align::Centre);
    fig.text(mx - 8, my + M * mcell / 2.0, "\u2190 a (ANSI index of K_a, incident)", 11.5, Align::Centre, false, M_PI / 2);
    bar_x = mx + M * mcell + 30;
  }
  draw_scale_bar(fig, bar_x, top, 20, std::max(160, std::min(ib_h, 360)), vs, "coefficient [1]");
  fig.text(left, height - 30,
           fmt::format("source: {}{}", shorten(s.source, 80), s.level >= 0 ? fmt::format(", {} grid level {}", s.grid_kind, s.level) : ""),
           11.0);
  fig.save_png(path);
  return {width, height, matrix, scale};
}

// ---------------------------------------------------------------------------------------------- sphere

namespace {

struct Shader {
  std::string name;
  int channels = 1;
  ReflectFunction reflect;
  AlbedoFunction albedo;
};

Shader spectrum_shader(const Spectrum& s, const std::string& name) {
  Shader sh;
  sh.name = name;
  sh.channels = s.channel_count();
  auto sp = std::make_shared<Spectrum>(s);
  sh.reflect = [sp](const RowMatrix3d& wi, const RowMatrix3d& wo) {
    Eigen::MatrixXd r(wi.rows(), sp->channel_count());
    for (int c = 0; c < sp->channel_count(); ++c) {
      r.col(c) = evaluate_coefficients(sp->channels[c], sp->order, wi, wo);
      if (!sp->cosine) r.col(c) = r.col(c).cwiseProduct(wi.col(2));
    }
    return r;
  };
  sh.albedo = [sp](const RowMatrix3d& wo) {
    // a(w_o) = integral f(w, w_o) cos(theta) dOmega = K(w_o)^T C^T e with e_b = integral K_b cos dOmega (f
    // spectra), or integral g(w, w_o) dOmega = K(w_o)^T C^T m with m = sqrt(2 pi) e_0 (g spectra: only K_0^0
    // = 1/sqrt(2 pi) has a non-zero integral).
    const int M = sp->modes();
    Eigen::VectorXd e = sp->cosine ? Eigen::VectorXd(Eigen::VectorXd::Unit(M, 0) * std::sqrt(2.0 * M_PI)) : cosine_moments(sp->order);
    const Eigen::MatrixXd k = hemisphere_basis_matrix(sp->order, wo);
    Eigen::MatrixXd a(wo.rows(), sp->channel_count());
    for (int c = 0; c < sp->channel_count(); ++c) a.col(c) = k * (sp->channels[c].transpose() * e);
    return a;
  };
  return sh;
}

Shader model_shader(const PairFunction& f, int channels, const std::string& name) {
  Shader sh;
  sh.name = name;
  sh.channels = channels;
  sh.reflect = [f](const RowMatrix3d& wi, const RowMatrix3d& wo) {
    Eigen::MatrixXd r = f(wi, wo);
    for (int c = 0; c < r.cols(); ++c) r.col(c) = r.col(c).cwiseProduct(wi.col(2));
    return r;
  };
  sh.albedo = [f, channels](const RowMatrix3d& wo) {
    // Midpoint rule over the cells of a tessellation, sum_c f(d_c, w_o) cos(theta_c) Omega_c, at a table of
    // theta_o, each node the mean over kAlbedoPhiNodes azimuths phi_o (exact for an isotropic material; the
    // quadrature's error for a lobe narrower than a cell differs from azimuth to azimuth and averages out),
    // then linear in theta_o: a few hundred thousand evaluations whatever the picture's size, smooth across
    // the sphere (no moire).
    // Every node's pairs go to f in one batch: one parallel region of a source's evaluation instead of one per
    // node (on a loaded machine each region's barrier waits for a descheduled thread: 2.4 s against 0.3 s for an
    // RGL material's 252 nodes).
    static const Grid g = build_equal_area_grid(kAlbedoQuadratureLevel);
    const Eigen::VectorXd wcos = g.solid_angles.cwiseProduct(g.directions.col(2));
    const int nt = kAlbedoThetaNodes, np = kAlbedoPhiNodes;
    const Eigen::Index cells = g.cells();
    RowMatrix3d wis(cells * nt * np, 3), wor(cells * nt * np, 3);
    for (int a = 0; a < nt; ++a)
      for (int b = 0; b < np; ++b) {
        const double th = kAlbedoLastTheta * a / (nt - 1), ph = 2 * M_PI * (b + 0.5) / np;
        const Eigen::Index first = (static_cast<Eigen::Index>(a) * np + b) * cells;
        wis.middleRows(first, cells) = g.directions;
        wor.middleRows(first, cells).rowwise() = Eigen::RowVector3d(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th));
      }
    const Eigen::MatrixXd values = f(wis, wor);
    std::vector<Eigen::RowVectorXd> table(static_cast<std::size_t>(nt), Eigen::RowVectorXd::Zero(channels));
    for (int a = 0; a < nt; ++a)
      for (int b = 0; b < np; ++b)
        table[static_cast<std::size_t>(a)] += (values.middleRows((static_cast<Eigen::Index>(a) * np + b) * cells, cells).transpose() * wcos).transpose() / np;
    // One pass of the (1, 2, 1) / 4 filter over theta_o (ends kept): the quadrature error of a lobe narrower
    // than a cell (about 5.6 degrees at level 3) ripples with that period and would show as rings.
    const std::vector<Eigen::RowVectorXd> raw = table;
    for (int a = 1; a + 1 < nt; ++a)
      table[static_cast<std::size_t>(a)] = (raw[static_cast<std::size_t>(a - 1)] + 2.0 * raw[static_cast<std::size_t>(a)] + raw[static_cast<std::size_t>(a + 1)]) / 4.0;
    Eigen::MatrixXd out(wo.rows(), channels);
    for (Eigen::Index k = 0; k < wo.rows(); ++k) {
      const double th = std::acos(std::clamp(wo(k, 2), -1.0, 1.0));
      const double x = std::clamp(th / kAlbedoLastTheta, 0.0, 1.0) * (nt - 1);
      const int a = std::min(static_cast<int>(x), nt - 2);
      const double u = x - a;
      out.row(k) = (1 - u) * table[static_cast<std::size_t>(a)] + u * table[static_cast<std::size_t>(a + 1)];
    }
    return out;
  };
  return sh;
}

void check_sphere_request(const SphereRequest& q) {
  if (!(q.light_theta >= 0.0 && q.light_theta <= M_PI))
    throw ArgumentError(fmt::format("sphere plot: light theta {} degrees outside 0..180", q.light_theta * kDeg));
  if (!(q.exposure > 0.0) || !std::isfinite(q.exposure)) throw ArgumentError(fmt::format("sphere plot: exposure {} is not > 0", q.exposure));
  if (!(q.sky >= 0.0) || !std::isfinite(q.sky)) throw ArgumentError(fmt::format("sphere plot: sky radiance {} is not >= 0", q.sky));
  if (q.size < kMinSphereSize || q.size > kMaxSphereSize)
    throw ArgumentError(fmt::format("sphere plot: size {} outside {}..{} pixels", q.size, kMinSphereSize, kMaxSphereSize));
}

// The shader of each material as `shading` asks: the model itself, or the spectrum.
std::vector<Shader> sphere_shaders(const std::vector<SphereMaterial>& materials, SphereRequest::Shading shading) {
  if (materials.empty()) throw ArgumentError("sphere plot: no material to draw");
  std::vector<Shader> shaders;
  for (const auto& m : materials) {
    const bool use_model = m.model && shading != SphereRequest::Shading::Spectrum;
    if (shading == SphereRequest::Shading::Model && !use_model)
      throw ArgumentError("sphere plot: model shading needs the model of '" + m.name + "' (a model without delta parts)");
    if (!use_model && !m.spectrum) throw ArgumentError("sphere plot: '" + m.name + "' has no spectrum to shade from");
    shaders.push_back(use_model ? model_shader(m.model, m.model_channels, m.name) : spectrum_shader(*m.spectrum, m.name));
  }
  return shaders;
}

// How the caption says the spheres were shaded.
std::string shading_method(const std::vector<SphereMaterial>& materials, SphereRequest::Shading shading) {
  if (materials.size() > 1) return shading == SphereRequest::Shading::Model ? "from the stored values" : "from the stored spectra";
  const SphereMaterial& m = materials.front();
  if (m.model && shading != SphereRequest::Shading::Spectrum) return "from the model";
  return fmt::format("from its spectrum (order {})", m.spectrum->order);
}

}  // namespace

SphereFigure plot_sphere(const std::string& title, const std::vector<SphereMaterial>& materials, const SphereRequest& q,
                         const std::string& path) {
  check_output_path(path);
  check_sphere_request(q);
  const std::vector<Shader> shaders = sphere_shaders(materials, q.shading);
  const std::string method = shading_method(materials, q.shading);
  SphereLighting light;
  light.light = light_direction(q.light_theta, q.light_phi);
  light.sky = q.sky;
  const int count = static_cast<int>(shaders.size());
  const int ncol = count == 1 ? 1 : std::min(count, std::max(3, static_cast<int>(std::ceil(std::sqrt(count * 1.5)))));
  const int nrow = (count + ncol - 1) / ncol;
  const int size = q.size, gap = 24, label_h = 26, left = 24, top = count == 1 ? 86 : 96;
  const int width = std::max(left + ncol * (size + gap) + 110, 780);
  const int x_off = count == 1 ? (width - 110 - size) / 2 - left : 0;  // centre a single sphere
  const int height = top + nrow * (size + label_h + gap) + 46;
  Figure fig(width, height);
  fig.title(count == 1 ? shorten(title, 70) : "Materials of " + shorten(title, 60), 17.0);
  fig.text(width / 2.0, 50,
           fmt::format("distant light at theta = {}, phi = {} (irradiance pi){}; shaded {}", deg(q.light_theta), deg(q.light_phi),
                       q.sky > 0 ? fmt::format(" + uniform sky of radiance {}", format_number(q.sky)) : "", method),
           12.5, Align::Centre);
  fig.text(width / 2.0, 68, "orthographic view along the normal of the picture; BRDF tangent along latitude circles about the vertical axis",
           11.0, Align::Centre);
  SphereFigure out;
  for (int k = 0; k < count; ++k) {
    const Shader& sh = shaders[static_cast<std::size_t>(k)];
    // Shaded at kAntiAlias x kAntiAlias samples per pixel and averaged in linear radiance; pixels on the
    // outline blend with the backdrop by the share of their samples on the sphere.
    const auto ch = shade_sphere(size * kAntiAlias, sh.channels, sh.reflect, sh.albedo, light);
    Raster r(size, size);
    constexpr double kBackdrop = 0.16;  // sRGB grey of the square behind each sphere
    const double back = srgb_decode(kBackdrop);
    for (int i = 0; i < size; ++i)
      for (int j = 0; j < size; ++j) {
        Rgb sum{0.0, 0.0, 0.0};
        int inside = 0;
        for (int u = 0; u < kAntiAlias; ++u)
          for (int v = 0; v < kAntiAlias; ++v) {
            const int ii = i * kAntiAlias + u, jj = j * kAntiAlias + v;
            if (!std::isfinite(ch[0](ii, jj))) continue;
            ++inside;
            for (int m = 0; m < 3; ++m) sum[m] += std::clamp(ch[sh.channels == 3 ? m : 0](ii, jj) / q.exposure, 0.0, 1.0);
          }
        const double n = kAntiAlias * kAntiAlias;
        Rgb c;
        for (int m = 0; m < 3; ++m) c[m] = srgb_encode(sum[m] / n + back * (n - inside) / n);
        r.set(i, j, c);
      }
    const PanelRect pr{left + x_off + (k % ncol) * (size + gap), top + (k / ncol) * (size + label_h + gap), size};
    fig.image(r, pr.x, pr.y);  // on a dark square, so that the lit sphere and its shadowed side read against the page
    if (count > 1) fig.text(pr.x + size / 2.0, pr.y + size + 18, shorten(sh.name, static_cast<std::size_t>(size / 7)), 13.0, Align::Centre);
    out.spheres.push_back(pr);
    out.names.push_back(sh.name);
  }
  const bool rgb = std::any_of(shaders.begin(), shaders.end(), [](const Shader& sh) { return sh.channels == 3; });
  if (rgb) {
    ValueScale radiance;
    radiance.top = q.exposure;
    draw_scale_bar(fig, width - 96, top, 18, std::min(size, 300), radiance, "radiance L per channel (E = pi)", 3);
  } else {
    fig.colorbar(width - 96, top, 18, std::min(size, 300), q.exposure, [](double t) {
      const double v = srgb_encode(std::max(0.0, t));
      return Rgb{v, v, v};
    }, "radiance L (E = pi)", false);
  }
  fig.text(left, height - 18, "sRGB-encoded linear radiance, white = exposure; light and sky in the camera frame (z towards the viewer)", 11.0);
  out.width = width;
  out.height = height;
  fig.save_png(path);
  return out;
}

}  // namespace icobrdf::plot
