#include "icobrdf/pipeline/half_angle_representation.hpp"

#include <Eigen/QR>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <optional>
#include <random>

#include "icobrdf/core/basis/direction.hpp"
#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/models/function_model.hpp"
#include "icobrdf/core/models/half_angle_factors.hpp"
#include "icobrdf/core/basis/isotropic_modes.hpp"
#include "icobrdf/core/fit/lobe_axes.hpp"
#include "icobrdf/io/material_eval.hpp"
#include "icobrdf/pipeline/keys.hpp"
#include "icobrdf/pipeline/lobe_budget.hpp"
#include "icobrdf/pipeline/modes_representation.hpp"

namespace icobrdf {
namespace {

// Share of the target the isotropy defect may take before a lobe is fitted anisotropically: the isotropic
// lobe then misses the azimuthal variation (about defect / sqrt 2), which leaves most of the target to the
// factorization and the interpolation.
constexpr double kIsotropyShare = 0.25;
// Share of the target the weighted node error may take: the rest is left to the interpolation between nodes
// (measured: the held-out error of a lobe is its node error plus an interpolation part of the same size on
// the first grid fine enough).
constexpr double kNodeShare = 0.5;
// Pairs of the peak-sampled error check (peak_error): half uniform, half reflected about normals near h = n.
constexpr int kPeakPairs = 20000;
// Smallest target a lobe is fitted for: the finest grid of the ladder leaves interpolation errors of
// 0.005-0.02 on the glossy scene's lobes (measured), so no grid meets a target below 1e-3, and trying all of
// them at rank 8 costs seconds (minutes under the sanitizers); such targets are refused at once.
constexpr double kSmallestLobeTarget = 1e-3;
// Smallest ratio of a lobe's widths (icobrdf/core/fit/lobe_axes.hpp) for which the h grid of an anisotropic lobe is
// stretched: below it a stretch changes the interpolation error by less than the estimate's own spread.
constexpr double kStretchRatio = 1.1;
// Largest rank tried at one grid.
constexpr int kMaxRank = 8;
// ALS sweeps per rank, and the relative decrease of the objective below which they stop: the node error only
// has to reach kNodeShare of the target, and the held-out error decides; tighter settings cost 4-10x the
// time for changes in the third digit of the error (measured on the glossy scene).
constexpr int kMaxSweeps = 60;
constexpr double kSweepTolerance = 1e-4;
// Body orders of a hybrid (isotropic modes: 5 and 14 coefficients at orders 2 and 4): a body is worth its
// bytes when it takes terms off the lobe (Lambert is rank 2 in the cosine quantity), which low orders do.
constexpr int kHybridOrders[] = {2, 4};
// Rounds of the alternation body <-> lobe (each a lobe fit); both steps minimize the metric's error, the body
// at kBodyPairs pairs and the lobe at its nodes, so the rounds descend until the two estimates part; the
// alternation stops at the first round without progress, or once the error is within kHybridSettled of the
// target (a few rounds more would buy a digit the choice does not need).
constexpr int kHybridRounds = 8;
// Measured data: rounds after the second moved RGL acrylic_felt_green's hybrid by 0.4 % (0.01589 -> 0.01582 over
// six rounds of per-channel rank-6 lobes on 256 x 64x16 nodes), at 10-20 s of CPU each (measured).
constexpr int kMeasuredHybridRounds = 2;
constexpr double kHybridSettled = 0.5;
// Pairs of the body's least-squares fit: 14 unknowns at most per channel (order 4), so 20,000 pairs uniform in
// solid angle leave a sampling error of ~1% of the body's own error.
constexpr int kBodyPairs = 20000;
// Lobe ranks a hybrid tries below the lobe alone's: a low-order body takes one or two terms off (Lambert is
// rank 2 in the cosine quantity).
constexpr int kHybridRankDrop = 2;

struct LadderStep {
  int n_t, n_phi_h, n_theta_d, n_phi_d;
  bool centred = false;  // nodes at bin centres (HalfAngleFactors::centred)
  double h_axis = 0.0, h_scale_1 = 1.0;  // stretch of an anisotropic h grid (set per material, fit_lobe)
};
// Grids in increasing size: isotropic (n_phi_h = 1) and anisotropic. theta_d starts fine: masking makes q
// steep towards grazing, and 32 theta_d nodes leave held-out errors of 0.03-0.47 for GGX alpha 0.05-0.3
// where 64 give 0.005-0.009 (measured, cosine metric); then resolution goes to theta_h (the lobe) and phi_d.
constexpr LadderStep kIsotropicLadder[] = {{32, 1, 64, 16},  {64, 1, 64, 32},   {128, 1, 96, 32},
                                           {256, 1, 128, 32}, {256, 1, 128, 64}, {512, 1, 128, 64}};
// Anisotropic lobes: on an h grid stretched along the lobe's axes (icobrdf/core/fit/lobe_axes.hpp) an elliptical lobe
// needs few phi_h nodes (GGX alpha 0.1 x 0.3, held-out errors at ranks 4-6: 0.025 on 32 x 8 h nodes, 0.010 on
// 48 x 16, against 0.035 at rank 8 on an unstretched 48 x 32; measured, mean-cosine quantity).
constexpr LadderStep kAnisotropicLadder[] = {{32, 8, 64, 16}, {48, 16, 64, 16}, {64, 32, 64, 16}, {96, 32, 96, 32}};
// Measured data (sources not reciprocal by construction: an RGL file, SCATMECH coefficients) carry noise, which no
// lobe holds. Isotropic lobes of such data are searched over the budget grids (icobrdf/pipeline/lobe_budget.hpp:
// every d grid, each rank at the largest n_t the bytes allow; measured_search); anisotropic ones over
// kAnisotropicLadder. Either way:
//   * rank: each rank is fitted on its own and judged on the held-out pairs; a rank whose error is above
//     kStallRatio of the best lower rank's ends the d grid (the error-vs-rank curve flattened, or rose: the
//     next terms fit the noise at the nodes; the node error alone keeps falling there);
//   * anisotropic grids: a step whose held-out error is not below kLadderGain of the best step before ends the
//     ladder. The isotropic search has no such rule (it ended RGL ilm_l3_37_matte on 128x32x8 at 0.0405 after
//     64x32x8's 0.0378, where 128x16x8 and 256 x 128x32 reach 0.041 at 2,700 B and 0.025 at 37 KB): it visits
//     every d grid within its work cap (kLobeSearchWork).
constexpr double kStallRatio = 0.9;
constexpr double kLadderGain = 0.9;
// Work of one material's isotropic measured search, in node-terms (n_t x n_theta_d x n_phi_d x rank summed over
// the lobes fitted): the fit's sweeps and the source's sampling grow with it. A search that would pass it ends
// there, and the best lobe so far is the material's (the note says so). 256 x 128x32 at rank 4 alone is 4.2e6;
// 6e6 took 7.6 s of CPU per RGL material (five in 38 s of user time, measured), so the five stay within
// about a minute on 2 cores.
constexpr long long kLobeSearchWork = 8000000;
// Storage the isotropic measured search sizes n_t for: shared factors for several channels (a third of the
// values for RGB), int16 (rounding 1.5e-5 of a column's largest value, far below measured data's errors;
// `bench measured` chose shared int16 at 1,350-5,400 B for four of five RGL materials).
constexpr FactorPrecision kSearchPrecision = FactorPrecision::Int16;
// A lobe is not judged on the held-out pairs when its weighted node error, times the lowest ratio of held-out to
// node error among the material's lobes judged so far, is above the best held-out error over this margin:
// the node error weighs grazing nodes as the mean-cosine quantity does, the held-out error as the cosine
// metric does, so their ratio is the material's (RGL acrylic_felt_green: held-out 0.031 where the node error
// is 0.065), and it varies between grids and ranks by less than this margin (measured, RGL files).
constexpr double kNodeScreen = 0.8;
// Largest rank of the isotropic measured search. Its lobes share one set of factors between the channels, so a
// colour that varies across the lobe takes terms of its own: RGL acrylic_felt_green's shared lobe on 256 x
// 32x16 nodes fell 0.033 -> 0.028 -> 0.024 from rank 4 to 6 (still 13 % a rank) where per-channel factors of
// rank 4 (12 terms) reach 0.016 (measured); 12 shared terms cost the bytes of rank 4 per channel.
constexpr int kMaxMeasuredRank = 12;
// A source whose data sit on a half-angle table of its own (BrdfSource::own_half_angle_nodes, e.g. a MERL table)
// is fitted on those nodes alone: the fit samples its values as they are, with no resampling, and missing
// samples are left out.

// f of a source minus a term at pairs: what a representation must still fit.
class ResidualSource final : public BrdfSource {
 public:
  using Term = std::function<Eigen::MatrixXd(const RowMatrix3d&, const RowMatrix3d&)>;
  ResidualSource(const BrdfSource& source, Term term) : source_(source), term_(std::move(term)) {}
  std::string spec() const override { return source_.spec() + " (residual)"; }
  int channels() const override { return source_.channels(); }
  Eigen::MatrixXd eval(const RowMatrix3d& wi, const RowMatrix3d& wr) const override {
    Eigen::MatrixXd f = source_.eval(wi, wr);
    if (term_) f -= term_(wi, wr);
    return f;
  }
  Spectrum fit(const ProjectionContext& ctx, const FitOptions& o) const override {
    const FunctionModel model(
        channels(), [this](const RowMatrix3d& wi, const RowMatrix3d& wr, Eigen::Ref<Eigen::MatrixXd> out) { out = eval(wi, wr); },
        spec(), o.isotropic, true);
    return fit_model(model, ctx, o);
  }

