#include "icobrdf/io/measured_sources.hpp"

#include <sys/stat.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <mutex>
#include <optional>
#include <random>
#include <sstream>
#include <vector>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/support/scramble.hpp"
#include "icobrdf/core/basis/helmholtz_modes.hpp"
#include "icobrdf/core/basis/hemisphere_basis.hpp"
#include "icobrdf/core/basis/isotropic_modes.hpp"
#include "icobrdf/core/projection/projection.hpp"
#include "icobrdf/core/fit/dense_kernels.hpp"
#include "icobrdf/core/fit/sample_fit_selection.hpp"
#include "icobrdf/core/spectrum/spectrum_ops.hpp"
#include "icobrdf/io/curet.hpp"
#include "icobrdf/io/merl.hpp"
#include "icobrdf/core/tables/grid_noise.hpp"
#include "icobrdf/io/rgl_bsdf.hpp"
#include "icobrdf/io/sample_arrays.hpp"
#include "icobrdf/io/sample_csv.hpp"
#include "icobrdf/io/scatmech_coefficients.hpp"

namespace icobrdf {

namespace {

bool ends_with(const std::string& s, const std::string& tail) {
  return s.size() > tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}
bool starts_with(const std::string& s, const std::string& head) { return s.rfind(head, 0) == 0; }

struct Options {
  std::string path;
  std::vector<std::pair<std::string, std::string>> kv;  // key, value ("" for flags)
};

// "PATH#k=v,flag" -> path and options.
Options split_options(const std::string& text) {
  Options o;
  const auto hash = text.rfind('#');
  o.path = hash == std::string::npos ? text : text.substr(0, hash);
  if (hash == std::string::npos) return o;
  std::stringstream ss(text.substr(hash + 1));
  std::string item;
  while (std::getline(ss, item, ',')) {
    if (item.empty()) continue;
    const auto eq = item.find('=');
    o.kv.emplace_back(item.substr(0, eq), eq == std::string::npos ? "" : item.substr(eq + 1));
  }
  return o;
}

double number_option(const std::string& text, const std::string& key, const std::string& value) {
  char* end = nullptr;
  const double x = std::strtod(value.c_str(), &end);
  if (value.empty() || *end != '\0' || !std::isfinite(x))
    throw ArgumentError("SOURCE '" + quoted_text(text) + "': option " + key + " expected a finite number, found '" + quoted_text(value) + "'");
  return x;
}

void require_file(const std::string& path, const std::string& text) {
  struct stat st{};
  if (::stat(path.c_str(), &st) != 0) throw InputError(path + ": no such file (SOURCE '" + quoted_text(text) + "')");
}

void check_fit_options(const FitOptions& o, const std::string& what) {
  if (o.cosine)
    throw UnsupportedError(what + ": --cosine is not supported (the fit uses the reciprocal modes of f; g = f cos(theta_i) is not reciprocal)");
}

double max_albedo_on(const ProjectionContext& ctx, const Spectrum& s) {
  if (!ctx.grid) return std::numeric_limits<double>::quiet_NaN();
  double m = 0;
  for (const auto& c : s.channels) m = std::max(m, spectral_albedo(c, s.order, ctx.grid->directions).maxCoeff());
  return m;
}

void finish(Spectrum& s, const FitOptions& o, const ProjectionContext& ctx) {
  if (o.filter.kind != LowPassFilter::Kind::None)
    for (auto& c : s.channels) c = filter_coefficients(c, s.order, o.filter);
  s.filter = o.filter.name();
  s.level = -1;
  s.grid_kind.clear();
  s.anisotropy_fraction = 0;
  for (const auto& c : s.channels) s.anisotropy_fraction = std::max(s.anisotropy_fraction, anisotropic_energy_fraction(c));
  s.max_albedo = max_albedo_on(ctx, s);
}

Spectrum spectrum_of(const CheckedSampleFit& c, const std::string& source, double tikhonov_power) {
  const SampleFitResult& r = c.fit;
  Spectrum s;
  s.order = r.order;
  s.isotropic = r.isotropic;
  s.channels = r.channels;
  s.source = source;
  s.reciprocity_violation = 0;  // the modes are reciprocal by construction
  SampleFitRecord f;
  f.samples = r.samples;
  f.unknowns = r.unknowns;
  f.effective_rank = r.effective_rank;
  f.condition = r.condition;
  f.residual_rms.assign(r.residual_rms.data(), r.residual_rms.data() + r.residual_rms.size());
  f.noise_sigma.assign(r.noise_sigma.data(), r.noise_sigma.data() + r.noise_sigma.size());
  f.cv_rms = c.cv_rms;
  f.cv_folds = c.cv_folds;
  f.tikhonov = r.tikhonov;
  f.tikhonov_power = tikhonov_power;
  f.order_choice = c.order_choice;
  f.tikhonov_choice = c.tikhonov_choice;
  f.fallback = c.fallback;
  f.solver = r.solver;
  f.effective_dof = r.hat_trace;
  f.class_choice = c.class_choice;
  f.cv_rms_isotropic = c.cv_rms_isotropic;
  f.cv_rms_general = c.cv_rms_general;
  f.standard_error = r.standard_error.transpose();
  s.sample_fit = std::move(f);
  return s;
}

class SampleFitHolder {
 public:
  const CheckedSampleFit* last() const {
    std::lock_guard<std::mutex> g(mu_);
    return has_ ? &last_ : nullptr;
  }
  void store(const CheckedSampleFit& r) const {
    std::lock_guard<std::mutex> g(mu_);
    last_ = r;
    has_ = true;
  }
  const KernelFit* last_kernels() const {
    std::lock_guard<std::mutex> g(mu_);
    return kernels_ ? &*kernels_ : nullptr;
  }
  void store_kernels(const KernelFit& k) const {
    std::lock_guard<std::mutex> g(mu_);
    kernels_ = k;
  }

