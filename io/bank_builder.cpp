#include "io/bank_builder.hpp"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <numeric>
#include <optional>
#include <random>

#include "core/direction.hpp"
#include "core/error.hpp"
#include "core/hemisphere_basis.hpp"
#include "core/helmholtz_modes.hpp"
#include "core/isotropic_modes.hpp"
#include "io/bank_file.hpp"
#include "io/brdf_source.hpp"
#include "mesh/tessellation.hpp"

namespace icobrdf {
namespace {

// Resume-file checkpoints: time between two rewrites of OUTPUT.partial over the duration of the last rewrite
// (at most 1/(1 + ratio) = 9% of a build is spent on them; a SIGKILL loses at most ratio x that duration).
constexpr double kCheckpointRatio = 10.0;

std::string fmt_double(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", x);
  return buf;
}

// Key of a material: everything that changes its result.
std::string material_key(const Scene& s, const SceneMaterial& m) {
  std::string t = "icobrdf-bank-material-v1|" + m.source + "|" + fmt_double(m.target) + "|" + m.isotropic + "|" +
                  std::to_string(m.order) + "|" + std::to_string(m.level) + "|" + m.metric + "|" + fmt_double(m.incidence_min) + "|" +
                  fmt_double(m.incidence_max) + "|" + (m.prune ? "prune" : "keep");
  for (const auto& d : m.lights) t += "|L" + fmt_double(d.first) + "," + fmt_double(d.second);
  for (const auto& d : m.cameras) t += "|C" + fmt_double(d.first) + "," + fmt_double(d.second);
  t += "|bank|" + std::to_string(s.level) + "|" + std::to_string(s.order_max) + "|" + s.sampling + "|" +
       std::to_string(s.holdout_pairs) + "|" + (s.store_lut ? "lut" : "nolut") + (s.lut_float32 ? "32" : "64");
  for (int l : s.levels) t += "|" + std::to_string(l);
  return fnv1a_hex(t);
}

struct HeldOut {
  RowMatrix3d wi, wr;
  Eigen::MatrixXd f;  // pairs x channels
};

HeldOut held_out_pairs(const Scene& s, const SceneMaterial& m, const BrdfSource& src) {
  HeldOut h;
  if (!m.lights.empty()) {
    const auto n = static_cast<Eigen::Index>(m.lights.size() * m.cameras.size());
    h.wi.resize(n, 3);
    h.wr.resize(n, 3);
    Eigen::Index k = 0;
    for (const auto& l : m.lights)
      for (const auto& c : m.cameras) {
        h.wi.row(k) = direction_from_angles(l.first * M_PI / 180, l.second * M_PI / 180).transpose();
        h.wr.row(k++) = direction_from_angles(c.first * M_PI / 180, c.second * M_PI / 180).transpose();
      }
  } else {
    // Uniform in solid angle: z = cos(theta) uniform. Seeded by the material's name: reproducible.
    std::mt19937_64 rng(std::stoull(fnv1a_hex("holdout|" + m.name).substr(0, 15), nullptr, 16));
    const double zlo = std::cos(m.incidence_max * M_PI / 180), zhi = std::cos(m.incidence_min * M_PI / 180);
    h.wi.resize(s.holdout_pairs, 3);
    h.wr.resize(s.holdout_pairs, 3);
    for (int k = 0; k < s.holdout_pairs; ++k) {
      h.wi.row(k) = uniform_direction(rng, zlo, zhi).transpose();
      h.wr.row(k) = uniform_direction(rng).transpose();
    }
  }
  h.f = src.eval(h.wi, h.wr);
  for (Eigen::Index k = 0; k < h.f.size(); ++k)
    if (!std::isfinite(h.f.data()[k])) throw InputError("source '" + src.spec() + "' gives a non-finite value at a held-out pair");
  return h;
}

// Errors of a spectrum (channels of C, order n = leading block) against the held-out values, with the
// basis values at the pairs precomputed to the largest order needed.
// Errors are measured on w f with w = 1 (metric "f") or w = cos(theta_i) cos(theta_r) (metric "cosine":
// the projected solid angle, i.e. the reflected radiance per unit irradiance as a renderer integrates it,
// which does not let the grazing growth of microfacet BRDFs dominate).
struct Evaluator {
  Eigen::MatrixXd ki, kr;  // pairs x M(max order)
  const HeldOut* h = nullptr;
  Eigen::VectorXd w;       // pairs
  double ref_norm = 0.0, ref_max = 0.0;