 private:
  const BrdfSource& source_;
  Term term_;
};

bool lobe_is_isotropic(const MaterialProblem& p) {
  if (p.material.isotropic == IsotropicChoice::Always) return true;
  if (p.material.isotropic == IsotropicChoice::Never) return false;
  const double defect = isotropy_defect(p.source, *p.errors);
  const bool iso = defect <= kIsotropyShare * p.material.target;
  p.say(p.material.name + ": isotropy defect " + exact_decimal(defect) + " -> " + (iso ? "isotropic" : "anisotropic") + " lobe");
  return iso;
}

struct LobeFit {
  HalfAngleFactors lobe;
  HeldOutError error;
  double node_error = 0.0;  // the fit's weighted node error (worst channel)
  bool screened = false;    // not judged (kNodeScreen): `error` is the node error, a lower estimate
};

// Measured data: no analytic form, so noise may put a floor under every lobe (measured_search).
bool measured_data(const MaterialProblem& p) { return !p.source.reciprocal_by_construction(); }

long long lobe_bytes(const HalfAngleFactors& lobe) { return static_cast<long long>(lobe.bytes()) + kLobeHeaderBytes; }

// Bytes of the smallest lobe on a ladder step, rank 1 with shared int8 factors (their column scales and the
// channel scales included): no lobe on that step costs less.
long long rank_one_bytes(const LadderStep& s, int channels) {
  return (s.n_t * s.n_phi_h + s.n_theta_d * s.n_phi_d) + 2LL * 8 + (channels > 1 ? 8LL * channels : 0) + kLobeHeaderBytes;
}

// The error of body + lobe on pairs that see the specular peak: w_i as the held-out pairs draw it; w_r
// uniform in solid angle (half the pairs) or the mirror of w_i about a normal h drawn with the density of the
// t^2 warp of theta_h (t uniform: a density that grows as theta_h^-3/2 towards h = n, so lobes of every width
// at the pole are sampled); each pair weighted by 1 / (mixture pdf of w_r). Uniform pairs see a lobe of
// width alpha with probability ~alpha^2: for GGX alpha <= 0.05 the held-out pairs put the error at 0.01-0.02
// where this estimate (and an independent one sampling GGX itself) gives 0.05-0.09 (measured). nullopt when
// the scene gives lights x cameras (its pairs are then all there is) and for a MERL table (judged at its own
// samples, icobrdf/pipeline/held_out.hpp: its lookup between them is a step function).
std::optional<HeldOutError> peak_error(const MaterialProblem& p, const BrdfSource& residual, const HalfAngleFactors& lobe) {
  const SceneMaterial& m = p.material;
  if (!m.lights.empty()) return std::nullopt;
  if (p.source.judged_at_own_samples()) return std::nullopt;  // e.g. a table, judged at its samples (icobrdf/pipeline/held_out.hpp)
  std::mt19937_64 rng(std::stoull(fnv1a_hex("peak|" + m.name).substr(0, 15), nullptr, 16));
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  const double zlo = std::cos(m.incidence_max * M_PI / 180), zhi = std::cos(m.incidence_min * M_PI / 180);
  RowMatrix3d wi(kPeakPairs, 3), wr(kPeakPairs, 3);
  Eigen::VectorXd pdf(kPeakPairs);
  Eigen::Index n = 0;
  for (int k = 0; k < kPeakPairs; ++k) {
    const Eigen::Vector3d a = uniform_direction(rng, zlo, zhi);
    Eigen::Vector3d b;
    if (k % 2 == 0) {
      b = uniform_direction(rng);
    } else {
      const double t = u01(rng), th = 0.5 * M_PI * t * t, ph = 2.0 * M_PI * u01(rng);
      const Eigen::Vector3d h(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th));
      b = 2.0 * a.dot(h) * h - a;
    }
    if (b.z() <= 0.0) continue;  // the mirror fell below the horizon: f = 0 there, no contribution
    const Eigen::Vector3d h = (a + b).normalized();
    const double th = std::atan2(std::hypot(h.x(), h.y()), h.z()), t = std::sqrt(th / (0.5 * M_PI));
    const double ph_density = (t > 0 && th > 0) ? 1.0 / (2.0 * M_PI * M_PI * t * std::sin(th)) : 0.0;  // per sr of h
    pdf(n) = 0.5 / (2.0 * M_PI) + 0.5 * ph_density / (4.0 * std::abs(a.dot(h)));
    wi.row(n) = a.transpose();
    wr.row(n++) = b.transpose();
  }
  const RowMatrix3d pi = wi.topRows(n), pr = wr.topRows(n);
  // The body is the data less the residual; the reference is the held-out one's (the reciprocal part of
  // measured data, icobrdf/pipeline/held_out.hpp).
  const Eigen::MatrixXd fit = add_lobe(p.source.eval(pi, pr) - residual.eval(pi, pr), lobe, pi, pr);
  const Eigen::MatrixXd f = p.errors->reference_at(p.source, pi, pr);
  Eigen::VectorXd w = (1.0 / pdf.head(n).array()).sqrt();
  if (m.metric == ErrorMetric::Cosine) w = w.cwiseProduct(pi.col(2)).cwiseProduct(pr.col(2));
  const double ref = (w.asDiagonal() * f).norm(), ref_max = (w.asDiagonal() * f).cwiseAbs().maxCoeff();
  const Eigen::MatrixXd d = w.asDiagonal() * (fit - f);
  return HeldOutError{ref > 0 ? d.norm() / ref : d.norm(), ref_max > 0 ? d.cwiseAbs().maxCoeff() / ref_max : 0.0};
}

// Stored forms a lobe that meets the target may take, fewest bytes first (HalfAngleFactors: precision).
constexpr FactorPrecision kLobePrecisions[] = {FactorPrecision::Int8, FactorPrecision::Int16, FactorPrecision::Float32};

// The stored form of a lobe meeting the target with the fewest bytes: its factors, or factors shared by the
// channels (fitted on the same grid, the rank from the same node target), each at the narrowest precision of
// kLobePrecisions whose error (of the stored values) still meets the target; the lobe as it is when none
// is smaller.
void compact_lobe(const MaterialProblem& p, const PairSampler& sampler, int channels, HalfAngleFitOptions o,
                  const std::function<HeldOutError(const HalfAngleFactors&)>& error_of, HalfAngleFactors& lobe, HeldOutError& e) {
  std::vector<HalfAngleFactors> bases{lobe};
  if (channels > 1 && !lobe.shared()) {
    o.shared_channels = true;
    try {
      bases.push_back(fit_half_angle(sampler, channels, o).factors);
    } catch (const UnsupportedError&) {  // no shared lobe meets the node target on this grid
    }
  }
  const long long before = lobe_bytes(lobe);
  for (size_t k = 0; k < bases.size(); ++k)
    for (const FactorPrecision precision : kLobePrecisions) {
      HalfAngleFactors q = bases[k];
      q.precision = precision;
      q.quantize();
      if (lobe_bytes(q) >= lobe_bytes(lobe)) continue;
      const HeldOutError qe = error_of(q);
      if (qe.l2 > p.material.target) continue;
      lobe = std::move(q);
      e = qe;
      break;  // the next precision of this base is wider
    }
  if (lobe_bytes(lobe) < before)
    p.say(p.material.name + ": stored as " + (lobe.shared() ? "shared " : "") + factor_precision_name(lobe.precision) + " factors, rank " +
          std::to_string(lobe.rank) + ", " + std::to_string(lobe_bytes(lobe)) + " bytes: error " + exact_decimal(e.l2));
}

// Errors of stored forms within this share of the lowest are ties, which go to the fewest bytes (as `bench
// measured` chooses its lobes: the held-out estimate's own spread between forms of one fit is of this order).
constexpr double kStoredFormTie = 0.005;

// Measured data short of the target: the stored form of the lobe with the lowest error within `budget` bytes
// (budget < 0: any size), among its factors and factors shared by the channels (fitted on the same grid at the
// same rank), each in float64 and every precision of kLobePrecisions. Shared factors hold all channels in one
// set (a third of the values for RGB, so a finer grid within the bytes) and fit less of each channel's noise;
// the narrower precisions cost a rounding far below measured data's errors. The lobe is kept when no other
// form is lower within the budget.
void lowest_error_form(const MaterialProblem& p, const PairSampler& sampler, int channels, HalfAngleFitOptions o,
                       const std::function<HeldOutError(const HalfAngleFactors&)>& error_of, long long budget, HalfAngleFactors& lobe,
                       HeldOutError& e) {
  std::vector<HalfAngleFactors> bases{lobe};
  if (channels > 1 && !lobe.shared()) {
    o.shared_channels = true;
    try {
      bases.push_back(fit_half_angle(sampler, channels, o).factors);
    } catch (const UnsupportedError&) {  // no shared lobe of this rank on this grid
    }
  }
  const auto within = [budget](const HalfAngleFactors& l) { return budget < 0 || lobe_bytes(l) < budget; };
  std::vector<std::pair<HalfAngleFactors, HeldOutError>> forms;
  if (within(lobe)) forms.emplace_back(lobe, e);
  for (size_t k = 0; k < bases.size(); ++k)
    for (const FactorPrecision precision : {FactorPrecision::Float64, FactorPrecision::Float32, FactorPrecision::Int16, FactorPrecision::Int8}) {
      if (k == 0 && precision == lobe.precision) continue;  // the lobe itself
      HalfAngleFactors q = bases[k];
      q.precision = precision;
      q.quantize();
      if (!within(q)) continue;
      const HeldOutError qe = error_of(q);
      forms.emplace_back(std::move(q), qe);
    }
  if (forms.empty()) return;
  double lowest = INFINITY;
  for (const auto& f : forms) lowest = std::min(lowest, f.second.l2);
  const std::pair<HalfAngleFactors, HeldOutError>* chosen = nullptr;
  for (const auto& f : forms)
    if (f.second.l2 <= lowest * (1 + kStoredFormTie) && (!chosen || lobe_bytes(f.first) < lobe_bytes(chosen->first))) chosen = &f;
  if (chosen->first.shared() == lobe.shared() && chosen->first.precision == lobe.precision) return;
  lobe = chosen->first;
  e = chosen->second;
  p.say(p.material.name + ": lowest error within the bytes as " + (lobe.shared() ? "shared " : "") + factor_precision_name(lobe.precision) +
        " factors, rank " + std::to_string(lobe.rank) + ", " + std::to_string(lobe_bytes(lobe)) + " bytes: error " + exact_decimal(e.l2));
}

// The lobe of `residual` on one grid, its rank from the target, and its error: the larger of the held-out
// error of body + lobe (body: values at the held-out pairs) and of the peak-sampled one (peak_error);
// nullopt when the grid cannot reach the node target. Measured data short of the target: the stored form of
// lowest error within `budget` bytes (lowest_error_form). shared: the channels' shared factors are fitted
// (and their stored forms tried) instead of per-channel ones. A fit whose node error is at least `screen`
// (kNodeScreen x the best held-out error so far) is returned unjudged (LobeFit::screened).
std::optional<LobeFit> fit_lobe_at(const MaterialProblem& p, const BrdfSource& residual, const Eigen::MatrixXd& body, bool isotropic,
                                   const LadderStep& s, int fixed_rank = 0, long long budget = -1, bool shared = false,
                                   double screen = INFINITY) {
  const PairSampler sampler = [&residual](const RowMatrix3d& wi, const RowMatrix3d& wr, Eigen::Ref<Eigen::MatrixXd> out) {
    out = residual.eval(wi, wr);
  };
  HalfAngleFitOptions o;
  // Cosine metric: p = f (cos_i + cos_r) / 2, weighted so that the node error is the metric's (see
  // icobrdf/core/models/half_angle_factors.hpp): smooth across the horizon and at grazing specular, where q = f cos_i cos_r
  // (the metric's own quantity) drops to 0 within a node or two and the grazing Fresnel peak sits.
  // Isotropic lobes of measured data: the metric's own quantity (kMeasuredLobeQuantity).
  o.quantity = p.material.metric != ErrorMetric::Cosine    ? HalfAngleQuantity::F
               : measured_data(p) && isotropic && !p.source.own_half_angle_nodes() ? kMeasuredLobeQuantity
                                                                                    : HalfAngleQuantity::MeanCosine;
  o.isotropic = isotropic;
  o.target = kNodeShare * p.material.target;
  o.max_rank = kMaxRank;
  o.max_sweeps = kMaxSweeps;
  o.sweep_tolerance = kSweepTolerance;
  o.n_t = s.n_t;
  o.n_phi_h = s.n_phi_h;
  o.n_theta_d = s.n_theta_d;
  o.n_phi_d = s.n_phi_d;
  o.centred = s.centred;
  o.skip_missing = p.source.may_miss_values();  // measured data may have missing samples
  o.h_axis = s.h_axis, o.h_scale_1 = s.h_scale_1;
  o.fixed_rank = fixed_rank;
  o.shared_channels = shared && residual.channels() > 1;
  HalfAngleFit fit;
  try {
    fit = fit_half_angle(sampler, residual.channels(), o);
  } catch (const UnsupportedError&) {
    return std::nullopt;
  }
  double node = 0.0;
  for (const double x : fit.report.error) node = std::max(node, x);
  if (node >= screen) {
    p.say(p.material.name + ": half-angle " + std::to_string(s.n_t) + " h, " + std::to_string(s.n_theta_d) + "x" + std::to_string(s.n_phi_d) +
          " d, rank " + std::to_string(fit.factors.rank) + ": node error " + exact_decimal(node) + ", not below the best held-out error");
    return LobeFit{std::move(fit.factors), HeldOutError{node, node}, node, true};
  }
  const auto& pairs = p.errors->pairs();
  // The held-out error of body + lobe and the peak-sampled one, the larger of the two.
  const auto error_of = [&](const HalfAngleFactors& lobe, std::optional<HeldOutError>* peak_out) {
    HeldOutError e = p.errors->of_values(add_lobe(body, lobe, pairs.wi, pairs.wr));
    const auto peak = peak_error(p, residual, lobe);
    if (peak_out) *peak_out = peak;
    if (peak) e = {std::max(e.l2, peak->l2), std::max(e.max, peak->max)};
    return e;
  };
  std::optional<HeldOutError> peak;
  HeldOutError e = error_of(fit.factors, &peak);
  p.say(p.material.name + ": half-angle " + std::to_string(s.n_t) + "x" + std::to_string(s.n_phi_h) + " h, " +
        std::to_string(s.n_theta_d) + "x" + std::to_string(s.n_phi_d) + " d, rank " + std::to_string(fit.factors.rank) +
        ": error " + exact_decimal(e.l2) + (peak ? " (with the peak-sampled " + exact_decimal(peak->l2) + ")" : std::string()));
  // Compact forms only in banks without LUTs: a LUT samples the lobe at every pair of the bank grid's cubature
  // points (7.6e7 evaluations at level 2, 15-25 s per material on one thread, whatever the factors' storage;
  // bench_half_angle --lut), and it outweighs the lobe's bytes in the file (cells^2 values per channel: 28,224
  // at level 2), so a few kilobytes saved would buy a lobe over the modes at that cost. Such banks keep float64
  // factors per channel, which win on bytes far less often.
  const bool compact = !p.scene.store_lut;
  const auto stored_error = [&](const HalfAngleFactors& l) { return error_of(l, nullptr); };
  const bool measured = compact && measured_data(p);
  std::optional<std::pair<HalfAngleFactors, HeldOutError>> fitted;  // measured data: the fit before compact_lobe
  if (measured) fitted.emplace(fit.factors, e);
  if (compact && e.l2 <= p.material.target) compact_lobe(p, sampler, residual.channels(), o, stored_error, fit.factors, e);
  // Measured data: short of the target, or meeting it only above the budget (the narrowest form meeting it is
  // still too large), the lowest error within the budget.
  if (measured && (e.l2 > p.material.target || (budget >= 0 && lobe_bytes(fit.factors) >= budget))) {
    fit.factors = std::move(fitted->first), e = fitted->second;
    lowest_error_form(p, sampler, residual.channels(), o, stored_error, budget, fit.factors, e);
  }
  return LobeFit{std::move(fit.factors), e, node};
}

LadderStep step_of(const HalfAngleFactors& l) {
  return {l.n_t, l.n_phi_h, l.n_theta_d, l.n_phi_d, l.centred, l.h_axis, l.h_scale_1};
}

// What a ladder search found short of the target: its lowest error within the bytes to beat, that lobe, and
// the figure that ended the search.
struct LobeMiss {
  double best = INFINITY;
  std::optional<LobeFit> fit;  // the lowest-error lobe within the bytes to beat (measured data)
  std::string stop;            // why the search ended before the last step ("" when it ran them all)
  std::string floor;           // the isotropic measured search: its error against bytes (floor_text)
};

std::string short_number(double x);

// Measured data: the ranks of one grid, each fitted on its own, from 1 to rank_cap, until one meets the target or
// its held-out error is above kStallRatio of the best before; the best (the one meeting the target, else the
// lowest error), its stored form of lowest error below `budget` bytes (< 0: any). nullopt when no rank could be fitted.
std::optional<LobeFit> measured_step(const MaterialProblem& p, const BrdfSource& residual, const Eigen::MatrixXd& body, bool isotropic,
                                     const LadderStep& s, int rank_cap, long long budget) {
  std::optional<LobeFit> best;
  for (int rank = 1; rank <= rank_cap; ++rank) {
    auto fit = fit_lobe_at(p, residual, body, isotropic, s, rank, budget);
    if (!fit) break;
    if (budget >= 0 && lobe_bytes(fit->lobe) >= budget) break;  // no stored form of this rank, nor of the next, is small enough
    if (fit->error.l2 <= p.material.target) return fit;
    const bool flat = best && fit->error.l2 > kStallRatio * best->error.l2;
    if (!best || fit->error.l2 < best->error.l2) best = std::move(fit);
    if (flat) break;
  }
  return best;
}

// "n_t x n_theta_d x n_phi_d rank R [shared ]precision": a lobe's grid and stored form in messages.
std::string lobe_text(const HalfAngleFactors& l) {
  return std::to_string(l.n_t) + "x" + std::to_string(l.n_theta_d) + "x" + std::to_string(l.n_phi_d) + " rank " + std::to_string(l.rank) +
         (l.shared() ? " shared " : " ") + factor_precision_name(l.precision);
}

// One lobe the isotropic measured search judged: its stored bytes and held-out error.
struct CurvePoint {
  long long bytes;
  double error;
};

// A missed target's measured figure: the lowest error of the search (its bytes, grid and form) beside the
// lowest error within half those bytes. A small gain for twice the bytes is the curve of error against bytes
// flattening: the isotropic half-angle lobe's floor on these data within the grids and ranks tried.
std::string floor_text(const std::vector<CurvePoint>& curve, const LobeFit& best) {
  const long long bytes = lobe_bytes(best.lobe);
  double half = INFINITY;
  for (const CurvePoint& c : curve)
    if (c.bytes <= bytes / 2) half = std::min(half, c.error);
  std::string s = "error against bytes: " + short_number(best.error.l2) + " at " + std::to_string(bytes) + " B (" + lobe_text(best.lobe) + ")";
  if (std::isfinite(half)) {
    char gain[64];
    std::snprintf(gain, sizeof gain, "%.0f %%", 100.0 * (1.0 - best.error.l2 / half));
    s += ", " + short_number(half) + " within " + std::to_string(bytes / 2) + " B: twice the bytes gained " + gain;
  }
  return s;
}

// Measured data, isotropic lobe: for each d grid of kLobeBudgetD (smallest first), the ranks from 1, each on the
// largest n_t of kLobeBudgetNt whose lobe (shared kSearchPrecision factors for several channels, per channel
// for one) stays below the bytes to beat, until a rank stalls (kStallRatio) or no n_t fits; every lobe fitted
// counts n_t x n_theta_d x n_phi_d x rank towards the work cap (MaterialProblem::lobe_work_cap, < 0:
// kLobeSearchWork), and the search ends before a lobe that would pass it. Lobes whose node error cannot beat
// the best so far are not judged (kNodeScreen). The first lobe meeting the target wins, on the smallest n_t of
// its d grid and rank that still meets it; nullopt when none does (*miss: the lowest error within the bytes,
// that lobe, the error-vs-bytes figure and why the search ended).
std::optional<LobeFit> measured_search(const MaterialProblem& p, const BrdfSource& residual, const Eigen::MatrixXd& body, LobeMiss* miss,
                                       long long body_bytes) {
  const int channels = residual.channels();
  const bool shared = channels > 1;
  const long long budget = p.bytes_to_beat < 0 ? -1 : p.bytes_to_beat - body_bytes;  // a lobe stays below it
  const long long cap = p.lobe_work_cap >= 0 ? p.lobe_work_cap : kLobeSearchWork;
  long long work = 0;
  std::vector<CurvePoint> curve;
  double ratio = INFINITY;  // lowest held-out / node error of the lobes judged (kNodeScreen)
  const auto grid_name = [](int n_t, const int* d) { return std::to_string(n_t) + "x" + std::to_string(d[0]) + "x" + std::to_string(d[1]); };
  const auto fit_at = [&](int n_t, const int* d, int rank, double screen) -> std::optional<LobeFit> {
    work += static_cast<long long>(n_t) * d[0] * d[1] * rank;
    return fit_lobe_at(p, residual, body, true, LadderStep{n_t, 1, d[0], d[1]}, rank, budget, shared, screen);
  };
  // Ranks on a d grid start one below the rank of the previous d grid's best lobe: a finer d grid needs as many
  // terms (RGL files: ranks 1-3 of a grid after one whose best was rank 5 were all screened out), and the work
  // they would take goes to higher ranks instead.
  int first_rank = 1;
  for (const auto& d : kLobeBudgetD) {
    double grid_best = INFINITY, previous_node = INFINITY;
    int grid_best_rank = first_rank;
    for (int rank = first_rank; rank <= kMaxMeasuredRank; ++rank) {
      const int n_t = largest_n_t(budget < 0 ? -1 : budget - 1, channels, rank, d[0], d[1], shared, kSearchPrecision);
      if (n_t == 0) break;
      if (work + static_cast<long long>(n_t) * d[0] * d[1] * rank > cap) {
        miss->stop = "its work cap (" + std::to_string(cap) + " node-terms) ended it before " + grid_name(n_t, d) + " rank " + std::to_string(rank) +
                     ", " + std::to_string(work) + " spent";
        if (miss->fit) miss->floor = floor_text(curve, *miss->fit);
        return std::nullopt;
      }
      auto fit = fit_at(n_t, d, rank, std::isfinite(ratio) ? miss->best / (kNodeScreen * ratio) : INFINITY);
      if (!fit) break;
      const double node = fit->node_error;
      if (fit->screened) {
        // Not judged: the rank stalls when the node error stopped falling (kStallRatio), else a higher rank
        // may still do better.
        if (node > kStallRatio * previous_node) break;
        previous_node = node;
        continue;
      }
      previous_node = node;
      if (node > 0) ratio = std::min(ratio, fit->error.l2 / node);
      if (budget >= 0 && lobe_bytes(fit->lobe) >= budget) break;
      curve.push_back({lobe_bytes(fit->lobe), fit->error.l2});
      note_tried(p, body_bytes + lobe_bytes(fit->lobe), fit->error.l2);
      if (fit->error.l2 <= p.material.target) {
        // The smallest n_t of this d grid and rank that still meets the target, within the work cap.
        const int* nt = std::find(std::begin(kLobeBudgetNt), std::end(kLobeBudgetNt), n_t);
        while (nt != std::begin(kLobeBudgetNt) && work + static_cast<long long>(*(nt - 1)) * d[0] * d[1] * rank <= cap) {
          --nt;
          auto smaller = fit_at(*nt, d, rank, INFINITY);
          if (!smaller || smaller->error.l2 > p.material.target) break;
          note_tried(p, body_bytes + lobe_bytes(smaller->lobe), smaller->error.l2);
          if (lobe_bytes(smaller->lobe) < lobe_bytes(fit->lobe)) fit = std::move(smaller);
        }
        return fit;
      }
      if (fit->error.l2 < miss->best) miss->best = fit->error.l2, miss->fit = *fit;
      const bool flat = fit->error.l2 > kStallRatio * grid_best;
      if (fit->error.l2 < grid_best) grid_best = fit->error.l2, grid_best_rank = rank;
      if (flat) break;
    }
    if (std::isfinite(grid_best)) first_rank = std::max(1, grid_best_rank - 1);
  }
  if (miss->fit) miss->floor = floor_text(curve, *miss->fit);
  return std::nullopt;
}

// The first grid of the ladder whose lobe, added to `body` at the held-out pairs, meets the target; nullopt
// when none does (*miss: the best error, for measured data the best lobe and why the search stopped). Steps
// whose rank-1 lobe plus `body_bytes` cannot beat p.bytes_to_beat are not tried, and the rank stays within it.
std::optional<LobeFit> fit_lobe(const MaterialProblem& p, const BrdfSource& residual, const Eigen::MatrixXd& body, bool isotropic,
                                LobeMiss* miss, long long body_bytes = 0) {
  const std::optional<HalfAngleNodes> own = p.source.own_half_angle_nodes();
  const bool measured = measured_data(p);
  if (measured && isotropic && !own) return measured_search(p, residual, body, miss, body_bytes);
  const LadderStep own_step[] = {own ? LadderStep{own->n_t, own->n_phi_h, own->n_theta_d, own->n_phi_d, own->centred} : LadderStep{}};
  const LadderStep* begin = own ? std::begin(own_step) : !isotropic ? std::begin(kAnisotropicLadder) : std::begin(kIsotropicLadder);
  const LadderStep* end = own ? std::end(own_step) : !isotropic ? std::end(kAnisotropicLadder) : std::end(kIsotropicLadder);
  // An anisotropic lobe's axes, once for every grid of the ladder.
  LobeAxes axes;
  if (!isotropic)
    axes = estimate_lobe_axes([&residual](const RowMatrix3d& wi, const RowMatrix3d& wr,
                                          Eigen::Ref<Eigen::MatrixXd> out) { out = residual.eval(wi, wr); },
                              residual.channels());
  const bool stretch = axes.found && axes.ratio() >= kStretchRatio;
  for (const LadderStep* s = begin; s != end; ++s) {
    const long long one = rank_one_bytes(*s, residual.channels());
    if (p.bytes_to_beat >= 0 && body_bytes + one >= p.bytes_to_beat) {
      if (measured) continue;  // a later step may be smaller
      break;
    }
    // The largest rank whose lobe stays below the bytes to beat.
    const int rank_cap = p.bytes_to_beat < 0 ? kMaxRank
                                             : static_cast<int>(std::min<long long>(kMaxRank, (p.bytes_to_beat - 1 - body_bytes - kLobeHeaderBytes) /
                                                                                                   (one - kLobeHeaderBytes)));
    LadderStep step = *s;
    if (stretch) step.h_axis = axes.axis, step.h_scale_1 = std::min(axes.ratio(), kMaxHScale);
    if (!measured) {
      auto fit = fit_lobe_at(p, residual, body, isotropic, step);
      if (!fit) continue;  // this grid cannot reach the node target within kMaxRank; a finer one may
      note_tried(p, body_bytes + lobe_bytes(fit->lobe), fit->error.l2);
      if (fit->error.l2 <= p.material.target) return fit;
      miss->best = std::min(miss->best, fit->error.l2);
      continue;
    }
    const long long budget = p.bytes_to_beat < 0 ? -1 : p.bytes_to_beat - body_bytes;
    auto fit = measured_step(p, residual, body, isotropic, step, rank_cap, budget);
    if (!fit) continue;
    note_tried(p, body_bytes + lobe_bytes(fit->lobe), fit->error.l2);
    if (fit->error.l2 <= p.material.target) return fit;
    const double before = miss->best;
    if (fit->error.l2 < miss->best && (budget < 0 || lobe_bytes(fit->lobe) < budget)) {
      miss->best = fit->error.l2;
      miss->fit = *fit;
    }
    const std::string grid = std::to_string(s->n_t) + "x" + std::to_string(s->n_theta_d) + "x" + std::to_string(s->n_phi_d);
    if (std::isfinite(before) && fit->error.l2 > kLadderGain * before) {
      miss->stop = "grid " + grid + " brought the error from " + short_number(before) + " to " + short_number(fit->error.l2) + " only";
      break;
    }
  }
  return std::nullopt;
}

// Numbers in messages: three significant digits (the progress lines keep every digit).
std::string short_number(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", x);
  return buf;
}

void require_pointwise(const MaterialProblem& p, const char* what) {
  if (!p.errors) throw UnsupportedError(std::string(what) + ": a delta BRDF has no pointwise values to factorize");
  if (p.source.values_only_at_samples())
    throw UnsupportedError(std::string(what) + ": scattered samples have no values between them to factorize (the modes fit them)");
  if (p.material.target < kSmallestLobeTarget)
    throw UnsupportedError(std::string(what) + ": target " + short_number(p.material.target) + " is below " +
                           short_number(kSmallestLobeTarget) + ", finer than linear interpolation on the lobe grids reaches");
}

MaterialCandidate lobe_candidate(const MaterialProblem& p, const char* representation, Spectrum body, LobeFit fit, int level,
                                 long long body_bytes, int body_kept) {
  MaterialCandidate c;
  c.representation = representation;
  c.record = modes_record(p.material.name, body);
  c.record.lobe = std::move(fit.lobe);
  c.bytes = body_bytes + lobe_bytes(*c.record.lobe);
  c.error = fit.error;
  c.isotropic = body.isotropic && c.record.lobe->isotropic;
  c.level = level;
  c.order = body.order > 0 ? body.order : -1;  // a lobe alone has no modes to speak of
  c.anisotropy = body.anisotropy_fraction;
  const int per_channel = c.record.lobe->rank * (c.record.lobe->h_nodes() + c.record.lobe->d_nodes());
  c.kept = c.total = body_kept + per_channel;
  return c;
}

// A zero spectrum of order 0: the modes part of a lobe alone.
Spectrum zero_body(const MaterialProblem& p, bool isotropic) {
  Spectrum s;
  s.order = 0;
  s.isotropic = isotropic;
  s.channels.assign(static_cast<size_t>(p.source.channels()), Eigen::MatrixXd::Zero(1, 1));
  s.source = p.source.spec();
  return s;
}

// Pairs on which the body of a hybrid is fitted: uniform in solid angle (their own seed, apart from the
// held-out pairs), with the metric's weights, the source's values and the isotropic modes up to the largest
// body order there.
struct BodyPairs {
  RowMatrix3d wi, wr;
  Eigen::VectorXd w;   // the metric's weight per pair
  Eigen::MatrixXd f;   // pairs x channels
  Eigen::MatrixXd modes;  // pairs x isotropic_mode_count(max order), library order (low orders first)
};

BodyPairs body_pairs(const MaterialProblem& p, int max_order) {
  BodyPairs b;
  uniform_pairs(kBodyPairs, std::stoull(fnv1a_hex("body|" + p.material.name).substr(0, 15), nullptr, 16), b.wi, b.wr);
  b.w = p.material.metric == ErrorMetric::Cosine ? Eigen::VectorXd(b.wi.col(2).cwiseProduct(b.wr.col(2)))
                                                : Eigen::VectorXd::Ones(kBodyPairs);
  b.f = p.source.eval(b.wi, b.wr);
  // Measured data may miss samples (a MERL table's missing and held-out bins are NaN): such pairs weigh 0.
  for (Eigen::Index k = 0; k < b.f.rows(); ++k)
    if (!b.f.row(k).allFinite()) {
      b.w(k) = 0.0;
      b.f.row(k).setZero();
    }
  b.modes = isotropic_modes_eval(max_order, b.wi, b.wr);
  return b;
}

// The body of a hybrid: isotropic modes of `order` minimizing the metric's error of body + lobe against f at
// the body pairs (weighted linear least squares, per channel), the same error the lobe's fit minimizes at its
// nodes, so that the alternation body <-> lobe descends one objective.
Spectrum fit_body(const MaterialProblem& p, const BodyPairs& b, const HalfAngleFactors* lobe, int order) {
  const int k = isotropic_mode_count(order);
  Eigen::MatrixXd target = b.f;
  if (lobe) target -= lobe->eval(b.wi, b.wr);
  const Eigen::MatrixXd A = b.w.asDiagonal() * b.modes.leftCols(k);
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(A);
  Spectrum s = zero_body(p, true);
  s.order = order;
  s.channels.clear();
  for (Eigen::Index c = 0; c < target.cols(); ++c) {
    const Eigen::VectorXd x = qr.solve(b.w.asDiagonal() * target.col(c));
    s.channels.push_back(coefficients_from_ibsss(order, x));
  }
  return s;
}

}  // namespace