 private:
  mutable std::mutex mu_;
  mutable CheckedSampleFit last_;
  mutable bool has_ = false;
  mutable std::optional<KernelFit> kernels_;
};

// The split of a sample fit over the processes of a distributed fit (null in one process).
std::shared_ptr<const SampleFitSplit> sample_fit_split(const FitOptions& o) {
  if (!o.share || o.share->parts <= 1 || !o.share->sample_sum) return nullptr;
  auto split = std::make_shared<SampleFitSplit>();
  split->part = o.share->part;
  split->parts = o.share->parts;
  split->sum = o.share->sample_sum;
  return split;
}

// The held-out draws of the sources judged at their own samples (icobrdf/pipeline/held_out.hpp describes them).
// A MERL table's held-out pairs are its own samples: its lookup between them is piecewise constant (1-degree
// bins), so pairs elsewhere would measure the bins' steps rather than the data (GGX 0.2 written to a table: the
// table's lookup is 0.056 from the model it sampled, a rank-2 lobe fitted to its samples 0.026). Bins are drawn
// with probability proportional to their solid-angle measure (icobrdf/io/merl.hpp merl_samples), so that the plain
// relative L2 over the pairs estimates the measure-weighted error over the table; each pair is turned about
// the normal by a random azimuth (the table is isotropic). Every bin drawn is left out of the fits (`bins`).
PairValues draw_merl_held_out(const HeldOutRequest& r, const MerlTable& table, std::vector<std::int64_t>& bins) {
  const MerlSamples smp = merl_samples(table);
  // Seeded by the first 15 hex digits of the name's hash (the seeds of earlier banks, kept so banks stay the same).
  std::mt19937_64 rng(fnv1a64("holdout|" + r.material) >> 4);
  const double zlo = std::cos(r.incidence_max_deg * M_PI / 180), zhi = std::cos(r.incidence_min_deg * M_PI / 180);
  Eigen::VectorXd w = smp.weights;
  for (Eigen::Index k = 0; k < w.size(); ++k)
    if (smp.wi(k, 2) < zlo || smp.wi(k, 2) > zhi) w(k) = 0.0;
  if (!(w.sum() > 0.0)) throw InputError("MERL table '" + table.path + "' has no valid sample in the material's incidence range");
  std::discrete_distribution<Eigen::Index> pick(w.data(), w.data() + w.size());
  std::uniform_real_distribution<double> turn(0.0, 2.0 * M_PI);
  PairValues h;
  h.wi.resize(r.pairs, 3);
  h.wr.resize(r.pairs, 3);
  h.f.resize(r.pairs, smp.values.cols());
  for (int k = 0; k < r.pairs; ++k) {
    const Eigen::Index j = pick(rng);
    const double a = turn(rng), c = std::cos(a), sn = std::sin(a);
    h.wi.row(k) << c * smp.wi(j, 0) - sn * smp.wi(j, 1), sn * smp.wi(j, 0) + c * smp.wi(j, 1), smp.wi(j, 2);
    h.wr.row(k) << c * smp.wr(j, 0) - sn * smp.wr(j, 1), sn * smp.wr(j, 0) + c * smp.wr(j, 1), smp.wr(j, 2);
    h.f.row(k) = smp.values.row(j);
    bins.push_back(smp.bins[static_cast<size_t>(j)]);
  }
  return h;
}

// CSV samples: the held_out_sample_count samples with the smallest splitmix64(seed + index) among those whose
// incidence lies in the material's range, seed = FNV-1a of "holdout|NAME"; a merged sample (weight = rows
// merged) is one pair per row. (Ranking FNV-1a of "holdout|NAME|INDEX" itself held out runs of 100
// consecutive samples: its high bits hardly depend on the last digits.)
PairValues draw_samples_held_out(const HeldOutRequest& r, const BrdfSamples& smp, const std::string& spec, std::vector<bool>& held) {
  if (r.lights_and_cameras)
    throw ArgumentError("material '" + r.material + "': SOURCE '" + quoted_text(spec) +
                        "' holds scattered samples, which have no values at the scene's light x camera pairs: remove lights and cameras, its errors are measured on held-out samples");
  const double zlo = std::cos(r.incidence_max_deg * M_PI / 180), zhi = std::cos(r.incidence_min_deg * M_PI / 180);
  const Eigen::Index n = smp.wi.rows();
  const std::uint64_t seed = fnv1a64("holdout|" + r.material);
  std::vector<std::pair<std::uint64_t, Eigen::Index>> eligible;
  for (Eigen::Index k = 0; k < n; ++k)
    if (smp.wi(k, 2) >= zlo && smp.wi(k, 2) <= zhi) eligible.emplace_back(splitmix64(seed + static_cast<std::uint64_t>(k)), k);
  const long long count = held_out_sample_count(n, r.pairs);
  if (count < 1 || eligible.empty())
    throw InputError("material '" + r.material + "': SOURCE '" + quoted_text(spec) + "' has " + std::to_string(n) + " sample(s), " +
                     std::to_string(eligible.size()) + " in the incidence range; a held-out split needs at least " +
                     std::to_string(kHeldOutShare) + " samples with some in the range");
  const auto take = static_cast<size_t>(std::min<long long>(count, static_cast<long long>(eligible.size())));
  std::partial_sort(eligible.begin(), eligible.begin() + static_cast<std::ptrdiff_t>(take), eligible.end());
  held.assign(static_cast<size_t>(n), false);
  Eigen::Index rows = 0;
  for (size_t k = 0; k < take; ++k) {
    held[static_cast<size_t>(eligible[k].second)] = true;
    rows += static_cast<Eigen::Index>(std::llround(smp.weights(eligible[k].second)));
  }
  PairValues h;
  h.wi.resize(rows, 3);
  h.wr.resize(rows, 3);
  h.f.resize(rows, smp.values.cols());
  Eigen::Index row = 0;
  for (size_t k = 0; k < take; ++k) {
    const Eigen::Index j = eligible[k].second;
    for (long long c = std::llround(smp.weights(j)); c > 0; --c, ++row) {
      h.wi.row(row) = smp.wi.row(j);
      h.wr.row(row) = smp.wr.row(j);
      h.f.row(row) = smp.values.row(j);
    }
  }
  return h;
}

// The largest order whose modes the samples determine: at least kMinSamplesPerUnknown samples per unknown.
int largest_order_of(long long samples, bool isotropic) {
  const int cap = isotropic ? kMaxAutoOrderIsotropic : kMaxAutoOrderGeneral;
  int best = -1;
  for (int n = 0; n <= cap; ++n) {
    const long long unknowns = isotropic ? isotropic_mode_count(n) : helmholtz_mode_count(n);
    if (unknowns * kMinSamplesPerUnknown > samples) break;
    best = n;
  }
  return best;
}

class MerlSource final : public BrdfSource, public SampleFitHolder {
 public:
  MerlSource(std::shared_ptr<const MerlTable> t, std::string text) : model_(std::move(t)), text_(std::move(text)) {}
  std::string spec() const override { return text_; }
  int channels() const override { return 3; }
  Eigen::MatrixXd eval(const RowMatrix3d& wi, const RowMatrix3d& wr) const override {
    Eigen::MatrixXd out(wi.rows(), 3);
    model_.eval(wi, wr, out);
    return out;
  }
  Spectrum fit(const ProjectionContext& ctx, const FitOptions& o) const override {
    check_fit_options(o, "MERL SOURCE '" + text_ + "'");
    if (o.order < 0)
      throw UnsupportedError("MERL SOURCE '" + text_ + "': give the order (--order); it is chosen automatically only for CSV samples");
    const MerlSamples smp = merl_samples(model_.table());
    SampleFitOptions so;
    so.order = o.order;
    so.isotropic = true;
    so.progress = o.progress;
    so.kernels = &default_dense_kernels();  // the program's choice (icobrdf::blas), Eigen's otherwise
    so.split = sample_fit_split(o);  // under mpirun: each rank passes over its part of the samples
    CheckedSampleFit c;
    c.fit = fit_samples(smp.wi, smp.wr, smp.values, smp.weights, so);
    c.cv_rms = std::numeric_limits<double>::quiet_NaN();  // not measured for MERL tables
    store(c);
    Spectrum s = spectrum_of(c, text_, so.tikhonov_power);
    finish(s, o, ctx);
    return s;
  }
  const MerlTable& table() const { return model_.table(); }
  // Per theta_h bin and channel, the noise of its theta_d x phi_d table; missing samples and nodes with a
  // direction below the horizon (no measurement: 0 or an extrapolation) are left out.
  std::optional<Eigen::MatrixXd> noise_sigma_at(const RowMatrix3d& wi, const RowMatrix3d& wr) const override {
    Eigen::MatrixXd slab(kMerlThetaHalfRes, 3);
    const std::int64_t per_slab = static_cast<std::int64_t>(kMerlThetaDiffRes) * kMerlPhiDiffRes;
    std::vector<double> v(static_cast<size_t>(per_slab));
    for (int h = 0; h < kMerlThetaHalfRes; ++h) {
      std::vector<bool> above(static_cast<size_t>(per_slab));
      for (int d = 0; d < kMerlThetaDiffRes; ++d)
        for (int p = 0; p < kMerlPhiDiffRes; ++p) {
          Eigen::Vector3d a, b;
          directions_from_half_diff(merl_node(MerlBin{h, d, p}), a, b);
          above[static_cast<size_t>(d * kMerlPhiDiffRes + p)] = a.z() > 0 && b.z() > 0;
        }
      for (int c = 0; c < 3; ++c) {
        const double* f = table().f.data() + c * kMerlSamplesPerChannel + h * per_slab;
        for (std::int64_t k = 0; k < per_slab; ++k) v[static_cast<size_t>(k)] = above[static_cast<size_t>(k)] ? f[k] : std::nan("");
        slab(h, c) = table_noise_sigma(v.data(), kMerlThetaDiffRes, kMerlPhiDiffRes);
      }
    }
    Eigen::MatrixXd out(wi.rows(), 3);
    for (Eigen::Index k = 0; k < wi.rows(); ++k) {
      if (!(wi(k, 2) > 0 && wr(k, 2) > 0)) {
        out.row(k).setZero();
        continue;
      }
      out.row(k) = slab.row(merl_bin(wi.row(k).transpose(), wr.row(k).transpose()).theta_h);
    }
    return out;
  }

