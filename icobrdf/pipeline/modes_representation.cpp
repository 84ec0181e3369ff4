#include "icobrdf/pipeline/modes_representation.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>

#include "icobrdf/core/basis/helmholtz_modes.hpp"
#include "icobrdf/core/basis/isotropic_modes.hpp"
#include "icobrdf/core/support/error.hpp"
#include "icobrdf/pipeline/keys.hpp"
#include "icobrdf/pipeline/level_order_search.hpp"
#include "icobrdf/pipeline/pruning.hpp"

namespace icobrdf {
namespace {

LevelOrderSearch search_for(const MaterialProblem& p) {
  LevelOrderSearch s;
  s.base.grid_kind = GridKind::EqualArea;
  s.base.sampling = p.scene.sampling;  // LUT rows and B sampled with the same rule (exact for BRDFs in the span)
  s.levels = p.material.level >= 0 ? std::vector<int>{p.material.level} : p.scene.levels;
  s.order_max = p.scene.order_max;
  s.fixed_order = p.material.order;
  // reciprocal = false: the antisymmetric terms of data that are not reciprocal are kept (a source reciprocal by
  // construction has none beyond rounding, and the fits of scattered samples are of the reciprocal modes).
  s.base.reciprocal = p.material.reciprocal || p.source.reciprocal_by_construction() || p.source.values_only_at_samples();
  // Scattered samples: no order beyond what they determine (unless the scene fixes it), each order fitted.
  const int cap = p.source.largest_sample_order(p.material.isotropic == IsotropicChoice::Always);
  if (p.source.values_only_at_samples()) {
    s.refit_each_order = true;
    if (s.fixed_order < 0 && cap >= 0) s.order_max = std::min(s.order_max, cap);
  } else if (cap >= 0) {
    s.order_max = std::min(s.order_max, cap);  // e.g. a MERL table's isotropic bound
  }
  return s;
}

// isotropic = "auto": the chosen fit becomes isotropic when its isotropic projection still meets the target.
void choose_isotropy(const MaterialProblem& p, LevelOrderChoice& c) {
  std::vector<Eigen::MatrixXd> iso;
  for (const auto& ch : c.spectrum.channels) iso.push_back(isotropic_part(ch, c.order));
  const HeldOutError e = (*p.errors)(iso, c.order);
  if (e.l2 <= p.material.target) {
    c.spectrum.channels = std::move(iso);
    c.spectrum.isotropic = true;
    c.error = e;
  }
  p.say(p.material.name + ": anisotropic energy fraction " + exact_decimal(c.spectrum.anisotropy_fraction) + ", isotropic error " +
        exact_decimal(e.l2) + " -> " + (c.spectrum.isotropic ? "isotropic" : "anisotropic"));
}

int coefficient_count(const Spectrum& s) { return coefficient_total(s); }

}  // namespace

MaterialRecord modes_record(const std::string& name, const Spectrum& spectrum) {
  MaterialRecord rec;
  rec.name = name;
  rec.spectrum = spectrum;
  if (!spectrum.isotropic) return rec;
  const auto modes = isotropic_modes(spectrum.order);
  rec.ibsss.resize(spectrum.channel_count(), static_cast<Eigen::Index>(modes.size()));
  for (int c = 0; c < spectrum.channel_count(); ++c) rec.ibsss.row(c) = ibsss_from_coefficients(spectrum.channels[c]).transpose();
  rec.ibsss_indices.resize(static_cast<Eigen::Index>(modes.size()), 3);
  for (size_t k = 0; k < modes.size(); ++k) rec.ibsss_indices.row(static_cast<Eigen::Index>(k)) << modes[k].n, modes[k].m, modes[k].l;
  return rec;
}

long long modes_bytes(const Spectrum& s, int kept) {
  return static_cast<long long>(kept) * (8LL * s.channel_count() + (s.isotropic ? 12 : 16));
}

MaterialCandidate fit_modes_candidate(const MaterialProblem& p) {
  const SceneMaterial& m = p.material;
  LevelOrderSearch search = search_for(p);
  MaterialCandidate c;
  c.representation = "modes";
  LevelOrderChoice choice;
  if (!p.errors) {
    search.base.isotropic = m.isotropic != IsotropicChoice::Never;
    choice = fit_at_given_order(p.source, search, p.contexts);
    c.measured = false;
    c.isotropic = search.base.isotropic;
  } else {
    search.base.isotropic = m.isotropic == IsotropicChoice::Always;
    // Every order measured, unpruned: its reciprocal modes (8 bytes a channel and their indices).
    search.seen = [&p, iso = search.base.isotropic](int, int order, double l2) {
      const long long modes = iso ? isotropic_mode_count(order) : helmholtz_mode_count(order);
      note_tried(p, modes * (8LL * p.source.channels() + (iso ? 12 : 16)), l2);
    };
    const auto accept = [&](LevelOrderChoice& found) {
      if (m.isotropic == IsotropicChoice::Auto) choose_isotropy(p, found);
    };
    choice = search_level_order(p.source, search, p.contexts, *p.errors, m.target, m.name, accept, p.say);
    c.isotropic = choice.spectrum.isotropic;
    if (m.prune) {
      const PruneResult pr = prune_coefficients(choice.spectrum, *p.errors, m.target);
      c.total = pr.total;
      c.kept = pr.kept;
      if (pr.pruned) choice.error = pr.error;
    }
  }
  c.level = choice.level;
  c.order = choice.order;
  c.error = choice.error;
  c.anisotropy = choice.spectrum.anisotropy_fraction;
  c.record = modes_record(m.name, choice.spectrum);
  if (c.total == 0) c.total = c.kept = coefficient_count(c.record.spectrum);
  const Spectrum& s = c.record.spectrum;
  c.bytes = modes_bytes(s, c.kept);
  return c;
}

MaterialCandidate fit_modes_within_budget(const MaterialProblem& p) {
  const SceneMaterial& m = p.material;
  if (!p.errors) throw UnsupportedError("modes: a delta BRDF has no pointwise error to minimize within max_bytes");
  LevelOrderSearch search = search_for(p);
  search.base.isotropic = m.isotropic == IsotropicChoice::Always;
  std::optional<MaterialCandidate> best;
  const auto consider = [&](int level, Spectrum s) {
    const long long each = modes_bytes(s, 1);
    const int total = coefficient_count(s);
    const int fits = m.max_bytes < 0 ? total : static_cast<int>(std::min<long long>(total, m.max_bytes / each));
    if (fits < 1) return;
    const PruneResult pr = keep_largest(s, *p.errors, fits);
    const long long bytes = modes_bytes(s, pr.kept);
    if (best && (pr.error.l2 > best->error.l2 || (pr.error.l2 == best->error.l2 && bytes >= best->bytes))) return;  // ties: fewer bytes
    MaterialCandidate c;
    c.representation = "modes";
    c.level = level;
    c.order = s.order;
    c.error = pr.error;
    c.isotropic = s.isotropic;
    c.anisotropy = s.anisotropy_fraction;
    c.kept = pr.kept;
    c.total = pr.total;
    c.bytes = bytes;
    c.record = modes_record(m.name, s);
    best = std::move(c);
  };
  each_level_order(p.source, search, p.contexts, [&](int level, const Spectrum& s) {
    consider(level, s);
    if (m.isotropic != IsotropicChoice::Auto || s.isotropic) return;
    Spectrum iso = s;
    for (auto& ch : iso.channels) ch = isotropic_part(ch, s.order);
    iso.isotropic = true;
    consider(level, std::move(iso));
  });
  if (!best)
    throw UnsupportedError("modes: not one coefficient fits max_bytes " + std::to_string(m.max_bytes) + " (" +
                           std::to_string(8 * p.source.channels() + 12) + " bytes each at least)");
  best->target_met = best->error.l2 <= m.target;
  p.say(m.name + ": lowest error within " + (m.max_bytes < 0 ? std::string("any size") : std::to_string(m.max_bytes) + " bytes") + ": " +
        exact_decimal(best->error.l2) + " at level " + std::to_string(best->level) + " order " + std::to_string(best->order) + " (" +
        std::to_string(best->bytes) + " bytes)");
  return std::move(*best);
}

}  // namespace icobrdf