double isotropy_defect(const BrdfSource& source, const HeldOutErrors& errors) {
  // A MERL table's lookup depends on the half-difference angles alone, which a turn about the normal keeps
  // (and its held-out bins are missing from the table the builder fits).
  if (source.isotropic_by_construction()) return 0.0;
  const HeldOutPairs& h = errors.pairs();
  std::mt19937_64 rng(0x5eed15070ULL);
  std::uniform_real_distribution<double> angle(0.0, 2.0 * M_PI);
  RowMatrix3d wi(h.wi.rows(), 3), wr(h.wr.rows(), 3);
  for (Eigen::Index k = 0; k < h.wi.rows(); ++k) {
    const double a = angle(rng), c = std::cos(a), s = std::sin(a);
    wi.row(k) << c * h.wi(k, 0) - s * h.wi(k, 1), s * h.wi(k, 0) + c * h.wi(k, 1), h.wi(k, 2);
    wr.row(k) << c * h.wr(k, 0) - s * h.wr(k, 1), s * h.wr(k, 0) + c * h.wr(k, 1), h.wr(k, 2);
  }
  const Eigen::MatrixXd rotated = errors.reference_at(source, wi, wr);
  const Eigen::VectorXd& w = errors.weights();
  const double ref = (w.asDiagonal() * h.f).norm();
  const double diff = (w.asDiagonal() * (rotated - h.f)).norm();
  return ref > 0 ? diff / ref : diff;
}