  bool may_miss_values() const override { return true; }
  bool isotropic_by_construction() const override { return true; }
  bool reciprocal_by_construction() const override { return true; }  // half and difference angles: exchange-invariant
  bool judged_at_own_samples() const override { return true; }
  // A table's fits are isotropic whatever is asked, and its million samples are never the bound.
  int largest_sample_order(bool) const override { return kMaxAutoOrderIsotropic; }
  // theta_h = (pi/2) ((k+1/2)/90)^2 is the t^2 warp with centred nodes; theta_d and phi_d are centred too: a
  // lookup at a node returns that node's value, so a lobe is fitted to the table's values as they are.
  std::optional<HalfAngleNodes> own_half_angle_nodes() const override {
    return HalfAngleNodes{kMerlThetaHalfRes, 1, kMerlThetaDiffRes, kMerlPhiDiffRes, true};
  }
  std::optional<OwnHeldOut> own_held_out(const HeldOutRequest& r) const override {
    if (r.lights_and_cameras) return std::nullopt;  // the scene's pairs, evaluated by lookup
    std::vector<std::int64_t> bins;
    OwnHeldOut out;
    out.pairs = draw_merl_held_out(r, table(), bins);
    out.training = without(bins);
    return out;
  }
  // The source whose table has the bins `held_out` (MerlBin::flat) missing.
  std::unique_ptr<BrdfSource> without(const std::vector<std::int64_t>& held_out) const {
    auto t = std::make_shared<MerlTable>(table());
    for (const std::int64_t flat : held_out) {
      if (flat < 0 || flat >= kMerlSamplesPerChannel) throw ArgumentError("merl_source_without: bin " + std::to_string(flat) + " out of range");
      for (int c = 0; c < 3; ++c) {
        double& v = t->f[static_cast<size_t>(c * kMerlSamplesPerChannel + flat)];
        if (!std::isnan(v)) ++t->missing[static_cast<size_t>(c)];
        v = std::numeric_limits<double>::quiet_NaN();
      }
    }
    return std::make_unique<MerlSource>(std::move(t), text_);
  }

