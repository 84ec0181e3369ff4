#include "icobrdf/io/spectrum_file.hpp"

#include <cctype>

#include <cfloat>
#include <cmath>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/support/finite_values.hpp"
#include "icobrdf/core/basis/helmholtz_modes.hpp"
#include "icobrdf/core/support/huge_pages.hpp"
#include "icobrdf/core/support/text.hpp"
#include "icobrdf/core/basis/isotropic_modes.hpp"
#include "icobrdf/io/bank_file.hpp"
#include "icobrdf/io/half_angle_file.hpp"

namespace icobrdf {

namespace {

using h5::Shape;
using h5::ShapePattern;

std::uint64_t dim64(std::int64_t n) { return static_cast<std::uint64_t>(n); }

using RowMap = Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>;
using RowMapF = Eigen::Map<Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>;

std::int64_t modes_of(std::int64_t order) { return (order + 1) * (order + 2) / 2; }


// Reason an IBSSS (n, m, l) entry is invalid for `order`, or "".
std::string ibsss_index_problem(int n, int m, int l, int order) {
  if (!(n >= m && m >= l && l >= 0)) return "expected n >= m >= l >= 0";
  if ((n - l) % 2 != 0 || (m - l) % 2 != 0) return "expected n - l and m - l even";
  if (n > order) return "expected n <= order " + std::to_string(order);
  return "";
}

std::string index_text(int n, int m, int l) {
  return "(" + std::to_string(n) + ", " + std::to_string(m) + ", " + std::to_string(l) + ")";
}

[[noreturn]] void bad_record(const std::string& name, const std::string& what) {
  throw ArgumentError("cannot write material '" + name + "': " + what);
}

// "r,g,b": names of the channels, checked (one per channel, non-empty, no comma).
std::string join_channel_names(const std::vector<std::string>& names, int channels, const std::string& nm) {
  if (static_cast<int>(names.size()) != channels)
    bad_record(nm, "expected " + std::to_string(channels) + " channel names, found " + std::to_string(names.size()));
  std::string out;
  for (const auto& n : names) {
    if (n.empty() || n.find(',') != std::string::npos) bad_record(nm, "channel name '" + quoted_text(n) + "' must be non-empty without a comma");
    out += (out.empty() ? "" : ",") + n;
  }
  return out;
}

}  // namespace

std::string material_name_problem(const std::string& name) {
  if (name.empty()) return "expected a non-empty name";
  if (name.size() > kMaxMaterialNameLength)
    return "expected at most " + std::to_string(kMaxMaterialNameLength) + " bytes, found " + std::to_string(name.size());
  for (unsigned char ch : name) {
    if (ch == '/' || ch == '.') return std::string("expected no '/' or '.', found '") + static_cast<char>(ch) + "'";
    if (ch < 0x20 || ch > 0x7e) return "expected printable ASCII, found byte " + std::to_string(ch);
  }
  return "";
}

void validate_material_name(const std::string& name) {
  const std::string p = material_name_problem(name);
  if (!p.empty()) throw ArgumentError("invalid material name '" + name + "': " + p);
}

std::string source_text_problem(const std::string& source) {
  if (source.size() <= kMaxSourceLength) return "";
  return "SOURCE of " + std::to_string(source.size()) + " bytes is longer than the " + std::to_string(kMaxSourceLength) +
         " a bank stores (one HDF5 attribute); shorten it, e.g. fewer model terms";
}

void require_storable_source(const std::string& source) {
  if (const std::string p = source_text_problem(source); !p.empty()) throw ArgumentError(p);
}

// Cell count of the equal-area hemisphere tessellation at `level` (whole cells 10 * 4^L, plus 2^(L+1)
// equator cells cut in half): docs/SPEC-NOTES "Discrete engine".
std::int64_t equal_area_cells(int level) { return 10 * (std::int64_t{1} << (2 * level)) + (std::int64_t{1} << (level + 1)); }

std::string lut_size_problem(std::int64_t cells, int channels, bool float32) {
  const double bytes = static_cast<double>(channels) * static_cast<double>(cells) * static_cast<double>(cells) * (float32 ? 4 : 8);
  if (bytes <= static_cast<double>(h5::kDefaultMaxDatasetBytes)) return "";
  return "a " + std::to_string(channels) + "-channel " + (float32 ? "float32" : "float64") + " LUT of " + std::to_string(cells) +
         " x " + std::to_string(cells) + " cells is " + std::to_string(static_cast<long long>(bytes / 1e6)) +
         " MB, more than the " + std::to_string(h5::kDefaultMaxDatasetBytes >> 20) +
         " MiB a LUT file may hold (level 5 is the largest stored LUT; banks of higher levels store spectra only)";
}

void require_storable_lut(std::int64_t cells, int channels, bool float32, const std::string& what) {
  if (const std::string p = lut_size_problem(cells, channels, float32); !p.empty()) throw UnsupportedError(what + ": " + p);
}

// Names of the `choice` attributes.
static bool choice_key_ok(const std::string& k) {
  if (k.empty() || k.size() > 64) return false;
  for (char c : k)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_')) return false;
  return true;
}

std::string representation_name(const MaterialRecord& rec) {
  if (!rec.lobe) return "modes";
  for (const auto& c : rec.spectrum.channels)
    if (!c.isZero(0.0)) return "hybrid";
  return "half-angle";
}

// The LUT datasets of a checked record (float32 with its rounding error, or float64).
static void write_lut(h5::Group& g, const MaterialRecord& rec, std::int64_t cells) {
  const int ch = rec.spectrum.channel_count();
  if (!rec.lut.empty()) {
    require_storable_lut(cells, ch, rec.lut_float32, g.path() + " material '" + rec.name + "'");
    const size_t per = static_cast<size_t>(cells * cells);
    const std::string what = "LUT[c, i, r] = BRDF on incident cell i and remitted cell r";
    if (rec.lut_float32) {
      std::vector<float> f(per * ch);
      double err = 0.0;
      for (int c = 0; c < ch; ++c) {
        RowMapF dst(f.data() + c * per, cells, cells);
        dst = rec.lut[c].cast<float>();
        err = std::max(err, (dst.cast<double>() - rec.lut[c]).cwiseAbs().maxCoeff());
      }
      // A record read from a float32 LUT (resumed builds, bank extract) holds already rounded values, which
      // round again exactly: keep the rounding error recorded against the original values.
      if (rec.lut_max_rounding_error >= 0) err = std::max(err, rec.lut_max_rounding_error);
      g.write("lut", f.data(), Shape{dim64(ch), dim64(cells), dim64(cells)}, "1/sr", what + " (float32)");
      // The rounding error is a material attribute (docs/file-format.md), next to the float32 dataset.
      g.set_attr("lut_max_abs_rounding_error", err);
    } else {
      std::vector<double> d(per * ch);
      for (int c = 0; c < ch; ++c) RowMap(d.data() + c * per, cells, cells) = rec.lut[c];
      g.write("lut", d.data(), Shape{dim64(ch), dim64(cells), dim64(cells)}, "1/sr", what);
    }
  }
}

// The `choice` subgroup: the figures and labels of a bank build.
static void write_choice(h5::Group& g, const MaterialRecord& rec) {
  const std::string& nm = rec.name;
  if (!rec.figures.empty() || !rec.labels.empty()) {
    h5::Group choice = g.create_group("choice");
    std::string figures, labels;
    for (const auto& [k, v] : rec.figures) {
      if (!choice_key_ok(k) || k == "figures" || k == "labels") bad_record(nm, "figure name '" + k + "' expected [A-Za-z0-9_]+, not figures or labels");
      choice.set_attr(k, v);
      figures += (figures.empty() ? "" : ",") + k;
    }
    for (const auto& [k, v] : rec.labels) {
      if (!choice_key_ok(k) || rec.figures.count(k) || k == "figures" || k == "labels")
        bad_record(nm, "label name '" + k + "' expected [A-Za-z0-9_]+, distinct from the figures, not figures or labels");
      choice.set_attr(k, v);
      labels += (labels.empty() ? "" : ",") + k;
    }
    choice.set_attr("figures", figures);
    choice.set_attr("labels", labels);
  }
}

void require_finite_material(const std::string& file, const MaterialRecord& rec) {
  const Spectrum& s = rec.spectrum;
  const std::string where = file + ": material '" + rec.name + "'";
  for (size_t c = 0; c < s.channels.size(); ++c)
    require_finite(s.channels[c], where + " dataset C channel " + std::to_string(c), "the spectrum's coefficients");
  if (rec.ibsss.size() > 0) require_finite(rec.ibsss, where + " dataset ibsss", "the isotropic mode coefficients");
  for (size_t c = 0; c < rec.lut.size(); ++c)
    require_finite(rec.lut[c], where + " dataset lut channel " + std::to_string(c), "the LUT (f sampled on cell pairs)");
  if (rec.lobe)
    for (size_t c = 0; c < rec.lobe->u.size() && c < rec.lobe->v.size(); ++c) {
      require_finite(rec.lobe->u[c], where + " dataset half_angle/u channel " + std::to_string(c), "the half-angle lobe's h factors");
      require_finite(rec.lobe->v[c], where + " dataset half_angle/v channel " + std::to_string(c), "the half-angle lobe's d factors");
    }
  // NaN is the documented "not measured"; an infinite figure is an overflow.
  const std::pair<const char*, double> figures[] = {{"gram_error", s.gram_error},
                                                    {"reciprocity_violation", s.reciprocity_violation},
                                                    {"anisotropy_fraction", s.anisotropy_fraction},
                                                    {"max_albedo", s.max_albedo}};
  for (const auto& [name, x] : figures)
    if (!std::isnan(x)) require_finite(x, where + " attribute " + name, "the fit's figure " + std::string(name));
}

// The `sample_fit` subgroup: the record of a fit of scattered samples (icobrdf/core/spectrum/spectrum.hpp SampleFitRecord).
bool sample_fit_record_matches(const Spectrum& s) {
  if (!s.sample_fit) return false;
  const SampleFitRecord& f = *s.sample_fit;
  const std::int64_t k = s.isotropic ? isotropic_mode_count(s.order) : helmholtz_mode_count(s.order);
  const int ch = s.channel_count();
  return f.unknowns == k && f.standard_error.rows() == ch && f.standard_error.cols() == k &&
         static_cast<int>(f.residual_rms.size()) == ch && static_cast<int>(f.noise_sigma.size()) == ch;
}

static void write_sample_fit(h5::Group& g, const Spectrum& s) {
  const SampleFitRecord& f = *s.sample_fit;
  const std::int64_t k = f.unknowns;
  const int ch = s.channel_count();
  h5::Group r = g.create_group("sample_fit");
  r.set_attr("modes", s.isotropic ? "isotropic (IBSSS, Table 2 order)" : "general Helmholtz (BSSS, library order)");
  r.set_attr("samples", static_cast<std::int64_t>(f.samples));
  r.set_attr("unknowns", static_cast<std::int32_t>(f.unknowns));
  r.set_attr("effective_rank", static_cast<std::int32_t>(f.effective_rank));
  r.set_attr("condition", f.condition);
  r.set_attr("cv_rms", f.cv_rms);
  r.set_attr("cv_folds", static_cast<std::int32_t>(f.cv_folds));
  r.set_attr("tikhonov", f.tikhonov);
  r.set_attr("tikhonov_power", f.tikhonov_power);
  r.set_attr("order_choice", f.order_choice);
  r.set_attr("tikhonov_choice", f.tikhonov_choice);
  r.set_attr("fallback", f.fallback);
  r.set_attr("solver", f.solver);
  r.set_attr("effective_dof", f.effective_dof);
  r.set_attr("class_choice", f.class_choice);
  r.set_attr("cv_rms_isotropic", f.cv_rms_isotropic);
  r.set_attr("cv_rms_general", f.cv_rms_general);
  r.write("residual_rms", f.residual_rms.data(), Shape{dim64(ch)}, "1/sr", "weighted residual RMS per channel");
  r.write("noise_sigma", f.noise_sigma.data(), Shape{dim64(ch)}, "1/sr",
          "estimated error of a sample of weight 1 per channel, RSS / (samples - tr H); NaN when not estimable");
  const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> se = f.standard_error;
  r.write("standard_error", se.data(), Shape{dim64(ch), dim64(k)}, "1",
          "standard error of each mode coefficient (columns in the order of the attribute modes), "
          "sigma * sqrt(diag(M M^T)) from the least-squares covariance; NaN where undefined");
}

static SampleFitRecord read_sample_fit(const h5::Group& g, const Spectrum& s, const h5::ReadLimits& lim) {
  const h5::Group r = g.open_group("sample_fit");
  const std::int64_t k = s.isotropic ? isotropic_mode_count(s.order) : helmholtz_mode_count(s.order);
  const int ch = s.channel_count();
  SampleFitRecord f;
  f.samples = r.attr_int("samples", 0, std::numeric_limits<std::int64_t>::max());
  f.unknowns = static_cast<int>(r.attr_int("unknowns", k, k));
  f.effective_rank = static_cast<int>(r.attr_int("effective_rank", 0, k));
  f.condition = r.attr_double("condition");
  f.cv_rms = r.attr_double("cv_rms");
  f.cv_folds = static_cast<int>(r.attr_int("cv_folds", 0, std::numeric_limits<std::int32_t>::max()));
  f.tikhonov = r.attr_double("tikhonov");
  f.tikhonov_power = r.attr_double("tikhonov_power");
  f.order_choice = r.attr_string("order_choice");
  f.tikhonov_choice = r.attr_string("tikhonov_choice");
  f.fallback = r.attr_string("fallback");
  f.solver = r.attr_string("solver");
  // Written since the class choice (older files lack them: NaN and "").
  if (r.has_attr("effective_dof")) f.effective_dof = r.attr_double("effective_dof");
  if (r.has_attr("class_choice")) f.class_choice = r.attr_string("class_choice");
  if (r.has_attr("cv_rms_isotropic")) f.cv_rms_isotropic = r.attr_double("cv_rms_isotropic");
  if (r.has_attr("cv_rms_general")) f.cv_rms_general = r.attr_double("cv_rms_general");
  const std::pair<const char*, double> figures[] = {{"condition", f.condition}, {"cv_rms", f.cv_rms},
                                                    {"tikhonov", f.tikhonov}, {"tikhonov_power", f.tikhonov_power},
                                                    {"effective_dof", f.effective_dof}, {"cv_rms_isotropic", f.cv_rms_isotropic},
                                                    {"cv_rms_general", f.cv_rms_general}};
  for (const auto& [name, x] : figures)
    if (!std::isnan(x) && !(x >= 0.0 && std::isfinite(x)))
      r.fail(r.path(), std::string("attribute ") + name + ": expected a finite value >= 0 or NaN, found " + std::to_string(x));
  auto vec = [&](const char* name) {
    const auto a = r.read<double>(name, ShapePattern{ch}, lim);
    for (double x : a.data)
      if (!std::isnan(x) && !(x >= 0.0 && std::isfinite(x)))
        r.fail(r.child_path(name), "expected finite values >= 0 or NaN, found " + std::to_string(x));
    return a.data;
  };
  f.residual_rms = vec("residual_rms");
  f.noise_sigma = vec("noise_sigma");
  const auto se = r.read<double>("standard_error", ShapePattern{ch, k}, lim);
  for (double x : se.data)
    if (!std::isnan(x) && !(x >= 0.0 && std::isfinite(x)))
      r.fail(r.child_path("standard_error"), "expected finite values >= 0 or NaN, found " + std::to_string(x));
  f.standard_error = Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(se.data.data(), ch, k);
  return f;
}

void write_material(h5::Group& materials, const MaterialRecord& rec) {
  validate_material_name(rec.name);
  const Spectrum& s = rec.spectrum;
  const std::string& nm = rec.name;
  if (const std::string p = source_text_problem(s.source); !p.empty()) bad_record(nm, p);
  if (s.order < 0 || s.order > kMaxFileOrder)
    bad_record(nm, "expected order in [0, " + std::to_string(kMaxFileOrder) + "], found " + std::to_string(s.order));
  const int ch = s.channel_count();
  if (ch != 1 && ch != 3) bad_record(nm, "expected 1 or 3 channels, found " + std::to_string(ch));
  const std::int64_t m = modes_of(s.order);
  for (int c = 0; c < ch; ++c) {
    if (s.channels[c].rows() != m || s.channels[c].cols() != m)
      bad_record(nm, "channel " + std::to_string(c) + ": expected C of " + std::to_string(m) + " x " + std::to_string(m) +
                         " for order " + std::to_string(s.order) + ", found " + std::to_string(s.channels[c].rows()) + " x " +
                         std::to_string(s.channels[c].cols()));
  }
  const bool has_ibsss = rec.ibsss.size() > 0 || rec.ibsss_indices.rows() > 0;
  if (has_ibsss) {
    if (rec.ibsss.rows() != ch || rec.ibsss.cols() != rec.ibsss_indices.rows())
      bad_record(nm, "expected ibsss of " + std::to_string(ch) + " x " + std::to_string(rec.ibsss_indices.rows()) +
                         " (channels x index rows), found " + std::to_string(rec.ibsss.rows()) + " x " + std::to_string(rec.ibsss.cols()));
    for (Eigen::Index k = 0; k < rec.ibsss_indices.rows(); ++k) {
      const auto& r = rec.ibsss_indices;
      const std::string p = ibsss_index_problem(r(k, 0), r(k, 1), r(k, 2), s.order);
      if (!p.empty()) bad_record(nm, "ibsss_indices row " + std::to_string(k) + " " + index_text(r(k, 0), r(k, 1), r(k, 2)) + ": " + p);
    }
  }
  std::int64_t cells = 0;
  if (!rec.lut.empty()) {
    if (static_cast<int>(rec.lut.size()) != ch)
      bad_record(nm, "expected one LUT per channel (" + std::to_string(ch) + "), found " + std::to_string(rec.lut.size()));
    cells = rec.lut[0].rows();
    for (size_t c = 0; c < rec.lut.size(); ++c) {
      if (rec.lut[c].rows() != cells || rec.lut[c].cols() != cells || cells == 0)
        bad_record(nm, "LUT channel " + std::to_string(c) + ": expected " + std::to_string(cells) + " x " + std::to_string(cells) +
                           " (non-empty, square, same for all channels), found " + std::to_string(rec.lut[c].rows()) + " x " +
                           std::to_string(rec.lut[c].cols()));
      if (rec.lut_float32 && rec.lut[c].cwiseAbs().maxCoeff() > FLT_MAX)
        bad_record(nm, "LUT channel " + std::to_string(c) + " exceeds the float32 range");
    }
    if (s.level < 0 || s.grid_kind.empty())
      bad_record(nm, "a LUT needs the spectrum's level and grid_kind, found level " + std::to_string(s.level) + " and kind '" +
                         s.grid_kind + "'");
    if (s.grid_kind == "equal-area" && cells != equal_area_cells(s.level))
      bad_record(nm, "expected a LUT of " + std::to_string(equal_area_cells(s.level)) + " cells for the equal-area level " +
                         std::to_string(s.level) + ", found " + std::to_string(cells));
  }

  h5::Group g = materials.create_group(nm);
  g.set_attr("source", s.source);
  g.set_attr("order", static_cast<std::int32_t>(s.order));
  g.set_attr("modes", static_cast<std::int32_t>(m));
  g.set_attr("isotropic", s.isotropic);
  g.set_attr("cosine", s.cosine);
  g.set_attr("function", s.cosine ? "g = f cos(theta_i)" : "f");
  g.set_attr("filter", s.filter);
  g.set_attr("level", static_cast<std::int32_t>(s.level));
  g.set_attr("grid_kind", s.grid_kind);
  g.set_attr("channels", static_cast<std::int32_t>(ch));
  // Written only when the source names its channels (RGL materials), so other files stay as they were.
  if (!s.channel_names.empty()) g.set_attr("channel_names", join_channel_names(s.channel_names, ch, nm));
  g.set_attr("gram_error", s.gram_error);
  g.set_attr("reciprocity_violation", s.reciprocity_violation);
  g.set_attr("anisotropy_fraction", s.anisotropy_fraction);
  g.set_attr("max_albedo", s.max_albedo);
  // Written only with a lobe, so that files of modes alone stay as format 1.0 wrote them.
  if (rec.lobe) {
    g.set_attr("representation", representation_name(rec));
    write_half_angle(g, *rec.lobe, ch, nm);
  }

  std::vector<double> buf(static_cast<size_t>(ch * m * m));
  for (int c = 0; c < ch; ++c) RowMap(buf.data() + c * m * m, m, m) = s.channels[c];
  g.write("C", buf.data(), Shape{dim64(ch), dim64(m), dim64(m)}, "1",
          std::string("C[c, a, b] = coefficient of K_a(w_i) K_b(w_r) in the expansion of ") +
              (s.cosine ? "g = f cos(theta_i)" : "f") + " [1/sr]; K in sr^-1/2, so C is dimensionless");

  if (has_ibsss) {
    const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> v = rec.ibsss;
    g.write("ibsss", v.data(), Shape{dim64(ch), dim64(v.cols())}, "1", "isotropic mode coefficients a_nm^l per channel, columns as ibsss_indices");
    g.write("ibsss_indices", reinterpret_cast<const std::int32_t*>(rec.ibsss_indices.data()),
            Shape{dim64(rec.ibsss_indices.rows()), 3}, "index", "(n, m, l) of each ibsss column");
  }

  write_lut(g, rec, cells);
  write_choice(g, rec);
  if (sample_fit_record_matches(s)) write_sample_fit(g, s);
}

namespace {

// The material's IBSSS list (datasets ibsss and ibsss_indices, which come together), when it has one.
void read_ibsss(const h5::Group& g, MaterialRecord& rec, int ch, const h5::ReadLimits& lim) {
  const Spectrum& s = rec.spectrum;
  const bool hv = g.has("ibsss"), hi = g.has("ibsss_indices");
  if (hv != hi) g.fail(g.child_path(hv ? "ibsss_indices" : "ibsss"), "missing dataset (ibsss and ibsss_indices come together)");
  if (hv) {
    auto idx = g.read<std::int32_t>("ibsss_indices", ShapePattern{-1, 3}, lim);
    const std::int64_t k = static_cast<std::int64_t>(idx.shape[0]);
    for (std::int64_t r = 0; r < k; ++r) {
      const int n = idx.data[3 * r], mm = idx.data[3 * r + 1], l = idx.data[3 * r + 2];
      const std::string p = ibsss_index_problem(n, mm, l, s.order);
      if (!p.empty()) g.fail(g.child_path("ibsss_indices"), "row " + std::to_string(r) + " " + index_text(n, mm, l) + ": " + p);
    }
    auto v = g.read<double>("ibsss", ShapePattern{ch, k}, lim);
    for (double x : v.data)
      if (!std::isfinite(x)) g.fail(g.child_path("ibsss"), "expected finite coefficients, found " + std::to_string(x));
    rec.ibsss = Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(v.data.data(), ch, k);
    rec.ibsss_indices = Eigen::Map<const RowMatrix3i>(idx.data.data(), k, 3);
  }
}

// The material's stored LUT (dataset lut): its type, shape and rounding record checked against the
// material's grid (and /grid's, when given); its values read when `read_lut`.
void read_material_lut(const h5::Group& g, MaterialRecord& rec, int ch, const h5::ReadLimits& lim, bool read_lut,
                       const std::optional<GridSummary>& grid) {
  const Spectrum& s = rec.spectrum;
  const std::string obj = g.child_path("lut");
  const h5::Type t = g.dataset_type("lut", lim);
  if (t != h5::Type::float64 && t != h5::Type::float32)
    g.fail(obj, std::string("expected float64 or float32, found ") + h5::type_name(t));
  const h5::Shape shape = g.dataset_shape("lut", lim);
  if (shape.size() != 3 || shape[0] != dim64(ch) || shape[1] != shape[2] || shape[1] == 0)
    g.fail(obj, "expected shape " + std::to_string(ch) + " x cells x cells, found " + h5::shape_text(shape));
  const std::int64_t cells = static_cast<std::int64_t>(shape[1]);
  if (s.level < 0 || s.grid_kind.empty())
    g.fail(obj, "a LUT needs the material's level and grid_kind, found level " + std::to_string(s.level) + " and kind '" +
                    s.grid_kind + "'");
  if (s.grid_kind == "equal-area" && cells != equal_area_cells(s.level))
    g.fail(obj, "expected " + std::to_string(equal_area_cells(s.level)) + " cells for the equal-area level " +
                    std::to_string(s.level) + ", found " + std::to_string(cells));
  if (grid && grid->level == s.level && grid->kind == s.grid_kind && cells != grid->cells)
    g.fail(obj, "expected " + std::to_string(grid->cells) + " cells as in /grid, found " + std::to_string(cells));
  rec.lut_float32 = t == h5::Type::float32;
  if (rec.lut_float32) {
    rec.lut_max_rounding_error = g.attr_double("lut_max_abs_rounding_error");
    if (!(rec.lut_max_rounding_error >= 0.0) || !std::isfinite(rec.lut_max_rounding_error))
      g.fail(g.path(), "attribute lut_max_abs_rounding_error: expected a finite value >= 0, found " +
                           std::to_string(rec.lut_max_rounding_error));
  } else {
    rec.lut_max_rounding_error = 0.0;
  }
  if (read_lut) {
    auto a = g.read_real("lut", ShapePattern{ch, cells, cells}, lim);
    const size_t per = static_cast<size_t>(cells * cells);
    for (size_t i = 0; i < a.data.size(); ++i)
      if (!std::isfinite(a.data[i]))
        g.fail(obj, "expected finite values, found " + std::to_string(a.data[i]) + " at channel " + std::to_string(i / per) +
                        ", incident cell " + std::to_string(i % per / cells) + ", remitted cell " + std::to_string(i % cells));
    rec.lut.resize(ch);
    for (int c = 0; c < ch; ++c) {
      rec.lut[c] = huge_page_matrix(cells, cells);  // advised before the first write (icobrdf/core/support/huge_pages.hpp)
      rec.lut[c] = Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
          a.data.data() + c * per, cells, cells);
    }
  }
}

}  // namespace

