#include "icobrdf/lab/hard_cases.hpp"

#include <fmt/core.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "icobrdf/core/spectrum/analytic_spectra.hpp"
#include "icobrdf/core/basis/direction.hpp"
#include "icobrdf/core/projection/discrete_basis.hpp"
#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/models/fresnel.hpp"
#include "icobrdf/core/basis/hemisphere_basis.hpp"
#include "icobrdf/core/projection/lut.hpp"
#include "icobrdf/core/models/model_registry.hpp"
#include "icobrdf/core/projection/projection.hpp"
#include "icobrdf/core/fit/spectral_fit.hpp"
#include "icobrdf/core/spectrum/spectrum_ops.hpp"
#include "icobrdf/core/projection/streaming_projection.hpp"
#include "icobrdf/lab/basis_orthonormality.hpp"
#include "icobrdf/lab/order_chart.hpp"
#include "icobrdf/lab/report_format.hpp"
#include "icobrdf/lab/zernike_reference.hpp"
#include "icobrdf/mesh/tessellation.hpp"
#include "icobrdf/plot/line_chart.hpp"

namespace icobrdf::lab {
namespace {

// Unit roundoff of float32 (round to nearest): |fl(x) - x| <= u |x|.
constexpr double kFloat32Roundoff = 0x1p-24;

// ---------------------------------------------------------------------------------------------------
// Shared: held-out direction pairs and region errors.
struct Pairs {
  RowMatrix3d wi, wr;
};
Pairs make_pairs(const std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>>& v) {
  Pairs p;
  p.wi.resize(static_cast<Eigen::Index>(v.size()), 3);
  p.wr.resize(static_cast<Eigen::Index>(v.size()), 3);
  for (size_t k = 0; k < v.size(); ++k) {
    p.wi.row(static_cast<Eigen::Index>(k)) = v[k].first.transpose();
    p.wr.row(static_cast<Eigen::Index>(k)) = v[k].second.transpose();
  }
  return p;
}
Eigen::VectorXd eval_model(const BrdfModel& m, const Pairs& p) {
  Eigen::MatrixXd out(p.wi.rows(), m.channels());
  m.eval(p.wi, p.wr, out);
  return out.col(0);
}
// sqrt(sum (a - b)^2 / sum b^2)
double rel_rms(const Eigen::VectorXd& a, const Eigen::VectorXd& b) { return (a - b).norm() / b.norm(); }

// ---------------------------------------------------------------------------------------------------
// 2. Delta BRDFs. For the mirror, C = D G^-1 (D = diag((-1)^l)), for the retroreflector C = G^-1; with
// G = I + E, |C - D|_max <= ||G^-1 - I||_2 <= ||E||_2 / (1 - ||E||_2) (tests/mesh/test_discrete_spectra.cpp).
nlohmann::json delta_case(int level, int scan_order, std::vector<std::string>& row) {
  const Grid g = build_equal_area_grid(level);
  const auto full = build_discrete_basis(g, scan_order);
  const int order = std::max(0, largest_supported_order(full, kDefaultGramTolerance));
  const int m = hemisphere_basis_count(order);
  DiscreteBasis b;
  b.order = order;
  b.B = full.B.leftCols(m);
  b.W = full.W;
  b.G = full.G.topLeftCorner(m, m);
  b.gram_error = (b.G - Eigen::MatrixXd::Identity(m, m)).cwiseAbs().maxCoeff();
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(b.G - Eigen::MatrixXd::Identity(m, m), Eigen::EigenvaluesOnly);
  const double e2 = eig.eigenvalues().cwiseAbs().maxCoeff();
  const double bound = e2 / (1.0 - e2);
  const auto p = make_projection(b);
  const double mirror = (delta_projection({DeltaPart::Mirror, 1.0}, g, p) - mirror_g_coefficients(order)).cwiseAbs().maxCoeff();
  const double retro = (delta_projection({DeltaPart::Retroreflector, 1.0}, g, p) - retroreflector_g_coefficients(order)).cwiseAbs().maxCoeff();
  row = {std::to_string(level), std::to_string(g.cells()), std::to_string(order), sci(b.gram_error), sci(e2), sci(bound),
         sci(mirror), sci(retro), fixed(std::max(mirror, retro) / bound, 2)};
  return {{"level", level},          {"cells", g.cells()},  {"order", order},   {"gram_error", b.gram_error},
          {"gram_error_2norm", e2},  {"bound", bound},      {"mirror_error", mirror}, {"retroreflector_error", retro}};
}

// ---------------------------------------------------------------------------------------------------
// 3. Fresnel. Independent reference: the s and p amplitude coefficients of a dielectric of index eta,
//   g = sqrt(eta^2 - 1 + c^2) = eta cos(theta_t),  r_s = (c - g)/(c + g),  r_p = (eta^2 c - g)/(eta^2 c + g),
//   F = (r_s^2 + r_p^2)/2;  F(1) = ((eta - 1)/(eta + 1))^2 exactly, F(0) = 1.
double fresnel_sp(double c, double eta) {
  const double g = std::sqrt(eta * eta - 1.0 + c * c);
  const double rs = (c - g) / (c + g), rp = (eta * eta * c - g) / (eta * eta * c + g);
  return 0.5 * (rs * rs + rp * rp);
}

nlohmann::json fresnel_cases(bool quick, std::string& md) {
  nlohmann::json j;
  const double eta = 1.5;
  const std::vector<double> angles = {0.0, 30.0, 60.0, 80.0, 85.0, 89.0, 89.9, 89.99, 90.0};
  std::vector<std::vector<std::string>> frows;
  nlohmann::json jf = nlohmann::json::array();
  double worst_rel = 0.0;
  for (double a : angles) {
    const double c = a == 90.0 ? 0.0 : std::cos(a * M_PI / 180.0);
    const double f = fresnel_dielectric(c, eta), ref = fresnel_sp(c, eta), sch = fresnel_schlick(c, std::pow((eta - 1) / (eta + 1), 2));
    const double rel = std::abs(f - ref) / ref;
    worst_rel = std::max(worst_rel, rel);
    frows.push_back({fixed(a, 2), fmt::format("{:.6e}", c), fmt::format("{:.15f}", f), sci(rel), fmt::format("{:.6f}", sch)});
    jf.push_back({{"theta_deg", a}, {"cos", c}, {"dielectric", f}, {"reference_sp", ref}, {"relative_difference", rel}, {"schlick", sch}});
  }
  j["fresnel"] = jf;
  j["fresnel_normal_expected"] = std::pow((eta - 1) / (eta + 1), 2);
  j["fresnel_max_relative_difference"] = worst_rel;

  // Model values at grazing and normal incidence: finite, >= 0, reciprocal.
  const std::string spec = "ggx:alpha=0.5,fresnel=dielectric,ior=1.5";
  const auto model = parse_model(spec);
  const std::vector<double> thetas = {0.0, 45.0, 80.0, 85.0, 89.0, 89.9};
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> v;
  for (double ti : thetas)
    for (double tr : thetas)
      for (double dphi : {0.0, 90.0, 180.0}) v.push_back({direction_from_angles(ti * M_PI / 180, 0.3), direction_from_angles(tr * M_PI / 180, 0.3 + dphi * M_PI / 180)});
  const Pairs p = make_pairs(v);
  const Pairs q{p.wr, p.wi};
  const Eigen::VectorXd f = eval_model(*model, p), fs = eval_model(*model, q);
  const bool finite = f.allFinite() && fs.allFinite() && f.minCoeff() >= 0.0;
  const double recip = (f - fs).cwiseAbs().maxCoeff() / f.cwiseAbs().maxCoeff();
  j["model"] = spec;
  j["model_values_finite_nonnegative"] = finite;
  j["model_pairs"] = f.size();
  j["model_max"] = f.maxCoeff();
  j["reciprocity_max_relative"] = recip;

  // Reconstruction error by region after fitting (centre-sampled equal-area grid, least squares).
  const int level = quick ? 3 : 4, order = quick ? 6 : 8, n = quick ? 4000 : 20000;
  auto grid = std::make_shared<const Grid>(build_fitting_grid(level, GridKind::EqualArea, true));
  const auto ctx = make_projection_context(grid, order);
  FitOptions fo;
  fo.order = order;
  const Spectrum sp = fit_model(*model, ctx, fo);
  std::mt19937_64 rng(6);
  struct Region {
    const char* name;
    double z_lo, z_hi;  // cos(theta_i) range
  };
  const Region regions[] = {{"all (uniform pairs)", 0.0, 1.0},
                            {"grazing incidence, theta_i in [80, 89.9] deg", std::cos(89.9 * M_PI / 180), std::cos(80.0 * M_PI / 180)},
                            {"normal incidence, theta_i in [0, 10] deg", std::cos(10.0 * M_PI / 180), 1.0}};
  std::vector<std::vector<std::string>> rrows;
  nlohmann::json jr = nlohmann::json::array();
  for (const auto& reg : regions) {
    std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> pv;
    for (int k = 0; k < n; ++k) pv.push_back({uniform_direction(rng, reg.z_lo, reg.z_hi), uniform_direction(rng)});
    const Pairs pp = make_pairs(pv);
    const Eigen::VectorXd truth = eval_model(*model, pp), rec = evaluate_coefficients(sp.channels[0], order, pp.wi, pp.wr);
    const double e = rel_rms(rec, truth), emax = (rec - truth).cwiseAbs().maxCoeff() / truth.cwiseAbs().maxCoeff();
    rrows.push_back({reg.name, sci(e), sci(emax), sci(truth.maxCoeff())});
    jr.push_back({{"region", reg.name}, {"relative_rms_error", e}, {"relative_max_error", emax}, {"model_max", truth.maxCoeff()}, {"pairs", n}});
  }
  j["reconstruction"] = {{"level", level}, {"order", order}, {"cells", grid->cells()}, {"regions", jr}};

  md += fmt::format(
      "### Fresnel at grazing and normal incidence\n\n"
      "Exact dielectric reflectance (eta = {}) against the s/p amplitude formulas r_s = (c - g)/(c + g), "
      "r_p = (eta^2 c - g)/(eta^2 c + g), F = (r_s^2 + r_p^2)/2 (expected: rounding; F(1) = ((eta - 1)/(eta + 1))^2 "
      "= 0.04, F(0) = 1), with Schlick's approximation for comparison:\n\n",
      eta);
  md += md_table({"theta [deg]", "cos theta", "F dielectric", "rel. diff. to s/p", "Schlick"}, frows);
  md += fmt::format(
      "Model `{}` at {} pairs with theta_i, theta_r in {{0, 45, 80, 85, 89, 89.9}} deg and dphi in {{0, 90, 180}} deg: "
      "all values finite and >= 0: {}; reciprocity max|f(i,r) - f(r,i)| / max f = {} (expected: rounding).\n\n"
      "Reconstruction after fitting at level {} (centre-sampled, {} cells), order {}, against the model at {} "
      "held-out pairs per region (theta_r uniform):\n\n",
      spec, f.size(), finite ? "yes" : "NO", sci(recip), level, grid->cells(), order, n);
  md += md_table({"region", "relative RMS error", "max error / max f", "max f"}, rrows);
  return j;
}

// ---------------------------------------------------------------------------------------------------
// 4. Dynamic range: f = w lambert + phong(n = 20), w chosen so that the Lambertian level w/pi is 1e-4 of the
// lobe's peak (n + 2)/(2 pi) (reached in the mirror direction at every incidence). A reciprocal Phong lobe
// because its peak is the same at every incidence and its tail cos^n vanishes beyond 90 deg from the mirror
// direction; a GGX lobe has neither: its tail D(90 deg)/D(0) = alpha^4 (1.6e-3 at alpha 0.2) stays above
// 1e-4 of the peak everywhere, and its values grow towards grazing as 1/(cos_i cos_r). The reconstruction of order N has
// a truncation error spread over the whole domain (ringing); if its size in the lobe, |e_lobe|, exceeds the
// background level, the background is swamped. Expected background relative error ~ RMS |e| / background.
constexpr double kDynamicRange = 1e4;
constexpr int kLobeExponent = 20;
// Half-angle of the cone around the mirror direction where half the held-out pairs lie [rad]:
// cos^20(0.6) = 4.6e-4, the cone covers the lobe down to its 1e-3 level.
constexpr double kLobeCone = 0.6;

nlohmann::json dynamic_range(bool quick, std::string& md) {
  const auto lobe_model = std::shared_ptr<const BrdfModel>(parse_model("phong:n=" + std::to_string(kLobeExponent)));
  const auto lambert = std::shared_ptr<const BrdfModel>(parse_model("lambert"));
  const Eigen::Vector3d nz(0, 0, 1);
  const double peak = lobe_model->eval(nz, nz);
  const double background = peak / kDynamicRange;
  const double w = background * M_PI;  // lambert = 1/pi
  const SumModel model({{w, lambert}, {1.0, lobe_model}});
  const int level = quick ? 3 : 4;
  const std::vector<int> orders = quick ? std::vector<int>{4, 6} : std::vector<int>{4, 8, 11};
  const int n = quick ? 4000 : 20000;
  // Held-out pairs: half uniform, half near the specular direction (cone of half-angle kLobeCone rad).
  std::mt19937_64 rng(7);
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> v;
  for (int k = 0; k < n; ++k) v.push_back({uniform_direction(rng), uniform_direction(rng)});
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int k = 0; k < n; ++k) {
    const Eigen::Vector3d wi = uniform_direction(rng, 0.5, 1.0);
    const Eigen::Vector3d m = mirror_direction(wi);
    const Eigen::Vector3d a = m.unitOrthogonal(), b = m.cross(a);
    const double ang = kLobeCone * std::sqrt(u(rng)), az = 2.0 * M_PI * u(rng);
    Eigen::Vector3d wr = std::cos(ang) * m + std::sin(ang) * (std::cos(az) * a + std::sin(az) * b);
    if (wr.z() < 0.0) wr.z() = -wr.z();
    v.push_back({wi, wr.normalized()});
  }
  const Pairs p = make_pairs(v);
  const Eigen::VectorXd truth = eval_model(model, p), lobe_part = eval_model(*lobe_model, p);
  std::vector<Eigen::Index> lobe, bg;
  for (Eigen::Index k = 0; k < truth.size(); ++k) {
    if (lobe_part[k] >= 0.1 * peak) lobe.push_back(k);      // lobe region: the lobe term above 10% of its peak
    if (lobe_part[k] <= 0.1 * background) bg.push_back(k);  // background: the Lambertian term dominates 10:1
  }
  auto grid = std::make_shared<const Grid>(build_fitting_grid(level, GridKind::EqualArea, true));
  std::vector<std::vector<std::string>> rows;
  nlohmann::json jo = nlohmann::json::array();
  for (int order : orders) {
    const auto ctx = make_projection_context(grid, order);
    FitOptions fo;
    fo.order = order;
    const Spectrum sp = fit_model(model, ctx, fo);
    const Eigen::VectorXd rec = evaluate_coefficients(sp.channels[0], order, p.wi, p.wr);
    const auto region_error = [&](const std::vector<Eigen::Index>& idx, double& rms_abs) {
      double se = 0.0, st = 0.0;
      for (auto k : idx) {
        se += (rec[k] - truth[k]) * (rec[k] - truth[k]);
        st += truth[k] * truth[k];
      }
      rms_abs = idx.empty() ? 0.0 : std::sqrt(se / idx.size());
      return idx.empty() ? std::numeric_limits<double>::quiet_NaN() : std::sqrt(se / st);
    };
    double lobe_abs = 0.0, bg_abs = 0.0;
    const double e_lobe = region_error(lobe, lobe_abs), e_bg = region_error(bg, bg_abs);
    double bg_min = std::numeric_limits<double>::infinity();
    Eigen::Index negative = 0;
    for (auto k : bg) {
      bg_min = std::min(bg_min, rec[k]);
      negative += rec[k] < 0.0;
    }
    const double predicted = lobe_abs / background;  // ringing of the lobe's size measured against the background
    const double all_min = rec.minCoeff();
    rows.push_back({std::to_string(order), sci(e_lobe), sci(lobe_abs / peak), sci(e_bg), sci(predicted), sci(bg_min / background),
                    fixed(100.0 * negative / std::max<size_t>(1, bg.size()), 1) + "%", sci(all_min / peak)});
    jo.push_back({{"order", order},
                  {"lobe_relative_rms_error", num(e_lobe)},
                  {"lobe_rms_abs_error_over_peak", lobe_abs / peak},
                  {"background_relative_rms_error", num(e_bg)},
                  {"background_rms_abs_error", bg_abs},
                  {"predicted_background_relative_error", predicted},
                  {"background_min_over_background", num(bg_min / background)},
                  {"background_negative_fraction", bg.empty() ? 0.0 : static_cast<double>(negative) / bg.size()},
                  {"min_over_peak", all_min / peak},
                  {"gram_error", ctx.basis.gram_error}});
  }
  md += fmt::format(
      "### Dynamic range 1e4 between lobe and background\n\n"
      "f = {:.4g} lambert + phong (n = {}): the Lambertian level {:.4g} /sr is 1e-4 of the lobe's peak {:.4g} /sr "
      "(the mirror direction, at every incidence). Fitted at level {} (centre-sampled, {} cells); {} held-out pairs "
      "(half uniform, half within {} rad of the mirror direction): {} in the lobe region (lobe term >= 10% of its peak), "
      "{} in the background region (lobe term <= 10% of the background). A reciprocal Phong lobe because its "
      "peak is the same at every incidence and its tail vanishes; a GGX lobe's tail, alpha^4 of its peak at a "
      "half-angle of 90 deg, stays above 1e-4 of the peak everywhere. Expected: the truncation error of the "
      "lobe rings over the whole domain, so the background's relative error is up to about the lobe's RMS absolute "
      "error divided by the background level (column 'predicted'; it decays away from the lobe, so the measured error is lower).\n\n",
      w, kLobeExponent, background, peak, level, grid->cells(), 2 * n, kLobeCone, lobe.size(), bg.size());
  md += md_table({"order", "lobe rel. RMS error", "lobe RMS error / peak", "background rel. RMS error", "predicted", "background min / background",
                  "background < 0", "min f / peak"},
                 rows);
  return {{"peak", peak},
          {"background", background},
          {"lambert_weight", w},
          {"level", level},
          {"cells", grid->cells()},
          {"lobe_pairs", lobe.size()},
          {"background_pairs", bg.size()},
          {"orders", jo}};
}

// ---------------------------------------------------------------------------------------------------
// 5. float32 vs float64 LUTs. F32 = fl32(F), |dF_ir| <= u |F_ir|. With the weighted norm
// ||F||_W^2 = sum Omega_i Omega_r F_ir^2 and A = W^-1/2 P, C = A^T (W^1/2 F W^1/2) A and
// ||A||_2^2 = lambda_max(P^T W^-1 P) = lambda_max(G^-1) = 1/lambda_min(G), so
//   ||dC||_F <= ||dF||_W / lambda_min(G) <= u ||F||_W / lambda_min(G);
// the reconstruction F' = B C B^T has ||W^1/2 B||_2^2 = lambda_max(G), so ||dF'||_W <= kappa(G) ||dF||_W.
// Independent roundings of random sign shrink this: projecting onto M^2 of cells^2 dimensions keeps
// about (M / cells)^2 of the squared norm, an estimate ||dF||_W M / (cells lambda_min).
nlohmann::json float32_case(int level, int order, std::vector<std::string>& row) {
  const auto model = parse_model("ggx:alpha=0.2");
  const Grid g = build_fitting_grid(level, GridKind::EqualArea, true);
  const auto b = build_discrete_basis(g, order);
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(b.G, Eigen::EigenvaluesOnly);
  const double lmin = eig.eigenvalues().minCoeff(), lmax = eig.eigenvalues().maxCoeff();
  const auto p = make_projection(b);
  const Eigen::MatrixXd f = build_lut(*model, g, false, LutSampling::CellCentre).channels[0];
  const Eigen::MatrixXd f32 = f.cast<float>().cast<double>();
  const Eigen::VectorXd& om = b.W;
  const auto wnorm = [&](const Eigen::MatrixXd& x) { return (om.cwiseSqrt().asDiagonal() * x * om.cwiseSqrt().asDiagonal()).norm(); };
  const double nf = wnorm(f), ndf = wnorm(f32 - f);
  const Eigen::MatrixXd c = project_lut(p, f), c32 = project_lut(p, f32);
  const double nc = c.norm(), ndc = (c32 - c).norm();
  const Eigen::MatrixXd r = reconstruct_lut(b, c), r32 = reconstruct_lut(b, c32);
  const double nr = wnorm(r), ndr = wnorm(r32 - r);
  const double lut_rel = ndf / nf;
  const double c_rel = ndc / nc, c_bound = kFloat32Roundoff * nf / (lmin * nc), c_post = ndf / (lmin * nc);
  const double c_estimate = ndf * b.modes() / (static_cast<double>(g.cells()) * lmin * nc);
  const double r_rel = ndr / nr, r_bound = kFloat32Roundoff * (lmax / lmin) * nf / nr;
  row = {std::to_string(level), std::to_string(order), sci(b.gram_error), fixed(lmax / lmin, 3), sci(lut_rel), sci(c_rel), sci(c_estimate),
         sci(c_bound), sci(r_rel), sci(r_bound)};
  return {{"level", level},
          {"cells", g.cells()},
          {"order", order},
          {"modes", b.modes()},
          {"gram_error", b.gram_error},
          {"lambda_min", lmin},
          {"lambda_max", lmax},
          {"condition", lmax / lmin},
          {"lut_relative_rounding", lut_rel},
          {"spectrum_relative_error", c_rel},
          {"spectrum_random_estimate", c_estimate},
          {"spectrum_a_posteriori_bound", c_post},
          {"spectrum_bound", c_bound},
          {"reconstruction_relative_error", r_rel},
          {"reconstruction_bound", r_bound}};
}

void add_delta_cases(const SectionOptions& o, ReportSection& s, std::string& md) {
  std::vector<int> levels;
  for (int L : o.levels)
    if (L >= 1 && L <= 6) levels.push_back(L);
  if (levels.empty()) throw ArgumentError("hard-cases: delta BRDFs need a level in [1, 6]");
  std::vector<std::vector<std::string>> rows;
  nlohmann::json jd = nlohmann::json::array();
  for (int L : levels) {
    std::vector<std::string> row;
    jd.push_back(delta_case(L, L <= 2 ? 12 : 24, row));
    rows.push_back(row);
  }
  s.data["delta"] = jd;
  md += "### Delta BRDFs\n\n"
        "Ideal mirror and retroreflector (g form) projected exactly on the equal-area grid (delta_projection) at "
        "the largest order each level supports (Gram tolerance 0.1), against the analytic spectra D = diag((-1)^l) "
        "and I. Since C = D G^-1 (resp. G^-1), every entry's error is at most ||G - I||_2 / (1 - ||G - I||_2).\n\n";
  md += md_table({"level", "cells", "order", "max|G - I|", "||G - I||_2", "bound", "mirror max error", "retro max error", "error / bound"}, rows);
}

void add_dynamic_range(const SectionOptions& o, ReportSection& s, std::string& md) {
  s.data["dynamic_range"] = dynamic_range(o.quick, md);
  if (!o.report_dir.empty()) {
    plot::Series lobe{"lobe, relative RMS error", {}, {}}, bg{"background, relative RMS error", {}, {}}, pred{"lobe RMS error / background", {}, {}};
    pred.dashed = true;
    for (const auto& r : s.data["dynamic_range"]["orders"]) {
      const double n = r["order"].get<double>();
      lobe.x.push_back(n);
      lobe.y.push_back(r["lobe_relative_rms_error"].is_null() ? std::nan("") : r["lobe_relative_rms_error"].get<double>());
      bg.x.push_back(n);
      bg.y.push_back(r["background_relative_rms_error"].is_null() ? std::nan("") : r["background_relative_rms_error"].get<double>());
      pred.x.push_back(n);
      pred.y.push_back(r["predicted_background_relative_error"].get<double>());
    }
    const plot::ChartOptions co = order_chart("Dynamic range 1e4: error by region", "relative RMS error");
    const std::string file = "hard_cases_dynamic_range.png";
    plot::draw_line_chart({lobe, bg, pred}, co, (o.report_dir / file).string());
    s.figures.push_back(file);
    md += "![" + file + "](" + file + ")\n\n";
  }
}

void add_float32_cases(const SectionOptions& o, ReportSection& s, std::string& md) {
  struct Case {
    int level, order;
  };
  const std::vector<Case> cases = o.quick ? std::vector<Case>{{2, 4}, {3, 6}, {3, 12}} : std::vector<Case>{{3, 6}, {3, 12}, {4, 8}};
  std::vector<std::vector<std::string>> rows;
  nlohmann::json jf = nlohmann::json::array();
  for (const auto& c : cases) {
    std::vector<std::string> row;
    jf.push_back(float32_case(c.level, c.order, row));
    rows.push_back(row);
  }
  s.data["float32"] = jf;
  md += fmt::format(
      "### float32 vs float64 LUTs\n\n"
      "The LUT of ggx (alpha 0.2), centre-sampled on the equal-area grid, rounded to float32 and projected "
      "(least squares) like the float64 one. Rounding to nearest gives |dF| <= u |F| entrywise with u = 2^-24 = "
      "{:.3g}; through C = P^T F P this becomes ||dC||_F <= u ||F||_W / lambda_min(G) (rigorous bound) and "
      "through F' = B C B^T ||dF'||_W <= kappa(G) u ||F||_W: the amplification is the conditioning of G. "
      "Independent roundings of random sign keep only ~ M/cells of the norm (random estimate). Errors are "
      "relative (Frobenius norm for C, solid-angle weighted norm for the LUTs).\n\n",
      kFloat32Roundoff);
  md += md_table({"level", "order", "max|G - I|", "kappa(G)", "LUT rounding", "spectrum error", "random estimate", "bound",
                  "reconstruction error", "bound"},
                 rows);
}

}  // namespace

ReportSection run_hard_cases(const SectionOptions& o) {
  ReportSection s;
  s.title = "Numerical stability on hard cases";
  std::string md;
  add_orthonormality(o, s, md);
  add_zernike_reference(o, s, md);
  add_delta_cases(o, s, md);
  s.data["fresnel"] = fresnel_cases(o.quick, md);
  add_dynamic_range(o, s, md);
  add_float32_cases(o, s, md);
  s.markdown = md;
  return s;
}

}  // namespace icobrdf::lab