 private:
  MerlModel model_;
  std::string text_;
};

class SampleCsvSource final : public BrdfSource, public SampleFitHolder {
 public:
  SampleCsvSource(BrdfSamples s, SampleFitOptions fo, bool tikhonov_auto, std::string text)
      : samples_(std::move(s)), fit_options_(fo), tikhonov_auto_(tikhonov_auto), text_(std::move(text)) {}
  std::string spec() const override { return text_; }
  int channels() const override { return samples_.channels; }
  // How the columns were read, when not the library's own f in 1/sr at theta_i,phi_i,theta_r,phi_r.
  std::vector<std::string> notes() const override {
    const BrdfSamples& s = samples_;
    if (s.layout == AngleLayout::Library && s.quantity == ValueQuantity::Brdf) return {};
    std::string n = "columns '" + s.header + "' read as ";
    if (s.layout == AngleLayout::SunViewRelative) n += "w_i = (sza, 0), w_r = (vza, raa) (raa = 0: the sun's side, hot spot at vza = sza)";
    else if (s.layout == AngleLayout::SunViewAzimuths) n += "w_i = (sza, 90 - saa), w_r = (vza, 90 - vaa) (compass azimuths; x east, y north)";
    else n += "theta_i,phi_i,theta_r,phi_r";
    n += s.quantity == ValueQuantity::Brf ? ", values BRF (f = BRF/pi, declared by " + s.quantity_declared_by + ")" : ", values f in 1/sr";
    n += std::string(", angles in ") + (s.radians ? "radians" : "degrees");
    return {n};
  }
  Eigen::MatrixXd eval(const RowMatrix3d&, const RowMatrix3d&) const override {
    throw ArgumentError("SOURCE '" + text_ + "' holds scattered samples, which have no value at arbitrary directions: " +
                        "fit them first (icobrdf fit " + text_ + " ... -o SPECTRUM.h5) and evaluate the spectrum");
  }
  Spectrum fit(const ProjectionContext& ctx, const FitOptions& o) const override {
    check_fit_options(o, "samples SOURCE '" + text_ + "'");
    SampleFitPlan plan;
    plan.options = fit_options_;
    plan.options.order = std::max(o.order, 0);
    plan.options.isotropic = o.isotropic;
    plan.options.progress = o.progress;
    plan.options.kernels = &default_dense_kernels();
    plan.options.split = sample_fit_split(o);  // under mpirun: each rank passes over its part of the samples
    plan.choose_order = o.order == kChooseOrder;
    plan.choose_class = plan.choose_order && !o.isotropic;  // no --isotropic: isotropic or general by CV too
    // An automatic order comes with an automatic lambda unless one was given.
    plan.choose_tikhonov = tikhonov_auto_ || (plan.choose_order && !tikhonov_given());
    const CheckedSampleFit c = fit_samples_checked(samples_.wi, samples_.wr, samples_.values, samples_.weights, plan);
    store(c);
    // The kernel-driven baseline on the same samples and folds (three weights: no split needed).
    store_kernels(fit_kernel_weights(samples_.wi, samples_.wr, samples_.values, samples_.weights, {}, plan.folds));
    Spectrum s = spectrum_of(c, text_, fit_options_.tikhonov_power);
    finish(s, o, ctx);
    return s;
  }