// Refuses at once when even the smallest lobe (the first step of the ladder, rank 1) cannot beat the bytes found.
static void require_can_beat(const MaterialProblem& p, const char* what, long long body_bytes) {
  const int channels = p.source.channels();
  const long long smallest = measured_data(p) ? stored_lobe_bytes(channels, 1, kLobeBudgetNt[0], kLobeBudgetD[0][0], kLobeBudgetD[0][1],
                                                                  channels > 1, kSearchPrecision)
                                              : rank_one_bytes(kIsotropicLadder[0], channels);
  if (p.bytes_to_beat >= 0 && body_bytes + smallest >= p.bytes_to_beat)
    throw UnsupportedError(std::string(what) + ": no lobe is smaller than the " + std::to_string(p.bytes_to_beat) +
                           " bytes already found");
}

MaterialCandidate fit_half_angle_candidate(const MaterialProblem& p) {
  require_pointwise(p, "half-angle");
  require_can_beat(p, "half-angle", 0);
  const bool iso = lobe_is_isotropic(p);
  const Eigen::MatrixXd none = Eigen::MatrixXd::Zero(p.errors->pairs().wi.rows(), p.source.channels());
  LobeMiss miss;
  auto fit = fit_lobe(p, p.source, none, iso, &miss);
  if (fit) return lobe_candidate(p, "half-angle", zero_body(p, iso), std::move(*fit), -1, 0, 0);
  const std::string why = "half-angle: target " + short_number(p.material.target) + " not met: best relative L2 error " + short_number(miss.best) +
                          (miss.stop.empty() ? (miss.floor.empty() ? " up to the largest grid and rank " + std::to_string(kMaxRank) : " over every grid tried")
                                             : " (the search stopped: " + miss.stop + ")") +
                          (miss.floor.empty() ? std::string() : "; " + miss.floor);
  if (miss.fit && p.best_efforts) {
    MaterialCandidate c = lobe_candidate(p, "half-angle", zero_body(p, iso), std::move(*miss.fit), -1, 0, 0);
    c.target_met = false;
    c.note = "lobe search: " + (miss.stop.empty() ? std::string("every grid tried") : miss.stop) + "; " +
             (miss.floor.empty() ? "best " + short_number(c.error.l2) + " at " + std::to_string(c.bytes) + " bytes" : miss.floor);
    p.best_efforts->push_back(std::move(c));
  }
  throw UnsupportedError(why);
}