  Evaluator(const HeldOut& held, int max_order, const std::string& metric) : h(&held) {
    ki = hemisphere_basis_matrix(max_order, held.wi);
    kr = hemisphere_basis_matrix(max_order, held.wr);
    w = metric == "cosine" ? Eigen::VectorXd(held.wi.col(2).cwiseProduct(held.wr.col(2))) : Eigen::VectorXd::Ones(held.wi.rows());
    const Eigen::MatrixXd wf = w.asDiagonal() * held.f;
    ref_norm = wf.norm();
    ref_max = wf.cwiseAbs().maxCoeff();
  }
  std::pair<double, double> errors(const std::vector<Eigen::MatrixXd>& c, int order) const {
    const int m = hemisphere_basis_count(order);
    double sq = 0.0, mx = 0.0;
    for (size_t ch = 0; ch < c.size(); ++ch) {
      const Eigen::VectorXd fit = ((ki.leftCols(m) * c[ch].topLeftCorner(m, m)).array() * kr.leftCols(m).array()).rowwise().sum();
      const Eigen::VectorXd d = w.cwiseProduct(fit - h->f.col(static_cast<Eigen::Index>(ch)));
      sq += d.squaredNorm();
      mx = std::max(mx, d.cwiseAbs().maxCoeff());
    }
    return {ref_norm > 0 ? std::sqrt(sq) / ref_norm : std::sqrt(sq), ref_max > 0 ? mx / ref_max : mx};
  }
};

std::vector<Eigen::MatrixXd> truncate(const std::vector<Eigen::MatrixXd>& c, int order) {
  const int m = hemisphere_basis_count(order);
  std::vector<Eigen::MatrixXd> out;
  for (const auto& x : c) out.push_back(x.topLeftCorner(m, m));
  return out;
}

class Builder {
 public:
  explicit Builder(const Scene& s) : s_(s) {}

  // Fitting grids: LUT rows and B sampled with the same rule (exact for BRDFs in the span): one point per
  // cell for "centre", a degree-2 rule for "average".
  std::shared_ptr<const Grid> grid(int level) {
    auto& g = grids_[level];
    if (!g)
      g = std::make_shared<const Grid>(build_fitting_grid(level, "equal-area", s_.sampling != "average"));
    return g;
  }
  const ProjectionContext& context(int level, int order) {
    auto& c = contexts_[{level, order}];
    if (!c) c = std::make_unique<ProjectionContext>(make_projection_context(grid(level), order));
    return *c;
  }
  // Operators on the bank's own grid (the stored /grid with its full cubature).
  const Grid& bank_grid() {
    if (!bank_grid_) bank_grid_ = std::make_shared<const Grid>(build_equal_area_grid(s_.level));
    return *bank_grid_;
  }
  // B and G at any order (reconstruction F = B C B^T needs only B); P only where the bank grid supports the
  // order (core/discrete_basis.hpp), else it is left out of the file.
  struct BankOperators {
    DiscreteBasis basis;
    std::optional<ProjectionOperator> projection;
  };
  const BankOperators& bank_context(int order) {
    auto& c = bank_contexts_[order];
    if (!c) {
      c = std::make_unique<BankOperators>();
      c->basis = build_discrete_basis(bank_grid(), order);
      if (c->basis.gram_error <= kDefaultGramTolerance) c->projection = make_projection(c->basis);
    }
    return *c;
  }
  int supported_order(int level) {
    auto it = supported_.find(level);
    if (it != supported_.end()) return it->second;
    const auto b = build_discrete_basis(*grid(level), s_.order_max);
    return supported_[level] = largest_supported_order(b);
  }