  const BrdfSamples& samples() const { return samples_; }

  bool values_only_at_samples() const override { return true; }
  bool judged_at_own_samples() const override { return true; }
  int largest_sample_order(bool isotropic) const override { return largest_order_of(samples_.wi.rows(), isotropic); }
  std::optional<OwnHeldOut> own_held_out(const HeldOutRequest& r) const override {
    std::vector<bool> held;
    OwnHeldOut out;
    out.pairs = draw_samples_held_out(r, samples_, text_, held);
    out.training = without(held);
    return out;
  }
  // The same source on the samples whose `held_out` entry is false.
  std::unique_ptr<BrdfSource> without(const std::vector<bool>& held_out) const {
    BrdfSamples kept = samples_;
    Eigen::Index n = 0;
    for (Eigen::Index k = 0; k < samples_.wi.rows(); ++k) {
      if (held_out[static_cast<size_t>(k)]) continue;
      kept.wi.row(n) = samples_.wi.row(k);
      kept.wr.row(n) = samples_.wr.row(k);
      kept.values.row(n) = samples_.values.row(k);
      kept.weights(n) = samples_.weights(k);
      kept.lines[static_cast<size_t>(n)] = samples_.lines[static_cast<size_t>(k)];
      ++n;
    }
    if (n == 0) throw ArgumentError("samples SOURCE '" + quoted_text(text_) + "': no sample is left to fit once the held-out ones are set aside");
    kept.wi.conservativeResize(n, 3);
    kept.wr.conservativeResize(n, 3);
    kept.values.conservativeResize(n, Eigen::NoChange);
    kept.weights.conservativeResize(n);
    kept.lines.resize(static_cast<size_t>(n));
    return std::make_unique<SampleCsvSource>(std::move(kept), fit_options_, tikhonov_auto_, text_);
  }

 private:
  bool tikhonov_given() const { return fit_options_.tikhonov > 0.0; }
  BrdfSamples samples_;
  SampleFitOptions fit_options_;
  bool tikhonov_auto_ = false;
  std::string text_;
};

class ScatmechSource final : public BrdfSource {
 public:
  ScatmechSource(Spectrum s, const ScatmechCoefficients& file, std::string text) : s_(std::move(s)), text_(std::move(text)) {
    s_.source = text_;
    if (file.polarized_rows > 0)
      notes_.push_back(std::to_string(file.polarized_rows) + " row(s) of polarized Mueller elements (i, j) != (1, 1) ignored: the BRDF is the unpolarized element's " +
                       std::to_string(file.unpolarized_rows) + " row(s)");
    if (file.k_differs_rows > 0)
      notes_.push_back(std::to_string(file.k_differs_rows) + " unpolarized row(s) with k != l: the azimuthal order is taken from l, as SCATMECH evaluates");
  }
  std::vector<std::string> notes() const override { return notes_; }
  std::string spec() const override { return text_; }
  int channels() const override { return 1; }
  Eigen::MatrixXd eval(const RowMatrix3d& wi, const RowMatrix3d& wr) const override {
    Eigen::MatrixXd out(wi.rows(), 1);
    out.col(0) = evaluate_coefficients(s_.channels[0], s_.order, wi, wr);
    return out;
  }
  // Exact re-expansion: truncation to a lower order or zero padding to a higher one.
  Spectrum fit(const ProjectionContext& ctx, const FitOptions& o) const override {
    check_fit_options(o, "SCATMECH SOURCE '" + text_ + "'");
    Spectrum s = s_;
    const int m_new = hemisphere_basis_count(o.order), k = std::min(m_new, s_.modes());
    Eigen::MatrixXd r = Eigen::MatrixXd::Zero(m_new, m_new);
    r.topLeftCorner(k, k) = s_.channels[0].topLeftCorner(k, k);
    s.channels[0] = r;
    s.order = o.order;
    finish(s, o, ctx);
    return s;
  }