MaterialRecord read_material(const h5::Group& materials, const std::string& name, const h5::ReadLimits& lim, bool read_lut,
                             const std::optional<GridSummary>& grid) {
  const std::string problem = material_name_problem(name);
  if (!problem.empty()) materials.fail(materials.child_path(name), "invalid material name: " + problem);
  const h5::Group g = materials.open_group(name);
  g.check_links();
  const h5::ReadScope budget;  // the material's datasets together are held to the memory budget
  MaterialRecord rec;
  rec.name = name;
  Spectrum& s = rec.spectrum;
  s.order = static_cast<int>(g.attr_int("order", 0, kMaxFileOrder));
  const std::int64_t m = modes_of(s.order);
  const std::int64_t modes = g.attr_int("modes", 1, std::numeric_limits<std::int32_t>::max());
  if (modes != m)
    g.fail(g.path(), "attribute modes: expected " + std::to_string(m) + " for order " + std::to_string(s.order) + ", found " +
                         std::to_string(modes));
  const int ch = static_cast<int>(g.attr_int("channels", 1, 3));
  if (ch != 1 && ch != 3) g.fail(g.path(), "attribute channels: expected 1 or 3, found " + std::to_string(ch));
  s.isotropic = g.attr_bool("isotropic");
  s.cosine = g.attr_bool("cosine");
  s.source = g.attr_string("source");
  s.filter = g.attr_string("filter");
  s.level = static_cast<int>(g.attr_int("level", -1, 15));
  s.grid_kind = g.attr_string("grid_kind");
  s.gram_error = g.attr_double("gram_error");
  s.reciprocity_violation = g.attr_double("reciprocity_violation");
  s.anisotropy_fraction = g.attr_double("anisotropy_fraction");
  s.max_albedo = g.attr_double("max_albedo");
  if (g.has_attr("channel_names")) {
    s.channel_names = split_at(g.attr_string("channel_names"), ',');
    if (static_cast<int>(s.channel_names.size()) != ch)
      g.fail(g.path(), "attribute channel_names: expected " + std::to_string(ch) + " comma-separated names, found " +
                           std::to_string(s.channel_names.size()) + " in '" + quoted_text(g.attr_string("channel_names")) + "'");
  }

  {
    auto a = g.read<double>("C", ShapePattern{ch, m, m}, lim);
    for (size_t i = 0; i < a.data.size(); ++i)
      if (!std::isfinite(a.data[i]))
        g.fail(g.child_path("C"), "expected finite coefficients, found " + std::to_string(a.data[i]) + " at channel " +
                                      std::to_string(i / (m * m)) + ", row " + std::to_string(i / m % m) + ", column " +
                                      std::to_string(i % m));
    s.channels.resize(ch);
    for (int c = 0; c < ch; ++c)
      s.channels[c] = Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
          a.data.data() + static_cast<size_t>(c * m * m), m, m);
  }

  if (g.has(kHalfAngleGroup)) {
    rec.lobe = read_half_angle(g, ch, lim);
    const std::string want = representation_name(rec);
    const std::string found = g.has_attr("representation") ? g.attr_string("representation") : std::string("(none)");
    if (found != want) g.fail(g.path(), "attribute representation: expected '" + want + "' for its C and half_angle, found '" + found + "'");
  } else if (g.has_attr("representation") && g.attr_string("representation") != "modes") {
    g.fail(g.child_path(kHalfAngleGroup), "missing group (representation '" + g.attr_string("representation") + "' needs it)");
  }

  read_ibsss(g, rec, ch, lim);
  if (g.has("lut")) read_material_lut(g, rec, ch, lim, read_lut, grid);
  if (g.has("choice")) {
    const h5::Group choice = g.open_group("choice");
    auto names = [&](const std::string& list) {
      std::vector<std::string> out;
      size_t b = 0;
      while (b < list.size()) {
        const size_t e = std::min(list.find(',', b), list.size());
        const std::string k = list.substr(b, e - b);
        if (!choice_key_ok(k) || k == "figures" || k == "labels") choice.fail(choice.path(), "attribute list names '" + k + "'");
        out.push_back(k);
        b = e + 1;
      }
      return out;
    };
    for (const auto& k : names(choice.attr_string("figures"))) rec.figures[k] = choice.attr_double(k);
    for (const auto& k : names(choice.attr_string("labels"))) rec.labels[k] = choice.attr_string(k);
  }
  if (g.has("sample_fit")) s.sample_fit = read_sample_fit(g, s, lim);
  return rec;
}

void write_spectrum_file(const std::string& path, const Spectrum& spectrum, const Grid* grid, const std::string& name) {
  BankContents b;
  if (grid) b.grid = *grid;
  MaterialRecord r;
  r.name = name;
  r.spectrum = spectrum;
  b.materials.push_back(std::move(r));
  write_bank(path, b);
}

std::string lobe_representation_phrase(const MaterialRecord& rec) {
  const std::string r = representation_name(rec);
  if (r == "half-angle") return "a half-angle lobe (no modes)";
  if (r == "hybrid") return "a hybrid of modes and a half-angle lobe (its modes alone are not the material)";
  return "";
}

Spectrum read_spectrum_file(const std::string& path, const std::string& name, const std::string& consumer) {
  ReadOptions o;
  o.read_luts = false;
  MaterialRecord rec = read_bank_material(path, name, o);
  if (rec.lobe)
    throw UnsupportedError(path + "#" + quoted_text(rec.name) + " is " + lobe_representation_phrase(rec) + ": " + consumer);
  return std::move(rec.spectrum);
}

}  // namespace icobrdf
