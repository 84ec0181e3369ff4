#include "icobrdf/core/models/model_registry.hpp"

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <map>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/support/text.hpp"
#include "icobrdf/core/models/hapke.hpp"
#include "icobrdf/core/models/kernel_models.hpp"
#include "icobrdf/core/models/lambert_models.hpp"
#include "icobrdf/core/models/lobe_models.hpp"
#include "icobrdf/core/models/microfacet.hpp"

namespace icobrdf {

namespace {

using Values = std::vector<double>;  // parameter values in registry order
using Factory = std::function<std::unique_ptr<BrdfModel>(const Values&)>;

struct Entry {
  ModelInfo info;
  Factory make;
};

ModelParameter number(std::string name, double def, double lo, double hi, std::string meaning, std::string unit = "") {
  return {std::move(name), def, lo, hi, std::move(meaning), std::move(unit), {}};
}
ModelParameter choice(std::string name, std::vector<std::string> choices, int def, std::string meaning) {
  const double hi = static_cast<double>(choices.size()) - 1.0;
  return {std::move(name), static_cast<double>(def), 0.0, hi, std::move(meaning), "", std::move(choices)};
}

constexpr double kMaxExponent = 1e4;  // lobe exponents beyond this are numerically deltas
// Bound of the weights of the remote-sensing models: MODIS stores kernel weights up to 32.766; 100 leaves room
// for any fit of a reflectance factor while refusing typing errors.
constexpr double kMaxKernelWeight = 100.0;
// Henyey-Greenstein asymmetry bound: (1 - T^2)/(1 + T)^3 grows without bound as |T| -> 1.
constexpr double kMaxHgAsymmetry = 0.99;

std::vector<ModelParameter> microfacet_tail() {
  return {choice("fresnel", {"schlick", "dielectric", "none"}, 0,
                 "Fresnel factor: Schlick with f0, exact unpolarized dielectric with ior, or none (F = 1)"),
          number("f0", 0.04, 0.0, 1.0, "reflectance at normal incidence (fresnel=schlick)"),
          number("ior", 1.5, 1.0, 4.0, "relative index of refraction (fresnel=dielectric)"),
          choice("masking", {"correlated", "separable"}, 0,
                 "Smith masking-shadowing: height-correlated G2 = 1/(1+L_i+L_r) or separable G1 G1")};
}

MicrofacetParams microfacet_params(MicrofacetDistribution dist, bool aniso, const Values& v) {
  MicrofacetParams p;
  p.distribution = dist;
  p.anisotropic = aniso;
  std::size_t k = 0;
  if (aniso) {
    p.alpha_x = v[k++];
    p.alpha_y = v[k++];
    p.azimuth_deg = v[k++];
  } else {
    p.alpha_x = p.alpha_y = v[k++];
  }
  p.fresnel = static_cast<FresnelMode>(static_cast<int>(v[k++]));
  p.f0 = v[k++];
  p.ior = v[k++];
  p.masking = static_cast<SmithMasking>(static_cast<int>(v[k++]));
  return p;
}

std::vector<ModelParameter> concat(std::vector<ModelParameter> a, const std::vector<ModelParameter>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

const std::vector<Entry>& entries() {
  static const std::vector<Entry> table = [] {
    std::vector<Entry> t;
    t.push_back({{"lambert", "Lambertian diffuser f = albedo/pi",
                  {number("albedo", 1.0, 0.0, 1.0, "directional albedo (same at every incidence)")}, true, ""},
                 [](const Values& v) { return std::make_unique<LambertModel>(v[0]); }});
    t.push_back({{"minnaert", "Minnaert f = (k+1)/(2 pi) (cos ti cos tr)^(k-1) (K&vD eq. 35); albedo cos(ti)^(k-1)",
                  {number("k", 2.0, 0.0, 100.0, "exponent (integer or real); k = 1 is Lambert, k < 1 diverges at grazing")},
                  false, "k >= 1"},
                 [](const Values& v) { return std::make_unique<MinnaertModel>(v[0]); }});
    t.push_back({{"phong", "reciprocal Phong lobe ks (n+2)/(2 pi) cos^n(angle to the mirror direction)",
                  {number("n", 20.0, 0.0, kMaxExponent, "lobe exponent"),
                   number("ks", 1.0, 0.0, 1.0, "directional albedo at normal incidence")},
                  true, ""},
                 [](const Values& v) { return std::make_unique<PhongModel>(v[0], v[1]); }});
    t.push_back({{"blinn-phong", "reciprocal Blinn-Phong lobe ks N(n) cos^n(theta_h), albedo ks at normal incidence",
                  {number("n", 50.0, 0.0, kMaxExponent, "lobe exponent"),
                   number("ks", 1.0, 0.0, 1.0, "directional albedo at normal incidence")},
                  true, ""},
                 [](const Values& v) { return std::make_unique<BlinnPhongModel>(v[0], v[1]); }});
    t.push_back({{"ggx", "Cook-Torrance microfacets, GGX distribution, Smith masking, Fresnel",
                  concat({number("alpha", 0.3, 1e-3, 4.0, "GGX roughness (slope scale)")}, microfacet_tail()), true, ""},
                 [](const Values& v) {
                   return std::make_unique<MicrofacetModel>(microfacet_params(MicrofacetDistribution::Ggx, false, v));
                 }});
    t.push_back({{"beckmann", "Cook-Torrance microfacets, Beckmann distribution, Smith masking, Fresnel",
                  concat({number("alpha", 0.3, 1e-3, 4.0, "Beckmann roughness (rms slope)")}, microfacet_tail()), true, ""},
                 [](const Values& v) {
                   return std::make_unique<MicrofacetModel>(microfacet_params(MicrofacetDistribution::Beckmann, false, v));
                 }});
    t.push_back({{"ggx-aniso", "anisotropic GGX microfacets (reciprocal, not isotropic unless alpha_x = alpha_y)",
                  concat({number("alpha_x", 0.1, 1e-3, 4.0, "roughness along the tangent x axis"),
                          number("alpha_y", 0.4, 1e-3, 4.0, "roughness along the tangent y axis"),
                          number("azimuth", 0.0, -360.0, 360.0, "azimuth of the tangent x axis from +x", "deg")},
                         microfacet_tail()),
                  true, ""},
                 [](const Values& v) {
                   return std::make_unique<MicrofacetModel>(microfacet_params(MicrofacetDistribution::Ggx, true, v));
                 }});
    t.push_back({{"oren-nayar", "qualitative Oren-Nayar rough diffuser",
                  {number("sigma", 20.0, 0.0, 90.0, "standard deviation of the facet slope angle", "deg"),
                   number("albedo", 1.0, 0.0, 1.0, "albedo of the facets")},
                  false, "albedo <= 0.985 (max directional albedo 1.015 x albedo, near sigma = 11 deg at grazing incidence)"},
                 [](const Values& v) { return std::make_unique<OrenNayarModel>(v[0], v[1]); }});
    t.push_back({{"lafortune", "Lafortune generalized cosine lobe max(0, wi^T Q^T diag(cx,cy,cz) Q wr)^n",
                  {number("cx", -1.0, -10.0, 10.0, "lobe matrix entry along the rotated x axis"),
                   number("cy", -1.0, -10.0, 10.0, "lobe matrix entry along the rotated y axis"),
                   number("cz", 1.0, -10.0, 10.0, "lobe matrix entry along the normal"),
                   number("n", 20.0, 0.0, kMaxExponent, "lobe exponent"),
                   number("azimuth", 0.0, -360.0, 360.0, "rotation Q of the lobe frame about the normal", "deg")},
                  false, "unnormalized; cx = cy = -cz = -c: albedo 2 pi c^n/(n+2) at normal incidence"},
                 [](const Values& v) { return std::make_unique<LafortuneModel>(v[0], v[1], v[2], v[3], v[4]); }});
    t.push_back({{"hapke", "Hapke 2012 with isotropic particles: exact Chandrasekhar H, opposition surge B0/(1 + tan(g/2)/h), "
                           "macroscopic roughness theta; b0 = theta = 0: w/(4 pi) H(mi) H(mr)/(mi+mr); reciprocal",
                  {number("w", 0.8, 0.0, 1.0, "single-scattering albedo"),
                   number("b0", 0.0, 0.0, 10.0, "amplitude B0 of the shadow-hiding opposition surge"),
                   number("h", 0.05, 1e-6, 10.0, "angular width h of the opposition surge"),
                   number("theta", 0.0, 0.0, 60.0, "mean slope angle theta-bar of the macroscopic roughness", "deg")},
                  false, "b0 = 0 and theta = 0"},
                 [](const Values& v) { return std::make_unique<HapkeModel>(v[0], v[1], v[2], v[3]); }});
    t.push_back({{"lommel-seeliger", "Lommel-Seeliger single scattering w/(4 pi (cos ti + cos tr))",
                  {number("w", 1.0, 0.0, 1.0, "single-scattering albedo")}, true, ""},
                 [](const Values& v) { return std::make_unique<LommelSeeligerModel>(v[0]); }});
    // Remote sensing's models (icobrdf/core/models/kernel_models.hpp: formulas, sources, conventions).
    t.push_back({{"ross-li", "MODIS kernel-driven f = (iso + vol K_vol + geo K_geo)/pi, Ross-Thick/Thin and Li-Sparse/Dense-R kernels (h/b 2, b/r 1); reciprocal",
                  {number("iso", 0.1, -kMaxKernelWeight, kMaxKernelWeight, "isotropic weight (BRF of the isotropic kernel)"),
                   number("vol", 0.05, -kMaxKernelWeight, kMaxKernelWeight, "volumetric kernel weight"),
                   number("geo", 0.0, -kMaxKernelWeight, kMaxKernelWeight, "geometric-optical kernel weight (f < 0 near grazing when > 0)"),
                   choice("volume", {"thick", "thin"}, 0, "volumetric kernel: Ross-Thick or Ross-Thin"),
                   choice("geometric", {"sparse", "dense"}, 0, "geometric kernel: Li-Sparse-R or Li-Dense-R")},
                  false, "the white-sky albedo iso + 0.189184 vol - 1.377622 geo (thick, sparse) is <= 1 and f >= 0 (geo > 0 makes f < 0 near grazing)"},
                 [](const Values& v) {
                   return std::make_unique<RossLiModel>(v[0], v[1], v[2], static_cast<VolumeKernel>(static_cast<int>(v[3])),
                                                        static_cast<GeometricKernel>(static_cast<int>(v[4])));
                 }});
    t.push_back({{"rpv", "Rahman-Pinty-Verstraete BRF/pi with Henyey-Greenstein phase and hot spot; reciprocal",
                  {number("rho0", 0.1, 0.0, 10.0, "amplitude (BRF scale)"),
                   number("k", 0.8, 0.0, 3.0, "Minnaert-like exponent (k < 1: bowl-shaped, brighter at grazing)"),
                   number("theta", -0.1, -kMaxHgAsymmetry, kMaxHgAsymmetry, "Henyey-Greenstein asymmetry (< 0: backward)"),
                   number("rhoc", 0.1, 0.0, 10.0, "hot-spot parameter (rhoc = rho0 in the 3-parameter form)")},
                  false, "rho0 is small enough for the shape (k < 1 diverges at grazing)"},
                 [](const Values& v) { return std::make_unique<RpvModel>(v[0], v[1], v[2], v[3]); }});
    t.push_back({{"walthall", "Walthall BRF/pi in Nilson-Kuusk's reciprocal form a (ti^2+tr^2) + b ti^2 tr^2 + c ti tr cos(raa) + d (radians)",
                  {number("a", 0.01, -kMaxKernelWeight, kMaxKernelWeight, "weight of sza^2 + vza^2"),
                   number("b", 0.0, -kMaxKernelWeight, kMaxKernelWeight, "weight of sza^2 vza^2"),
                   number("c", -0.01, -kMaxKernelWeight, kMaxKernelWeight, "weight of sza vza cos(raa)"),
                   number("d", 0.1, -kMaxKernelWeight, kMaxKernelWeight, "BRF at the normal")},
                  false, "the weights keep f >= 0 and the albedo <= 1"},
                 [](const Values& v) { return std::make_unique<WalthallModel>(v[0], v[1], v[2], v[3]); }});
    t.push_back({{"mirror", "ideal mirror: delta part of weight 1 (K&vD eq. 27), regular part 0", {}, true, "", true},
                 [](const Values&) { return std::make_unique<MirrorModel>(); }});
    t.push_back({{"retroreflector", "ideal retroreflector: delta part of weight 1 (K&vD eq. 31), regular part 0", {},
                  true, "", true},
                 [](const Values&) { return std::make_unique<RetroreflectorModel>(); }});
    return t;
  }();
  return table;
}

// Splits at '+' except a '+' following an exponent marker that follows a digit or '.' (1e+5, 2.E+3).
std::vector<std::string> split_terms(const std::string& s) {
  std::vector<std::string> parts;
  std::string cur;
  for (std::size_t k = 0; k < s.size(); ++k) {
    const char c = s[k];
    const bool exponent_sign = c == '+' && k >= 2 && (s[k - 1] == 'e' || s[k - 1] == 'E') &&
                               (std::isdigit(static_cast<unsigned char>(s[k - 2])) || s[k - 2] == '.');
    if (c == '+' && !exponent_sign) {
      parts.push_back(cur);
      cur.clear();
    } else {
      cur += c;
    }
  }
  parts.push_back(cur);
  return parts;
}

bool parse_double(const std::string& text, double& out) {
  const std::string t = trim(text);
  if (t.empty()) return false;
  char* end = nullptr;
  out = std::strtod(t.c_str(), &end);
  return end == t.c_str() + t.size() && std::isfinite(out);
}

std::string known_names() {
  std::string s;
  for (const auto& e : entries()) s += (s.empty() ? "" : ", ") + e.info.name;
  return s;
}

std::string range_text(const ModelParameter& p) {
  if (!p.choices.empty()) {
    std::string s;
    for (const auto& c : p.choices) s += (s.empty() ? "" : "|") + c;
    return s;
  }
  return "[" + format_parameter(p.min) + ", " + format_parameter(p.max) + "]";
}

std::unique_ptr<BrdfModel> parse_term(const std::string& spec, const std::string& term_text, std::size_t index,
                                      std::size_t count, double& weight) {
  // A sum names the failing term (quoted) and its place, not the whole spec: one short line at any size.
  const std::string where = count > 1 ? "model spec term " + std::to_string(index + 1) + " of " + std::to_string(count) + " '" +
                                            quoted_text(trim(term_text)) + "'"
                                      : "model spec '" + quoted_text(spec) + "'";
  std::string term = trim(term_text);
  if (term.empty()) throw ArgumentError(where + ": empty term; expected [weight*]name[:key=value,...]");
  weight = 1.0;
  const auto star = term.find('*');
  if (star != std::string::npos) {
    const std::string w = trim(term.substr(0, star));
    if (!parse_double(w, weight) || weight < 0.0)
      throw ArgumentError(where + ": weight '" + quoted_text(w) + "' is not a finite number >= 0");
    term = trim(term.substr(star + 1));
  }
  const auto colon = term.find(':');
  const std::string name = trim(term.substr(0, colon)), qname = quoted_text(name);
  const Entry* entry = nullptr;
  for (const auto& e : entries())
    if (e.info.name == name) entry = &e;
  if (!entry) throw ArgumentError(where + ": unknown model '" + qname + "'; expected one of " + known_names());
  const auto& params = entry->info.parameters;
  Values values(params.size());
  std::vector<bool> given(params.size(), false);
  for (std::size_t k = 0; k < params.size(); ++k) values[k] = params[k].default_value;
  if (colon != std::string::npos) {
    const std::string list = term.substr(colon + 1);
    std::size_t start = 0;
    while (true) {
      const auto comma = list.find(',', start);
      const std::string item = trim(list.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
      const auto eq = item.find('=');
      if (eq == std::string::npos)
        throw ArgumentError(where + ": parameter '" + quoted_text(item) + "' of '" + qname + "' is not key=value");
      const std::string key = trim(item.substr(0, eq)), text = trim(item.substr(eq + 1)), qkey = quoted_text(key);
      std::size_t idx = params.size();
      for (std::size_t k = 0; k < params.size(); ++k)
        if (params[k].name == key) idx = k;
      if (idx == params.size()) {
        std::string names;
        for (const auto& p : params) names += (names.empty() ? "" : ", ") + p.name;
        throw ArgumentError(where + ": unknown parameter '" + qkey + "' for model '" + qname + "'; expected " +
                            (names.empty() ? std::string("no parameters") : "one of " + names));
      }
      const auto& p = params[idx];
      if (given[idx]) throw ArgumentError(where + ": parameter '" + qkey + "' of '" + qname + "' given twice");
      given[idx] = true;
      if (!p.choices.empty()) {
        std::size_t c = 0;
        while (c < p.choices.size() && p.choices[c] != text) ++c;
        if (c == p.choices.size())
          throw ArgumentError(where + ": parameter '" + qkey + "' of '" + qname + "' must be one of " + range_text(p) +
                              ", got '" + quoted_text(text) + "'");
        values[idx] = static_cast<double>(c);
      } else {
        double v = 0.0;
        if (!parse_double(text, v))
          throw ArgumentError(where + ": parameter '" + qkey + "' of '" + qname + "' must be a finite number in " +
                              range_text(p) + ", got '" + quoted_text(text) + "'");
        if (v < p.min || v > p.max)
          throw ArgumentError(where + ": parameter '" + qkey + "' of '" + qname + "' must be in " + range_text(p) +
                              ", got " + quoted_text(text));
        values[idx] = v;
      }
      if (comma == std::string::npos) break;
      start = comma + 1;
    }
  }
  return entry->make(values);
}

}  // namespace

const std::vector<ModelInfo>& model_registry() {
  static const std::vector<ModelInfo> infos = [] {
    std::vector<ModelInfo> v;
    for (const auto& e : entries()) v.push_back(e.info);
    return v;
  }();
  return infos;
}

const ModelInfo* find_model_info(const std::string& name) {
  for (const auto& info : model_registry())
    if (info.name == name) return &info;
  return nullptr;
}

namespace {

std::unique_ptr<BrdfModel> parse_spec(const std::string& spec) {
  const auto texts = split_terms(spec);
  std::vector<std::pair<double, std::unique_ptr<BrdfModel>>> parsed;
  for (std::size_t k = 0; k < texts.size(); ++k) {
    double w = 1.0;
    auto m = parse_term(spec, texts[k], k, texts.size(), w);
    parsed.emplace_back(w, std::move(m));
  }
  if (parsed.size() == 1 && parsed[0].first == 1.0) return std::move(parsed[0].second);
  std::vector<SumModel::Term> terms;
  for (auto& [w, m] : parsed) terms.push_back({w, std::shared_ptr<const BrdfModel>(std::move(m))});
  return std::make_unique<SumModel>(std::move(terms));
}

}  // namespace

std::unique_ptr<BrdfModel> parse_model(const std::string& spec) {
  try {
    return parse_spec(spec);
  } catch (const ArgumentError& e) {
    throw ArgumentError(printable_text(e.what()));  // the spec is quoted: keep its control bytes off the line
  }
}


bool is_model_source(const std::string& source) { return source.rfind(kModelSourcePrefix, 0) == 0; }

std::unique_ptr<BrdfModel> parse_model_source(const std::string& source) {
  if (!is_model_source(source))
    throw ArgumentError("SOURCE '" + quoted_text(source) + "': expected model:NAME[:key=value,...]");
  return parse_model(source.substr(std::string(kModelSourcePrefix).size()));
}

}  // namespace icobrdf