 private:
  Spectrum s_;
  std::string text_;
  std::vector<std::string> notes_;
};

// f of an RGL material (icobrdf/io/rgl_bsdf.hpp): evaluated as Mitsuba's measured BSDF does, divided by cos(theta_r);
// fitted like an analytic model (its values sampled on the context's grid, icobrdf/core/fit/spectral_fit.hpp fit_model).
class RglSource final : public BrdfSource {
 public:
  RglSource(std::shared_ptr<const RglBsdf> b, std::vector<double> lambdas, std::vector<std::string> names, std::string text)
      : model_(std::move(b), std::move(lambdas), text), names_(std::move(names)), text_(std::move(text)) {}
  std::string spec() const override { return text_; }
  int channels() const override { return model_.channels(); }
  std::vector<std::string> channel_names() const override { return names_; }
  std::vector<std::string> notes() const override {
    return {"measured data (not reciprocal): w_i is the illumination direction, the one that selects the measured slice"};
  }
  Eigen::MatrixXd eval(const RowMatrix3d& wi, const RowMatrix3d& wr) const override {
    Eigen::MatrixXd out(wi.rows(), model_.channels());
    model_.eval(wi, wr, out);
    return out;
  }
  Spectrum fit(const ProjectionContext& ctx, const FitOptions& o) const override {
    if (channels() != 1 && channels() != 3)
      throw UnsupportedError("RGL SOURCE '" + quoted_text(text_) + "' has " + std::to_string(channels()) +
                             " wavelengths; a spectrum holds 1 or 3 channels: choose them with " + quoted_text(split_options(text_).path) +
                             "#lambda=NM or #lambda=NM/NM/NM");
    Spectrum s = fit_model(model_, ctx, o);
    s.source = text_;
    s.channel_names = names_;
    return s;
  }
  bool slow_to_evaluate() const override { return true; }  // an inverse warp of the vndf per pair
  std::optional<Eigen::MatrixXd> noise_sigma_at(const RowMatrix3d& wi, const RowMatrix3d& wr) const override {
    Eigen::MatrixXd out(wi.rows(), model_.channels());
    model_.noise_sigma(wi, wr, out);
    return out;
  }