  MaterialRecord fit_material(const SceneMaterial& m, MaterialReport& rep, const std::function<void(const std::string&)>& say) {
    const auto t0 = std::chrono::steady_clock::now();
    const auto src = open_source(m.source);
    rep.source = src->spec();
    rep.target = m.target;
    FitOptions o;
    o.sampling = LutSampling::CellAverage;  // over the fitting grid's own rule (one point per cell for "centre")
    std::vector<int> levels = m.level >= 0 ? std::vector<int>{m.level} : s_.levels;
    Spectrum best;
    if (src->has_delta()) {
      // No pointwise error for a delta: fit at the given (or largest allowed) order on the first level that
      // supports it.
      rep.measured = false;
      int level = -1, order = -1;
      for (int l : levels) {
        const int top = std::min(s_.order_max, supported_order(l));
        if (m.order >= 0 ? top >= m.order : top >= 0) {
          level = l;
          order = m.order >= 0 ? m.order : top;
          break;
        }
      }
      if (level < 0)
        throw UnsupportedError("order " + std::to_string(m.order) + " is not supported by any of the levels tried (up to " +
                               std::to_string(levels.back()) + ")");
      o.order = order;
      o.isotropic = m.isotropic != "false";
      best = src->fit(context(level, order), o);
      rep.level = level;
      rep.order = order;
      rep.isotropic = o.isotropic;
      rep.anisotropy = best.anisotropy_fraction;
      rep.error_l2 = rep.error_max = std::nan("");
    } else {
      const HeldOut held = held_out_pairs(s_, m, *src);
      const int max_order = m.order >= 0 ? m.order : s_.order_max;
      const Evaluator ev(held, max_order, m.metric);
      const bool force_iso = m.isotropic == "true";
      double best_err = INFINITY;
      std::string best_where;
      bool met = false;
      for (int level : levels) {
        const int top = std::min(max_order, supported_order(level));
        if (top < 0 || (m.order >= 0 && top < m.order)) continue;
        o.order = top;
        o.isotropic = force_iso;
        const Spectrum s = src->fit(context(level, top), o);
        const int first = m.order >= 0 ? m.order : 0;
        for (int n = first; n <= top; ++n) {
          const auto [l2, mx] = ev.errors(truncate(s.channels, n), n);
          if (l2 < best_err) {
            best_err = l2;
            best_where = "level " + std::to_string(level) + " order " + std::to_string(n);
          }
          if (l2 > m.target) continue;
          // Fit at exactly this order and verify (at n = top that fit is the one just made: reused).
          o.order = n;
          Spectrum exact = n == top ? s : src->fit(context(level, n), o);
          const auto [l2e, mxe] = ev.errors(exact.channels, n);
          if (l2e > m.target) continue;
          rep.anisotropy = exact.anisotropy_fraction;
          rep.level = level;
          rep.order = n;
          rep.error_l2 = l2e;
          rep.error_max = mxe;
          // "auto": isotropic when the isotropic projection of the same fit still meets the target.
          if (m.isotropic == "auto") {
            std::vector<Eigen::MatrixXd> iso;
            for (const auto& c : exact.channels) iso.push_back(isotropic_part(c, n));
            const auto [l2i, mxi] = ev.errors(iso, n);
            if (l2i <= m.target) {
              exact.channels = std::move(iso);
              exact.isotropic = true;
              rep.error_l2 = l2i;
              rep.error_max = mxi;
            }
            say(m.name + ": anisotropic energy fraction " + fmt_double(exact.anisotropy_fraction) + ", isotropic error " +
                fmt_double(l2i) + " -> " + (exact.isotropic ? "isotropic" : "anisotropic"));
          }
          best = std::move(exact);
          met = true;
          break;
        }
        say(m.name + ": level " + std::to_string(level) + " up to order " + std::to_string(top) + (met ? ": target met" : ": target not met"));
        if (met) break;
      }
      if (!met) {
        char buf[256];
        std::snprintf(buf, sizeof buf, "target %.3g not met: best relative L2 error %.3g at %s (order_max %d, levels tried up to %d)",
                      m.target, best_err, best_where.c_str(), s_.order_max, levels.back());
        throw UnsupportedError(buf);
      }
      rep.isotropic = best.isotropic;
      if (m.prune) prune(best, ev, m.target, rep);
    }
    MaterialRecord rec;
    rec.name = m.name;
    rec.spectrum = best;
    rec.spectrum.source = rep.source;
    if (rec.spectrum.isotropic) {
      const auto modes = isotropic_modes(rec.spectrum.order);
      rec.ibsss.resize(rec.spectrum.channel_count(), static_cast<Eigen::Index>(modes.size()));
      for (int c = 0; c < rec.spectrum.channel_count(); ++c) rec.ibsss.row(c) = ibsss_from_coefficients(rec.spectrum.channels[c]).transpose();
      rec.ibsss_indices.resize(static_cast<Eigen::Index>(modes.size()), 3);
      for (size_t k = 0; k < modes.size(); ++k) rec.ibsss_indices.row(static_cast<Eigen::Index>(k)) << modes[k].n, modes[k].m, modes[k].l;
    }
    if (rep.total == 0) rep.total = rep.kept = coefficient_count(rec.spectrum);
    rep.bytes = static_cast<long long>(rep.kept) * (8LL * rec.spectrum.channel_count() + (rec.spectrum.isotropic ? 12 : 16));
    if (s_.store_lut) {
      const auto& ctx = bank_context(rec.spectrum.order);
      for (const auto& c : rec.spectrum.channels) rec.lut.push_back(reconstruct_lut(ctx.basis, c));
      // The LUT lives on the bank grid; the fitting level stays in the figure fit_level.
      rec.spectrum.level = s_.level;
      rec.spectrum.grid_kind = "equal-area";
      rec.lut_float32 = s_.lut_float32;
    }
    rep.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    rec.figures = {{"target", rep.target},         {"error_l2", rep.error_l2},     {"error_max", rep.error_max},
                   {"kept_coefficients", rep.kept}, {"total_coefficients", rep.total}, {"bytes", static_cast<double>(rep.bytes)},
                   {"seconds", rep.seconds},        {"fit_level", rep.level}};
    rec.labels = {{"key", rep.key}, {"error_measured", rep.measured ? "yes" : "no (delta BRDF)"}};
    return rec;
  }

