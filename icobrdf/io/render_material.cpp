#include "icobrdf/io/render_material.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <utility>

#include "icobrdf/core/basis/hemisphere_basis.hpp"
#include "icobrdf/core/models/ggx_vndf.hpp"
#include "icobrdf/core/models/microfacet.hpp"
#include "icobrdf/core/models/model_registry.hpp"
#include "icobrdf/core/support/error.hpp"
#include "icobrdf/io/bank_file.hpp"
#include "icobrdf/io/material_eval.hpp"
#include "icobrdf/io/spectrum_file.hpp"

namespace icobrdf {

// A model term of the regular part: weight x model, a pair formula when the model has one.
struct RenderModelTerm {
  double weight;
  std::shared_ptr<const BrdfModel> model;
  const ScalarBrdfModel* scalar;  // null: batch evaluation with one row
};

struct RenderGgxPart {
  double weight;
  const MicrofacetModel* model;
  double alpha_x, alpha_y, ca, sa;  // widths, tangent axis (cos, sin of its azimuth)
  std::vector<double> albedo;      // per incident node
};

namespace {

// Largest number of parts a material's mixture draws from (delta kinds + GGX terms + the table).
constexpr int kMaxParts = 16;
// Stratified draws per side for a GGX term's albedo at one incident node: 32 x 32 draws estimate the albedo
// to about 1e-3 relative (the weights F G2 / G1 vary by tens of percent at most): the albedos only set the
// mixture's probabilities, which any positive values keep unbiased.
constexpr int kGgxAlbedoDraws = 32;
constexpr int kMaxBasis = (kMaxPointModeOrder + 1) * (kMaxPointModeOrder + 2) / 2;

inline Eigen::Vector3d reflect_about(const Eigen::Vector3d& wi, const Eigen::Vector3d& h) { return 2.0 * wi.dot(h) * h - wi; }

double mean_nonnegative(const Eigen::MatrixXd& f, Eigen::Index row) {
  double s = 0.0;
  for (Eigen::Index c = 0; c < f.cols(); ++c) s += std::max(f(row, c), 0.0);
  return s / static_cast<double>(f.cols());
}

Eigen::VectorXd row_means(const Eigen::MatrixXd& f) {
  Eigen::VectorXd v(f.rows());
  for (Eigen::Index r = 0; r < f.rows(); ++r) v[r] = mean_nonnegative(f, r);
  return v;
}

}  // namespace

struct RenderMaterial::Impl {
  enum class Kind { Model, Record, Source } kind = Kind::Model;
  std::string spec;
  int channels = 1;
  bool isotropic = true;
  std::uint32_t flags = kMaterialReflection;
  // Evaluation.
  std::shared_ptr<const BrdfModel> model;
  std::vector<RenderModelTerm> terms;
  Spectrum modes;
  bool has_modes = false;
  std::shared_ptr<const HalfAngleFactors> lobe;
  std::optional<HalfAnglePairEvaluator> lobe_eval;
  // A stored lobe without modes: eval is the lobe's pair code alone (f = max(0, q), the same values as
  // max(0, 0 + q)); measured 105 -> 83 ns per call for a rank-2 lobe, one program, the general path beside it.
  bool lobe_only = false;
  // Modes of order 0 are a constant (a Lambertian part, as banks store a paint's diffuse layer beside its lobe):
  // c = (C_00 K_0) K_0 per channel (K_0 does not depend on the direction), the products the general sum forms,
  // so eval_modes returns c scale without evaluating the basis at both directions.
  double modes_constant[kMaxMaterialChannels] = {};
  std::shared_ptr<const BrdfSource> source;
  // Sampling.
  HalfVectorTableOptions nodes;
  std::vector<RenderGgxPart> ggx;
  HalfVectorTable table;
  std::uint32_t table_flag = kMaterialDiffuse;
  std::vector<DeltaPart> deltas;
  // The modes' coefficients for eval_modes (after the sampling's members, which sample() reads on every call):
  // modes_count = hemisphere_basis_count(modes.order), modes_rows = modes_count rounded up to a multiple of 4;
  // channel c's column b at (c modes_count + b) modes_rows, each column C_c(., b) padded with zeros to
  // modes_rows. Empty for order 0 (a constant: modes_constant).
  int modes_count = 0;
  int modes_rows = 0;
  std::vector<double> modes_padded;