 private:
  RglModel model_;
  std::vector<std::string> names_;
  std::string text_;
};

std::string wavelength_name(double nm) {
  std::string t = format_parameter(nm);
  return t + "nm";
}

std::unique_ptr<BrdfSource> open_rgl(const std::string& text, const std::string& body) {
  const Options op = split_options(body);
  require_file(op.path, text);
  std::vector<double> lambdas;
  bool chosen = false;
  for (const auto& [k, v] : op.kv) {
    if (k == "lambda") {
      chosen = true;
      std::stringstream ss(v);
      std::string item;
      while (std::getline(ss, item, '/')) lambdas.push_back(number_option(text, k, item));
      if (lambdas.empty() || lambdas.size() > 3 || v.back() == '/')
        throw ArgumentError("SOURCE '" + quoted_text(text) + "': option lambda expected 1 to 3 wavelengths in nm separated by '/', found '" + quoted_text(v) + "'");
    } else {
      throw ArgumentError("SOURCE '" + quoted_text(text) + "': unknown RGL option '" + quoted_text(k) + "', expected lambda=NM[/NM/NM] (spectral files)");
    }
  }
  auto b = std::make_shared<const RglBsdf>(read_rgl_bsdf(op.path));
  std::vector<std::string> names;
  if (!b->spectral) {
    if (chosen)
      throw ArgumentError("SOURCE '" + quoted_text(text) + "': option lambda applies to spectral RGL files; " + op.path + " holds RGB values");
    lambdas = {0, 1, 2};
    names = {"r", "g", "b"};
  } else {
    if (!chosen) lambdas = b->wavelengths;
    for (double l : lambdas) {
      if (l < b->wavelengths.front() || l > b->wavelengths.back())
        throw ArgumentError("SOURCE '" + quoted_text(text) + "': wavelength " + format_parameter(l) + " nm outside the file's range " +
                            format_parameter(b->wavelengths.front()) + " .. " + format_parameter(b->wavelengths.back()) + " nm");
      names.push_back(wavelength_name(l));
    }
  }
  return std::make_unique<RglSource>(std::move(b), std::move(lambdas), std::move(names), text);
}

// The fit options of sample SOURCEs (CSV, CURET): true when `k` is one of them.
bool sample_fit_option(const std::string& text, const std::string& k, const std::string& v, SampleFitOptions& fo, bool& tikhonov_auto) {
  if (k == "tikhonov" && v == "auto") tikhonov_auto = true;
  else if (k == "tikhonov") fo.tikhonov = number_option(text, k, v);
  else if (k == "power") fo.tikhonov_power = number_option(text, k, v);
  else if (k == "rank-tol") fo.rank_tolerance = number_option(text, k, v);
  else return false;
  if (fo.tikhonov < 0 || fo.tikhonov_power < 0)
    throw ArgumentError("SOURCE '" + quoted_text(text) + "': tikhonov and power must be >= 0");
  return true;
}

// columns=NAME/NAME/...: the names in order, lower-case (as the CSV reader gives the header's).
std::vector<std::string> column_names(const std::string& text, const std::string& v) {
  std::vector<std::string> names;
  std::stringstream ss(v);
  std::string item;
  while (std::getline(ss, item, '/')) {
    std::transform(item.begin(), item.end(), item.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (item.empty()) throw ArgumentError("SOURCE '" + quoted_text(text) + "': columns= has an empty name, expected NAME/NAME/...");
    names.push_back(item);
  }
  if (names.empty()) throw ArgumentError("SOURCE '" + quoted_text(text) + "': columns= names no column, expected NAME/NAME/...");
  return names;
}

std::unique_ptr<BrdfSource> open_samples(const std::string& text, const std::string& body) {
  const Options op = split_options(body);
  require_file(op.path, text);
  SampleCsvOptions co;
  SampleFitOptions fo;
  bool tikhonov_auto = false;
  for (const auto& [k, v] : op.kv) {
    if (k == "radians" && v.empty()) co.radians = true;
    else if (k == "strict" && v.empty()) co.strict = true;
    else if (k == "values") co.columns.values = v;
    else if (k == "columns") co.columns.names = column_names(text, v);
    else if (!sample_fit_option(text, k, v, fo, tikhonov_auto))
      throw ArgumentError("SOURCE '" + quoted_text(text) + "': unknown samples option '" + k + (v.empty() ? "" : "=" + v) +
                          "', expected radians, strict, values=brf|brdf, columns=NAME/NAME/..., tikhonov=LAMBDA|auto, power=P or rank-tol=T");
  }
  return std::make_unique<SampleCsvSource>(read_sample_csv(op.path, co), fo, tikhonov_auto, text);
}

// curet:ABRDF.DAT#sample=N[,table=TABLE.TXT][,fit options] (icobrdf/io/curet.hpp): one sample of the database.
std::unique_ptr<BrdfSource> open_curet(const std::string& text, const std::string& body) {
  const Options op = split_options(body);
  require_file(op.path, text);
  std::string table = curet_table_beside(op.path);
  int sample = -1;
  SampleFitOptions fo;
  bool tikhonov_auto = false;
  for (const auto& [k, v] : op.kv) {
    if (k == "sample") {
      const double n = number_option(text, k, v);
      if (!(n >= 1 && n == std::floor(n) && n < 1e9))
        throw ArgumentError("SOURCE '" + quoted_text(text) + "': option sample expected a sample number >= 1, found '" + quoted_text(v) + "'");
      sample = static_cast<int>(n);
    } else if (k == "table" && !v.empty()) {
      table = v;
    } else if (!sample_fit_option(text, k, v, fo, tikhonov_auto)) {
      throw ArgumentError("SOURCE '" + quoted_text(text) + "': unknown CURET option '" + k + (v.empty() ? "" : "=" + v) +
                          "', expected sample=N, table=FILE, tikhonov=LAMBDA|auto, power=P or rank-tol=T");
    }
  }
  if (sample < 0)
    throw ArgumentError("SOURCE '" + quoted_text(text) + "': a CURET SOURCE names its sample, e.g. " + quoted_text(op.path) + "#sample=12");
  require_file(table, text + " (the geometry table; give another with table=FILE)");
  return std::make_unique<SampleCsvSource>(curet_samples(read_curet(op.path, table), sample), fo, tikhonov_auto, text);
}

std::unique_ptr<BrdfSource> open_scatmech(const std::string& text, const std::string& body) {
  const Options op = split_options(body);
  require_file(op.path, text);
  ScatmechImportOptions io;
  for (const auto& [k, v] : op.kv) {
    if (k == "lambda") io.wavelength_um = number_option(text, k, v);
    else if (k == "scale") io.scale = number_option(text, k, v);
    else
      throw ArgumentError("SOURCE '" + quoted_text(text) + "': unknown SCATMECH option '" + quoted_text(k) + "', expected lambda=UM or scale=R");
  }
  if (io.wavelength_um != -1.0 && !(io.wavelength_um > 0))
    throw ArgumentError("SOURCE '" + quoted_text(text) + "': lambda must be > 0 (micrometres)");
  const ScatmechCoefficients file = read_scatmech_coefficients(op.path);
  return std::make_unique<ScatmechSource>(scatmech_to_spectrum(file, io), file, text);
}

}  // namespace

std::unique_ptr<BrdfSource> open_measured_source(const std::string& text) {
  const bool merl_prefix = starts_with(text, "merl:");
  if (merl_prefix || ends_with(text, ".binary")) {
    const std::string path = merl_prefix ? text.substr(5) : text;
    return std::make_unique<MerlSource>(std::make_shared<const MerlTable>(read_merl(path)), text);
  }
  if (starts_with(text, "rgl:")) return open_rgl(text, text.substr(4));
  if (starts_with(text, "scatmech:")) return open_scatmech(text, text.substr(9));
  if (starts_with(text, "samples:")) return open_samples(text, text.substr(8));
  if (starts_with(text, "curet:")) return open_curet(text, text.substr(6));
  const std::string path = split_options(text).path;
  if (ends_with(path, ".bsdf")) return open_rgl(text, text);
  if (ends_with(path, ".zernike.csv")) return open_scatmech(text, text);
  // Other files by content: a SCATMECH coefficient file whatever its name (NIST's *.coeff.csv, *.coef.csv,
  // *.txt), else a .csv is BRDF samples.
  if (looks_like_scatmech_coefficients(path)) return open_scatmech(text, text);
  if (ends_with(path, ".csv")) return open_samples(text, text);
  return nullptr;
}

std::unique_ptr<BrdfSource> open_sample_arrays(BrdfSamples samples, const SampleArrayFit& options, const std::string& spec) {
  const SampleFitOptions& fo = options.fit;
  if (!(std::isfinite(fo.tikhonov) && fo.tikhonov >= 0 && std::isfinite(fo.tikhonov_power) && fo.tikhonov_power >= 0))
    throw ArgumentError("samples '" + quoted_text(spec) + "': tikhonov and power must be finite and >= 0, found " +
                        std::to_string(fo.tikhonov) + " and " + std::to_string(fo.tikhonov_power));
  if (!std::isfinite(fo.rank_tolerance))
    throw ArgumentError("samples '" + quoted_text(spec) + "': rank_tol must be finite (< 0: the default)");
  return std::make_unique<SampleCsvSource>(std::move(samples), fo, options.tikhonov_auto, spec);
}

const SampleFitResult* last_sample_fit(const BrdfSource& source) {
  const CheckedSampleFit* c = last_checked_sample_fit(source);
  return c ? &c->fit : nullptr;
}

const CheckedSampleFit* last_checked_sample_fit(const BrdfSource& source) {
  if (const auto* h = dynamic_cast<const SampleFitHolder*>(&source)) return h->last();
  return nullptr;
}

const KernelFit* last_kernel_fit(const BrdfSource& source) {
  if (const auto* c = dynamic_cast<const SampleCsvSource*>(&source)) return c->last_kernels();
  return nullptr;
}

const BrdfSamples* samples_of(const BrdfSource& source) {
  if (const auto* c = dynamic_cast<const SampleCsvSource*>(&source)) return &c->samples();
  return nullptr;
}

std::unique_ptr<BrdfSource> samples_source_without(const BrdfSource& source, const std::vector<bool>& held_out) {
  const auto* c = dynamic_cast<const SampleCsvSource*>(&source);
  if (!c) throw ArgumentError("SOURCE '" + quoted_text(source.spec()) + "' does not hold scattered samples");
  if (held_out.size() != static_cast<size_t>(c->samples().wi.rows()))
    throw ArgumentError("samples_source_without: " + std::to_string(held_out.size()) + " flags for " +
                        std::to_string(c->samples().wi.rows()) + " samples");
  return c->without(held_out);
}

std::unique_ptr<BrdfSource> merl_source_without(const BrdfSource& source, const std::vector<std::int64_t>& held_out) {
  const auto* m = dynamic_cast<const MerlSource*>(&source);
  if (!m) throw ArgumentError("SOURCE '" + quoted_text(source.spec()) + "' is not a MERL table");
  return m->without(held_out);
}

bool chooses_order(const BrdfSource& source) { return dynamic_cast<const SampleCsvSource*>(&source) != nullptr; }

const MerlTable* merl_table_of(const BrdfSource& source) {
  if (const auto* m = dynamic_cast<const MerlSource*>(&source)) return &m->table();
  return nullptr;
}

std::int64_t merl_missing_samples(const BrdfSource& source) {
  const MerlTable* table = merl_table_of(source);
  return table ? table->missing_total() : -1;
}

}  // namespace icobrdf