  static int coefficient_count(const Spectrum& s) {
    return s.isotropic ? isotropic_mode_count(s.order) : static_cast<int>(helmholtz_mode_count(s.order));
  }

  // Drops coefficients smallest first (by their largest magnitude over the channels) while the error holds.
  void prune(Spectrum& s, const Evaluator& ev, double target, MaterialReport& rep) {
    const int ch = s.channel_count();
    std::vector<Eigen::VectorXd> v(static_cast<size_t>(ch));
    for (int c = 0; c < ch; ++c) v[c] = s.isotropic ? ibsss_from_coefficients(s.channels[c]) : bsss_from_coefficients(s.channels[c]);
    const Eigen::Index total = v[0].size();
    Eigen::VectorXd mag = Eigen::VectorXd::Zero(total);
    for (int c = 0; c < ch; ++c) mag = mag.cwiseMax(v[c].cwiseAbs());
    std::vector<Eigen::Index> order(static_cast<size_t>(total));
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(), [&](Eigen::Index a, Eigen::Index b) { return mag[a] > mag[b]; });
    auto with_kept = [&](Eigen::Index kept) {
      std::vector<Eigen::MatrixXd> out;
      for (int c = 0; c < ch; ++c) {
        Eigen::VectorXd w = Eigen::VectorXd::Zero(total);
        for (Eigen::Index k = 0; k < kept; ++k) w[order[static_cast<size_t>(k)]] = v[c][order[static_cast<size_t>(k)]];
        out.push_back(s.isotropic ? coefficients_from_ibsss(s.order, w) : coefficients_from_bsss(w));
      }
      return out;
    };
    // Smallest kept count meeting the target, by bisection on the (nearly monotone) error; the result is
    // verified, and the full spectrum (which meets the target) is the fallback.
    Eigen::Index lo = 0, hi = total;
    while (lo < hi) {
      const Eigen::Index mid = (lo + hi) / 2;
      if (ev.errors(with_kept(mid), s.order).first <= target) hi = mid;
      else lo = mid + 1;
    }
    auto pruned = with_kept(hi);
    const auto [l2, mx] = ev.errors(pruned, s.order);
    rep.total = static_cast<int>(total);
    if (l2 <= target) {
      s.channels = std::move(pruned);
      rep.kept = static_cast<int>(hi);
      rep.error_l2 = l2;
      rep.error_max = mx;
    } else {
      rep.kept = static_cast<int>(total);
    }
  }