  [[gnu::always_inline]] inline void eval_regular(const Eigen::Vector3d& wi, const Eigen::Vector3d& wr, double* out) const;
  // eval_regular's sum over the parts, for checked directions (out of line: its stack frame for the models'
  // matrices stays off the lobe-only path).
  [[gnu::noinline]] void eval_parts(const Eigen::Vector3d& wi, const Eigen::Vector3d& wr, double* out) const;
  void eval_modes(const Eigen::Vector3d& wi, const Eigen::Vector3d& wr, double* out) const;
  // Albedos of the parts at w_i: deltas, then GGX terms, then the table; returns the number of parts.
  // b: the blend of the incident nodes at w_i (HalfVectorTable::blend(nodes, wi)), computed once per call.
  int part_albedos(const HalfVectorBlend& b, std::array<double, kMaxParts>& a, double& total) const;
  double regular_pdf(const HalfVectorBlend& b, const Eigen::Vector3d& wi, const Eigen::Vector3d& wr) const;
  void finish(const RenderMaterialOptions& options, const NonNegativeBrdf& rest, double t_warp);
};

void RenderMaterial::Impl::eval_modes(const Eigen::Vector3d& wi, const Eigen::Vector3d& wr, double* out) const {
  const double scale = modes.cosine ? 1.0 / std::max(wi.z(), kGrazingCosFloor) : 1.0;
  if (modes.order == 0) {  // a constant (modes_constant)
    for (int c = 0; c < channels; ++c) out[c] = modes_constant[c] * scale;
    return;
  }
  // f_c = sum_b sum_a C_c(a, b) K_a(w_i) K_b(w_r), over modes_padded's columns: each padded to a multiple of
  // four rows (K_a(w_i) = 0 there), so the inner loop runs over whole groups of four lanes, one accumulator each.
  const int m = modes_count, mp = modes_rows;
  alignas(64) double ki[kMaxBasis + 4], kr[kMaxBasis];
  hemisphere_basis_eval_pair(modes.order, wi.data(), wr.data(), ki, kr);
  for (int q = 0; q < 4; ++q) ki[m + q] = 0.0;  // the padding (mp - m < 4 entries), without a loop on m
  const double* col = modes_padded.data();
  for (int c = 0; c < channels; ++c) {
    double t[4] = {};
    for (int b = 0; b < m; ++b, col += mp) {
      const double kb = kr[b];
      for (int a = 0; a < mp; a += 4)
        for (int q = 0; q < 4; ++q) t[q] += col[a + q] * (ki[a + q] * kb);
    }
    out[c] = ((t[0] + t[1]) + (t[2] + t[3])) * scale;
  }
}

namespace {
// Whether both directions are finite with z >= 0. x - x is 0 for a finite x and NaN for an infinite or NaN one,
// so one sum tests all six components (no branch per component, as allFinite's).
inline bool finite_above_horizon(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const double zeros = ((a.x() - a.x()) + (a.y() - a.y())) + ((a.z() - a.z()) + (b.x() - b.x())) + ((b.y() - b.y()) + (b.z() - b.z()));
  return zeros == 0.0 && a.z() >= 0.0 && b.z() >= 0.0;
}
}  // namespace

inline void RenderMaterial::Impl::eval_regular(const Eigen::Vector3d& wi_in, const Eigen::Vector3d& wr_in, double* out) const {
  if (!finite_above_horizon(wi_in, wr_in)) {
    for (int c = 0; c < channels; ++c) out[c] = 0.0;
    return;
  }
  if (lobe_only) {  // a stored lobe alone (no modes): f = max(0, the lobe's q), without the sum over parts
    lobe_eval->eval(wi_in.data(), wr_in.data(), out);
    if (channels == 1) {  // one channel without the vectorized loop's set-up: 522 -> 512 instructions per call
      out[0] = std::max(0.0, out[0]);
      return;
    }
    for (int c = 0; c < channels; ++c) out[c] = std::max(0.0, out[c]);
    return;
  }
  eval_parts(wi_in, wr_in, out);
}

void RenderMaterial::Impl::eval_parts(const Eigen::Vector3d& wi_in, const Eigen::Vector3d& wr_in, double* out) const {
  for (int c = 0; c < channels; ++c) out[c] = 0.0;
  if (kind == Kind::Model) {
    for (const RenderModelTerm& t : terms) {
      if (t.scalar) {
        const double v = t.weight * t.scalar->value(wi_in, wr_in);
        for (int c = 0; c < channels; ++c) out[c] += v;
        continue;
      }
      const RowMatrix3d a = wi_in.transpose(), b = wr_in.transpose();
      Eigen::MatrixXd v(1, t.model->channels());
      t.model->eval(a, b, v);
      for (int c = 0; c < channels; ++c) out[c] += t.weight * v(0, v.cols() == 1 ? 0 : c);
    }
    return;
  }
  if (kind == Kind::Source) {
    const RowMatrix3d a = wi_in.transpose(), b = wr_in.transpose();
    const Eigen::MatrixXd v = source->eval(a, b);
    for (int c = 0; c < channels; ++c) out[c] = v(0, c);
    return;
  }
  if (has_modes) eval_modes(wi_in, wr_in, out);
  if (!lobe_eval) return;
  double q[kMaxMaterialChannels];
  lobe_eval->eval(wi_in.data(), wr_in.data(), q);
  for (int c = 0; c < channels; ++c) out[c] = std::max(0.0, out[c] + q[c]);
}

int RenderMaterial::Impl::part_albedos(const HalfVectorBlend& b, std::array<double, kMaxParts>& a, double& total) const {
  int n = 0;
  total = 0.0;
  for (const DeltaPart& d : deltas) total += a[static_cast<size_t>(n++)] = d.weight;
  for (const RenderGgxPart& g : ggx) {
    double s = 0.0;
    for (int i = 0; i < b.count; ++i) s += b.weight[i] * g.albedo[static_cast<size_t>(b.node[i])];
    total += a[static_cast<size_t>(n++)] = s;
  }
  if (!table.empty()) total += a[static_cast<size_t>(n++)] = table.albedo(b);
  return n;
}

namespace {

// w in the frame of a GGX term's tangent axes and back.
inline Eigen::Vector3d to_tangent(const RenderGgxPart& g, const Eigen::Vector3d& w) {
  return {g.ca * w.x() + g.sa * w.y(), -g.sa * w.x() + g.ca * w.y(), w.z()};
}
inline Eigen::Vector3d from_tangent(const RenderGgxPart& g, const Eigen::Vector3d& w) {
  return {g.ca * w.x() - g.sa * w.y(), g.sa * w.x() + g.ca * w.y(), w.z()};
}

double ggx_pdf(const RenderGgxPart& g, const Eigen::Vector3d& wi, const Eigen::Vector3d& wr) {
  Eigen::Vector3d h;
  double c;
  if (!reflection_half_vector(wi, wr, h, c)) return 0.0;
  return ggx_visible_normal_pdf(to_tangent(g, wi), to_tangent(g, h), g.alpha_x, g.alpha_y) / (4.0 * c);
}

}  // namespace

double RenderMaterial::Impl::regular_pdf(const HalfVectorBlend& b, const Eigen::Vector3d& wi, const Eigen::Vector3d& wr) const {
  if (!(wi.z() >= 0.0) || !(wr.z() >= 0.0)) return 0.0;
  std::array<double, kMaxParts> a;
  double total;
  part_albedos(b, a, total);
  if (!(total > 0.0)) return 0.0;
  int n = static_cast<int>(deltas.size());
  double p = 0.0;
  for (const RenderGgxPart& g : ggx) {
    const double w = a[static_cast<size_t>(n++)];
    if (w > 0.0) p += w * ggx_pdf(g, wi, wr);
  }
  if (!table.empty() && a[static_cast<size_t>(n)] > 0.0) p += a[static_cast<size_t>(n)] * table.pdf(b, wi, wr);
  return p / total;
}

void RenderMaterial::Impl::finish(const RenderMaterialOptions& options, const NonNegativeBrdf& rest, double t_warp) {
  if (channels < 1 || channels > kMaxMaterialChannels)
    throw ArgumentError(spec + ": " + std::to_string(channels) + " channels, expected 1 to " + std::to_string(kMaxMaterialChannels) +
                        " for a render material");
  if (static_cast<int>(deltas.size() + ggx.size()) + 1 > kMaxParts)
    throw ArgumentError(spec + ": " + std::to_string(ggx.size()) + " GGX terms, expected at most " +
                        std::to_string(kMaxParts - 1 - static_cast<int>(deltas.size())));
  nodes = options.table;
  if (!isotropic && nodes.azimuth_nodes == 1)
    nodes.azimuth_nodes = options.anisotropic_azimuth_nodes, nodes.theta_nodes = options.anisotropic_theta_nodes;
  nodes.t_warp = std::clamp(t_warp, 1.0, 4.0);
  HalfVectorTable::check(nodes);
  if (rest) table = HalfVectorTable(rest, nodes);
  // GGX albedos per node: the mean visible-normal weight over stratified draws.
  for (RenderGgxPart& g : ggx) {
    g.albedo.assign(static_cast<size_t>(nodes.theta_nodes) * static_cast<size_t>(nodes.azimuth_nodes), 0.0);
    for (size_t n = 0; n < g.albedo.size(); ++n) {
      const Eigen::Vector3d wi = HalfVectorTable::node_direction(nodes, static_cast<int>(n));
      const Eigen::Vector3d wt = to_tangent(g, wi);
      double s = 0.0;
      for (int a = 0; a < kGgxAlbedoDraws; ++a)
        for (int b = 0; b < kGgxAlbedoDraws; ++b) {
          const Eigen::Vector3d h = from_tangent(g, sample_ggx_visible_normal(wt, g.alpha_x, g.alpha_y, (a + 0.5) / kGgxAlbedoDraws,
                                                                              (b + 0.5) / kGgxAlbedoDraws));
          const Eigen::Vector3d wr = reflect_about(wi, h);
          if (!(wr.z() >= 0.0)) continue;
          const double pdf = ggx_pdf(g, wi, wr);
          if (pdf > 0.0) s += g.model->value(wi, wr) * wr.z() / pdf;
        }
      g.albedo[n] = g.weight * s / (kGgxAlbedoDraws * kGgxAlbedoDraws);
    }
  }
  if (!deltas.empty()) flags |= kMaterialSpecular;
  if (!ggx.empty()) flags |= kMaterialGlossy;
  if (!table.empty()) flags |= table_flag;
}

RenderMaterial::RenderMaterial(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
RenderMaterial::~RenderMaterial() = default;
RenderMaterial::RenderMaterial(RenderMaterial&&) noexcept = default;
RenderMaterial& RenderMaterial::operator=(RenderMaterial&&) noexcept = default;

RenderMaterial::RenderMaterial(std::shared_ptr<const BrdfModel> model, const RenderMaterialOptions& options)
    : impl_(std::make_unique<Impl>()) {
  if (!model) throw ArgumentError("render material: no model");
  Impl& m = *impl_;
  m.kind = Impl::Kind::Model;
  m.spec = "model:" + model->spec();
  m.channels = model->channels();
  m.isotropic = model->is_isotropic();
  m.model = model;
  m.deltas = model->delta_parts();
  std::vector<SumModel::Term> flat;
  if (const auto* sum = dynamic_cast<const SumModel*>(model.get()))
    flat = sum->terms();
  else
    flat.push_back({1.0, model});
  std::vector<RenderModelTerm> rest;
  m.table_flag = kMaterialDiffuse;
  for (const auto& t : flat) {
    if (dynamic_cast<const MirrorModel*>(t.model.get()) || dynamic_cast<const RetroreflectorModel*>(t.model.get())) continue;
    const auto* mf = dynamic_cast<const MicrofacetModel*>(t.model.get());
    const RenderModelTerm term{t.weight, t.model, dynamic_cast<const ScalarBrdfModel*>(t.model.get())};
    m.terms.push_back(term);
    if (mf && mf->params().distribution == MicrofacetDistribution::Ggx && options.visible_normals) {
      const MicrofacetParams& p = mf->params();
      const double az = p.azimuth_deg * M_PI / 180.0;
      m.ggx.push_back({t.weight, mf, p.alpha_x, p.anisotropic ? p.alpha_y : p.alpha_x, std::cos(az), std::sin(az), {}});
    } else {
      rest.push_back(term);
      if (mf) m.table_flag = kMaterialGlossy;  // Beckmann: a glossy lobe sampled from the tables
    }
  }
  NonNegativeBrdf fbar;
  if (!rest.empty())
    fbar = [rest, channels = m.channels](const RowMatrix3d& wi, const RowMatrix3d& wr) {
      Eigen::MatrixXd sum = Eigen::MatrixXd::Zero(wi.rows(), channels), part;
      for (const RenderModelTerm& t : rest) {
        part.resize(wi.rows(), t.model->channels());
        t.model->eval(wi, wr, part);
        for (int c = 0; c < channels; ++c) sum.col(c) += t.weight * part.col(part.cols() == 1 ? 0 : c);
      }
      return row_means(sum);
    };
  m.finish(options, fbar, 2.0);
}

RenderMaterial::RenderMaterial(const Spectrum& modes, const std::optional<HalfAngleFactors>& lobe, const RenderMaterialOptions& options)
    : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.kind = Impl::Kind::Record;
  m.spec = modes.source.empty() ? std::string("stored material") : modes.source;
  m.channels = modes.channel_count();
  m.modes = modes;
  for (const auto& c : modes.channels) m.has_modes |= c.size() > 0 && c.cwiseAbs().maxCoeff() > 0.0;
  if (m.has_modes && modes.order > kMaxPointModeOrder)
    throw ArgumentError(m.spec + ": modes of order " + std::to_string(modes.order) + ", expected at most " +
                        std::to_string(kMaxPointModeOrder) + " for a render material");
  if (m.has_modes) {  // every channel's coefficients are read as a count x count matrix per sample
    const int count = modes.order >= 0 ? hemisphere_basis_count(modes.order) : 0;
    for (size_t c = 0; c < modes.channels.size(); ++c) {
      const Eigen::MatrixXd& C = modes.channels[c];
      if (C.rows() != count || C.cols() != count)
        throw ArgumentError(m.spec + ": modes of channel " + std::to_string(c) + " are " + std::to_string(C.rows()) + " x " +
                            std::to_string(C.cols()) + ", expected " + std::to_string(count) + " x " + std::to_string(count) +
                            " for order " + std::to_string(modes.order));
    }
    m.modes_count = count;
    if (modes.order == 0) {  // a constant (modes_constant): no basis, no padded copy
      double k0;
      hemisphere_basis_eval(0, Eigen::Vector3d(0.0, 0.0, 1.0), &k0);
      for (int c = 0; c < m.channels; ++c) m.modes_constant[c] = (modes.channels[static_cast<size_t>(c)](0, 0) * k0) * k0;
    } else {
      m.modes_rows = (count + 3) / 4 * 4;
      const size_t rows = static_cast<size_t>(m.modes_rows), cols = static_cast<size_t>(count);
      m.modes_padded.assign(static_cast<size_t>(m.channels) * cols * rows, 0.0);
      for (size_t c = 0; c < static_cast<size_t>(m.channels); ++c)
        for (size_t b = 0; b < cols; ++b)
          for (size_t a = 0; a < cols; ++a)
            m.modes_padded[(c * cols + b) * rows + a] = modes.channels[c](static_cast<Eigen::Index>(a), static_cast<Eigen::Index>(b));
    }
  }
  if (lobe) {
    if (lobe->channels() != m.channels)
      throw ArgumentError(m.spec + ": lobe of " + std::to_string(lobe->channels()) + " channels beside modes of " + std::to_string(m.channels));
    m.lobe = std::make_shared<const HalfAngleFactors>(*lobe);
    m.lobe_eval.emplace(m.lobe);
    m.lobe_only = !m.has_modes;
  }
  m.isotropic = (!m.has_modes || modes.isotropic) && (!lobe || lobe->isotropic);
  m.table_flag = lobe ? kMaterialGlossy : kMaterialDiffuse;
  std::shared_ptr<const HalfAngleFactors> l = m.lobe;
  const Spectrum* s = &m.modes;
  const bool has_modes = m.has_modes;
  const NonNegativeBrdf fbar = [s, l, has_modes](const RowMatrix3d& wi, const RowMatrix3d& wr) {
    if (!has_modes) return row_means(l->eval(wi, wr).cwiseMax(0.0));
    return row_means(evaluate_material(*s, l ? std::optional<HalfAngleFactors>(*l) : std::nullopt, wi, wr));
  };
  m.finish(options, fbar, lobe ? lobe->h_warp : 2.0);
}

RenderMaterial::RenderMaterial(std::shared_ptr<const BrdfSource> source, const RenderMaterialOptions& options)
    : impl_(std::make_unique<Impl>()) {
  if (!source) throw ArgumentError("render material: no source");
  Impl& m = *impl_;
  m.kind = Impl::Kind::Source;
  m.spec = source->spec();
  m.channels = source->channels();
  m.isotropic = source->isotropic_by_construction();
  m.source = source;
  m.table_flag = kMaterialGlossy;
  m.finish(options, [source](const RowMatrix3d& wi, const RowMatrix3d& wr) {
    Eigen::MatrixXd f = source->eval(wi, wr);
    for (Eigen::Index r = 0; r < f.rows(); ++r)
      for (Eigen::Index c = 0; c < f.cols(); ++c)
        if (std::isnan(f(r, c))) f(r, c) = 0.0;  // a measured table's empty bins carry no mass
    return row_means(f);
  }, 2.0);
}

RenderMaterial RenderMaterial::open(const std::string& text, const RenderMaterialOptions& options) {
  if (is_model_source(text)) return RenderMaterial(std::shared_ptr<const BrdfModel>(parse_model_source(text)), options);
  const auto ref = split_material_ref(text);
  if (ref.path.size() > 3 && ref.path.compare(ref.path.size() - 3, 3, ".h5") == 0) {
    ReadOptions ro;
    ro.read_luts = false;
    MaterialRecord rec = read_bank_material(ref.path, ref.name, ro);
    rec.spectrum.source = text;
    return RenderMaterial(rec.spectrum, rec.lobe, options);
  }
  return RenderMaterial(std::shared_ptr<const BrdfSource>(open_source(text)), options);
}

int RenderMaterial::channels() const { return impl_->channels; }
std::uint32_t RenderMaterial::flags() const { return impl_->flags; }
bool RenderMaterial::isotropic() const { return impl_->isotropic; }
const std::string& RenderMaterial::spec() const { return impl_->spec; }

MaterialColor<double> RenderMaterial::eval(const Eigen::Vector3d& wi, const Eigen::Vector3d& wr) const {
  MaterialColor<double> out(impl_->channels);
  impl_->eval_regular(wi, wr, out.data());
  return out;
}

MaterialColor<float> RenderMaterial::eval(const Eigen::Vector3f& wi, const Eigen::Vector3f& wr) const {
  double v[kMaxMaterialChannels];  // the double values, rounded once into the result (no double vector between)
  impl_->eval_regular(Eigen::Vector3d(wi.cast<double>()), Eigen::Vector3d(wr.cast<double>()), v);
  MaterialColor<float> out(impl_->channels);
  for (int c = 0; c < impl_->channels; ++c) out[c] = static_cast<float>(v[c]);
  return out;
}

double RenderMaterial::pdf(const Eigen::Vector3d& wi, const Eigen::Vector3d& wr) const {
  if (!wi.allFinite() || !wr.allFinite()) return 0.0;
  return impl_->regular_pdf(HalfVectorTable::blend(impl_->nodes, wi), wi, wr);
}

float RenderMaterial::pdf(const Eigen::Vector3f& wi, const Eigen::Vector3f& wr) const {
  return static_cast<float>(pdf(Eigen::Vector3d(wi.cast<double>()), Eigen::Vector3d(wr.cast<double>())));
}

double RenderMaterial::albedo_estimate(const Eigen::Vector3d& wi) const {
  std::array<double, kMaxParts> a;
  double total;
  impl_->part_albedos(HalfVectorTable::blend(impl_->nodes, wi), a, total);
  return total;
}

double RenderMaterial::delta_albedo() const {
  double s = 0.0;
  for (const DeltaPart& d : impl_->deltas) s += d.weight;
  return s;
}

MaterialSample<double> RenderMaterial::sample(const Eigen::Vector3d& wi, double u1, double u2) const {
  const Impl& m = *impl_;
  MaterialSample<double> s;
  s.weight.setZero(m.channels);
  if (!(wi.z() >= 0.0) || !wi.allFinite() || !(u1 >= 0.0 && u1 <= 1.0) || !(u2 >= 0.0 && u2 <= 1.0)) return s;
  // u1 alone gives the table's cell index: its entries are fetched while the blend and the part are found.
  m.table.prefetch_draw(u1);
  std::array<double, kMaxParts> a;
  double total;
  const HalfVectorBlend b = HalfVectorTable::blend(m.nodes, wi);
  const int parts = m.part_albedos(b, a, total);
  if (!(total > 0.0)) return s;
  // The part: u2 by the albedos, then rescaled to [0, 1) within it (one part: u2 itself, which the rescale
  // returns to rounding; the draw does not wait for a division then).
  double x = u2, acc = 0.0, part_lo = 0.0;
  int part = 0;
  if (parts > 1) {
    x = u2 * total, part = -1;
    for (int i = 0; i < parts; ++i) {
      if (!(a[static_cast<size_t>(i)] > 0.0)) continue;
      part = i, part_lo = acc;  // the last part with albedo takes u2 rounding up to its end
      if (x < acc + a[static_cast<size_t>(i)]) break;
      acc += a[static_cast<size_t>(i)];
    }
    x = std::clamp((x - part_lo) / a[static_cast<size_t>(part)], 0.0, 1.0);
  }
  const int n_delta = static_cast<int>(m.deltas.size()), n_ggx = static_cast<int>(m.ggx.size());
  if (part < n_delta) {
    const DeltaPart& d = m.deltas[static_cast<size_t>(part)];
    s.wr = d.kind == DeltaPart::Mirror ? Eigen::Vector3d(-wi.x(), -wi.y(), wi.z()) : wi;
    s.pdf = d.weight / total;
    s.weight.setConstant(d.weight / s.pdf);
    s.flags = kMaterialReflection | kMaterialSpecular;
    return s;
  }
  Eigen::Vector3d wr;
  std::uint32_t lobe_flag;
  double table_pdf = -1.0;  // the table's density at its own draw, when the table is the only regular part
  if (part < n_delta + n_ggx) {
    const RenderGgxPart& g = m.ggx[static_cast<size_t>(part - n_delta)];
    wr = reflect_about(wi, from_tangent(g, sample_ggx_visible_normal(to_tangent(g, wi), g.alpha_x, g.alpha_y, u1, x)));
    lobe_flag = kMaterialGlossy;
  } else {
    double p;
    if (!m.table.sample(b, wi, u1, x, wr, p)) return s;
    if (m.ggx.empty()) table_pdf = a[static_cast<size_t>(part)] / total * p;
    lobe_flag = m.table_flag;
  }
  if (!(wr.z() >= 0.0)) return s;
  const double pdf = table_pdf >= 0.0 ? table_pdf : m.regular_pdf(b, wi, wr);
  if (!(pdf > 0.0)) return s;
  double f[kMaxMaterialChannels];
  m.eval_regular(wi, wr, f);
  s.wr = wr;
  s.pdf = pdf;
  const double cos_over_pdf = wr.z() / pdf;
  for (int c = 0; c < m.channels; ++c) s.weight[c] = f[c] * cos_over_pdf;
  s.flags = kMaterialReflection | lobe_flag;
  return s;
}

MaterialSample<float> RenderMaterial::sample(const Eigen::Vector3f& wi, float u1, float u2) const {
  const MaterialSample<double> d = sample(Eigen::Vector3d(wi.cast<double>()), static_cast<double>(u1), static_cast<double>(u2));
  MaterialSample<float> s;
  s.wr = d.wr.cast<float>();
  s.weight = d.weight.cast<float>();
  s.pdf = static_cast<float>(d.pdf);
  s.flags = d.flags;
  return s;
}

}  // namespace icobrdf