MaterialCandidate fit_hybrid_candidate(const MaterialProblem& p) {
  require_pointwise(p, "hybrid");
  require_can_beat(p, "hybrid", 0);
  // The grid and rank of the half-angle candidate (or of the same ladder search when there is none) bound
  // the lobe: a hybrid pays for its body by a lobe of lower rank on that grid. For each body order and each
  // lower rank, body and lobe alternate: body = modes of f - lobe, lobe = rank-R fit of f - body, from
  // body = modes of f.
  std::optional<HalfAngleFactors> first;
  if (p.earlier)
    for (const auto& c : *p.earlier)
      if (c.representation == "half-angle" && c.record.lobe) first = c.record.lobe;
  // The half-angle candidate, tried before with the same bytes to beat, ran this very ladder search: when it
  // left no candidate, the search finds no lobe again.
  const auto& allowed = p.scene.representations;
  if (!first && p.earlier && std::find(allowed.begin(), allowed.end(), "half-angle") != allowed.end())
    throw UnsupportedError("hybrid: no lobe meets target " + short_number(p.material.target) + " (the half-angle candidate's search found none)");
  if (!first) {
    LobeMiss alone;
    const Eigen::MatrixXd none = Eigen::MatrixXd::Zero(p.errors->pairs().wi.rows(), p.source.channels());
    auto fit = fit_lobe(p, p.source, none, lobe_is_isotropic(p), &alone);
    if (!fit) throw UnsupportedError("hybrid: no lobe meets target " + short_number(p.material.target) + " (best " + short_number(alone.best) + ")");
    first = std::move(fit->lobe);
  }
  double best = INFINITY;  // of the hybrids tried
  if (first->rank < 2) throw UnsupportedError("hybrid: the lobe alone has rank 1, no body can lower it");
  // An isotropic body cannot take a term off an anisotropic lobe, whose extra terms carry the azimuthal
  // coupling of masking (measured: every body order and rank missed the target on GGX 0.1 x 0.3, at 40 s).
  if (!first->isotropic) throw UnsupportedError("hybrid: not offered for anisotropic lobes");
  const LadderStep step = step_of(*first);
  std::optional<MaterialCandidate> chosen;
  const BodyPairs pairs = body_pairs(p, std::min(p.scene.order_max, kHybridOrders[std::size(kHybridOrders) - 1]));
  for (int order : kHybridOrders) {
    if (order > p.scene.order_max) break;
    const int kept = isotropic_mode_count(order);
    // From one term fewer than the lobe alone down to kHybridRankDrop fewer, while the target is met.
    for (int rank = first->rank - 1; rank >= std::max(1, first->rank - kHybridRankDrop); --rank) {
      Spectrum body = fit_body(p, pairs, nullptr, order);
      std::optional<LobeFit> lobe;  // the best pair over the rounds
      Spectrum kept_body;
      const int rounds = measured_data(p) ? kMeasuredHybridRounds : kHybridRounds;
      for (int round = 0; round < rounds; ++round) {
        const Spectrum s = body;
        const auto body_values = [s](const RowMatrix3d& wi, const RowMatrix3d& wr) { return evaluate_material(s, std::nullopt, wi, wr); };
        auto next = fit_lobe_at(p, ResidualSource(p.source, body_values), p.errors->modes_values(s.channels, s.order),
                                first->isotropic, step, rank);
        if (!next) break;
        const bool better = !lobe || next->error.l2 < lobe->error.l2;
        if (better) lobe = next, kept_body = body;
        if (!better || lobe->error.l2 <= kHybridSettled * p.material.target) break;  // no progress, or settled
        body = fit_body(p, pairs, &next->lobe, order);
      }
      if (!lobe) break;
      best = std::min(best, lobe->error.l2);
      if (lobe->error.l2 > p.material.target) break;  // fewer terms will not do better
      kept_body.source = p.source.spec();
      MaterialCandidate c = lobe_candidate(p, "hybrid", kept_body, std::move(*lobe), -1, modes_bytes(kept_body, kept), kept);
      if (!chosen || c.bytes < chosen->bytes) chosen = std::move(c);
    }
  }
  if (!chosen)
    throw UnsupportedError("hybrid: target " + short_number(p.material.target) + " not met below the lobe's rank " +
                           std::to_string(first->rank) + ": best relative L2 error " + short_number(best));
  return std::move(*chosen);
}

}  // namespace icobrdf