  void add_basis(BankContents& bank, int order) {
    const auto& ctx = bank_context(order);
    const std::string p = std::to_string(order);
    bank.basis.push_back(BasisArray::matrix(p + "/B", ctx.basis.B, "1/sqrt(sr)", "cells x modes: cell averages of K_j (ANSI order)"));
    bank.basis.push_back(BasisArray::matrix(p + "/G", ctx.basis.G, "1", "modes x modes: Gram matrix B^T W B"));
    if (ctx.projection)
      bank.basis.push_back(BasisArray::matrix(p + "/P", ctx.projection->P, "sr^(1/2)",
                                              "cells x modes: least-squares projection W B G^-1; C = P^T F P"));
    // Smoothing S = B diag(w) P^T is stored in this factored form (S itself is cells x cells); the bank's
    // spectra are plain truncations, so w = 1 (core/lowpass_filter.hpp gives other filters' weights).
    const Eigen::VectorXd w = mode_weights(LowPassFilter{}, order);
    bank.basis.push_back(BasisArray::matrix(p + "/filter_weights", Eigen::MatrixXd(w.transpose()), "1",
                                            "1 x modes: low-pass weights w of the smoothing S = B diag(w) P^T (plain truncation)"));
    BasisArray idx;
    idx.path = p + "/indices";
    const int m = hemisphere_basis_count(order);
    idx.shape = {static_cast<std::uint64_t>(m), 2};
    for (int j = 0; j < m; ++j) {
      idx.indices.push_back(ansi_to_nl(j).n);
      idx.indices.push_back(ansi_to_nl(j).l);
    }
    idx.unit = "index";
    idx.description = "modes x 2: (n, l) of K_j in ANSI order j = (n(n+2)+l)/2";
    bank.basis.push_back(std::move(idx));
  }

 private:
  const Scene& s_;
  std::map<int, std::shared_ptr<const Grid>> grids_;
  std::map<std::pair<int, int>, std::unique_ptr<ProjectionContext>> contexts_;
  std::map<int, int> supported_;
  std::shared_ptr<const Grid> bank_grid_;
  std::map<int, std::unique_ptr<BankOperators>> bank_contexts_;
};

}  // namespace

std::string fnv1a_hex(const std::string& text) {
  std::uint64_t h = 1469598103934665603ULL;
  for (unsigned char c : text) {
    h ^= c;
    h *= 1099511628211ULL;
  }
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
  return buf;
}

BankBuildResult build_bank(const Scene& scene, const BankBuildOptions& opt) {
  if (opt.output.empty()) throw ArgumentError("bank build: an output path is required");
  auto say = [&](const std::string& line) {
    if (opt.progress) opt.progress(line);
  };
  const std::string partial_path = opt.output + ".partial";
  std::map<std::string, MaterialRecord> previous;  // key -> record
  if (opt.resume && ::access(partial_path.c_str(), F_OK) == 0) {
    for (auto& rec : read_bank(partial_path).materials) {
      const auto it = rec.labels.find("key");
      if (it != rec.labels.end()) previous.emplace(it->second, std::move(rec));
    }
    say("resuming: " + std::to_string(previous.size()) + " finished material(s) in " + partial_path);
  }
  Builder b(scene);
  BankBuildResult result;
  BankContents done;  // finished materials, in scene order
  bool failed = false;
  // Resume-file checkpoints: the whole file is rewritten each time (atomically), so its cost grows with the
  // materials finished; a checkpoint is written once the time since the previous one reaches
  // kCheckpointRatio times that one's duration (always after the first material, and at the end of a failed
  // or interrupted build), which bounds the time spent on them to 1/(1 + kCheckpointRatio) of the build.
  size_t saved = 0;  // materials in the resume file
  double last_write_s = 0.0;
  auto last_end = std::chrono::steady_clock::now();
  auto checkpoint = [&](bool force) {
    if (done.materials.size() == saved) return;
    const auto t = std::chrono::steady_clock::now();
    if (!force && std::chrono::duration<double>(t - last_end).count() < kCheckpointRatio * last_write_s) return;
    write_bank(partial_path, done);
    last_end = std::chrono::steady_clock::now();
    last_write_s = std::chrono::duration<double>(last_end - t).count();
    saved = done.materials.size();
  };
  for (size_t i = 0; i < scene.materials.size(); ++i) {
    const auto& m = scene.materials[i];
    if (opt.stop && opt.stop->load() != 0) {
      result.interrupted = true;
      break;
    }
    MaterialReport rep;
    rep.name = m.name;
    rep.key = material_key(scene, m);
    say("[" + std::to_string(i + 1) + "/" + std::to_string(scene.materials.size()) + "] " + m.name + " (" + m.source + ")");
    const auto prev = previous.find(rep.key);
    try {
      MaterialRecord rec;
      if (prev != previous.end()) {
        rec = prev->second;
        rec.name = m.name;
        rep.resumed = true;
        rep.source = rec.spectrum.source;
        rep.isotropic = rec.spectrum.isotropic;
        rep.order = rec.spectrum.order;
        auto fig = [&](const char* k) { return rec.figures.count(k) ? rec.figures.at(k) : std::nan(""); };
        rep.level = static_cast<int>(fig("fit_level"));
        rep.target = fig("target");
        rep.error_l2 = fig("error_l2");
        rep.error_max = fig("error_max");
        rep.kept = static_cast<int>(fig("kept_coefficients"));
        rep.total = static_cast<int>(fig("total_coefficients"));
        rep.bytes = static_cast<long long>(fig("bytes"));
        rep.seconds = fig("seconds");
        rep.anisotropy = rec.spectrum.anisotropy_fraction;
        rep.measured = !(rec.labels.count("error_measured") && rec.labels.at("error_measured") != "yes");
      } else {
        rec = b.fit_material(m, rep, say);
      }
      rep.ok = true;
      done.materials.push_back(std::move(rec));
      checkpoint(false);
    } catch (const std::exception& e) {
      rep.ok = false;
      rep.error = e.what();
      failed = true;
      say(m.name + ": FAILED: " + rep.error);
    }
    result.materials.push_back(std::move(rep));
  }
  if (failed || result.interrupted) {
    checkpoint(true);  // every finished material is kept for --resume
    return result;
  }
  // The bank: grid and operators on the bank level for every order used, and the materials.
  BankContents bank;
  bank.grid = b.bank_grid();
  std::vector<int> orders;
  for (const auto& rec : done.materials) orders.push_back(rec.spectrum.order);
  std::sort(orders.begin(), orders.end());
  orders.erase(std::unique(orders.begin(), orders.end()), orders.end());
  for (int n : orders) b.add_basis(bank, n);
  bank.materials = std::move(done.materials);
  write_bank(opt.output, bank);
  ::unlink(partial_path.c_str());
  result.written = true;
  return result;
}

}  // namespace icobrdf
