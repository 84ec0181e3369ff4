#include "icobrdf/io/scene.hpp"

#include <toml++/toml.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <algorithm>
#include <set>

#include "icobrdf/core/models/brdf_model.hpp"
#include "icobrdf/core/support/error.hpp"
#include "icobrdf/io/direction_csv.hpp"
#include "icobrdf/io/spectrum_file.hpp"

namespace icobrdf {
namespace {

[[noreturn]] void fail(const Scene& s, const std::string& where, const std::string& what) {
  throw InputError(printable_text(s.path + ": " + where + ": " + what));  // quoted file text stays on one line
}

// An integer setting as int; values beyond int's range fail instead of wrapping (2^32 + 4 is not 4).
int checked_int(const Scene& s, const std::string& where, const char* key, int64_t v) {
  if (v < std::numeric_limits<int>::min() || v > std::numeric_limits<int>::max())
    fail(s, where, std::string("'") + key + "' expected an integer of a few digits, found " + std::to_string(v));
  return static_cast<int>(v);
}

template <class T>
T get_or(const Scene& s, const toml::table& t, const std::string& where, const char* key, T fallback) {
  const toml::node* n = t.get(key);
  if (!n) return fallback;
  if constexpr (std::is_same_v<T, double>) {
    if (auto v = n->value<double>()) {
      if (std::isfinite(*v)) return *v;
      fail(s, where, std::string("'") + key + "' expected a finite number, found " + std::to_string(*v));
    }
    fail(s, where, std::string("'") + key + "' expected a number");
  } else if constexpr (std::is_same_v<T, int>) {
    if (auto v = n->value<int64_t>()) return checked_int(s, where, key, *v);
    fail(s, where, std::string("'") + key + "' expected an integer");
  } else if constexpr (std::is_same_v<T, bool>) {
    if (auto v = n->value<bool>()) return *v;
    fail(s, where, std::string("'") + key + "' expected true or false");
  } else {
    if (auto v = n->value<std::string>()) return *v;
    fail(s, where, std::string("'") + key + "' expected a string");
  }
}

// Largest |phi| of a light or camera [deg]: the direction CSV readers' bound (icobrdf/io/direction_csv.hpp).
constexpr double kMaxSceneAzimuthDeg = kMaxAzimuthTurns * 360.0;

std::vector<std::pair<double, double>> directions(const Scene& s, const toml::table& t, const std::string& where, const char* key) {
  std::vector<std::pair<double, double>> out;
  const toml::node* n = t.get(key);
  if (!n) return out;
  const auto* arr = n->as_array();
  if (!arr) fail(s, where, std::string("'") + key + "' expected an array of [theta, phi] pairs in degrees");
  for (size_t k = 0; k < arr->size(); ++k) {
    const auto* pair = (*arr)[k].as_array();
    if (!pair || pair->size() != 2 || !(*pair)[0].value<double>() || !(*pair)[1].value<double>())
      fail(s, where, std::string("'") + key + "' entry " + std::to_string(k + 1) + " expected [theta, phi] in degrees");
    const double th = *(*pair)[0].value<double>(), ph = *(*pair)[1].value<double>();
    if (!(th >= 0 && th <= 90))
      fail(s, where, std::string("'") + key + "' entry " + std::to_string(k + 1) + ": theta expected in [0, 90], found " + std::to_string(th));
    if (!(std::abs(ph) <= kMaxSceneAzimuthDeg))
      fail(s, where, std::string("'") + key + "' entry " + std::to_string(k + 1) + ": phi expected in [-" + format_parameter(kMaxSceneAzimuthDeg) +
                         ", " + format_parameter(kMaxSceneAzimuthDeg) + "] (two turns), found " + format_parameter(ph));
    out.emplace_back(th, ph);
  }
  return out;
}

// The key "max_bytes" of a [bank] or [[material]] table (an integer >= 1), `fallback` when absent.
long long max_bytes_or(const Scene& s, const toml::table& t, const std::string& where, long long fallback) {
  if (!t.get("max_bytes")) return fallback;
  const int v = get_or(s, t, where, "max_bytes", 0);
  if (v < 1) fail(s, where, "'max_bytes' expected an integer >= 1, found " + std::to_string(v));
  return v;
}

// The key "on_miss" of a [bank] or [[material]] table, `fallback` when absent.
OnMiss on_miss_or(const Scene& s, const toml::table& t, const std::string& where, OnMiss fallback) {
  const std::string v = get_or(s, t, where, "on_miss", to_string(fallback));
  if (v == "fail") return OnMiss::Fail;
  if (v == "keep-best") return OnMiss::KeepBest;
  fail(s, where, "'on_miss' expected \"fail\" or \"keep-best\", found \"" + quoted_text(v) + "\"");
}

// The key "metric" of a [bank] or [[material]] table, `fallback` when absent.
ErrorMetric metric_or(const Scene& s, const toml::table& t, const std::string& where, ErrorMetric fallback) {
  const std::string metric = get_or(s, t, where, "metric", to_string(fallback));
  if (metric == "f") return ErrorMetric::F;
  if (metric == "cosine") return ErrorMetric::Cosine;
  fail(s, where, "'metric' expected \"f\" or \"cosine\", found \"" + quoted_text(metric) + "\"");
}

bool valid_name(const std::string& n) {
  if (n.empty() || n.size() > 64) return false;
  for (char c : n)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-')) return false;
  return true;
}

}  // namespace

std::string to_string(OnMiss on_miss) { return on_miss == OnMiss::KeepBest ? "keep-best" : "fail"; }
std::string to_string(ErrorMetric metric) { return metric == ErrorMetric::Cosine ? "cosine" : "f"; }

std::string to_string(IsotropicChoice choice) {
  switch (choice) {
    case IsotropicChoice::Always: return "true";
    case IsotropicChoice::Never: return "false";
    case IsotropicChoice::Auto: break;
  }
  return "auto";
}

std::string to_string(LutSampling sampling) { return sampling == LutSampling::CellAverage ? "average" : "centre"; }

namespace {

// The [bank] table's keys into `s`, each checked.
void read_bank_table(Scene& s, const toml::table& bank_table) {
  const toml::table* bank = &bank_table;
  const std::string w = "[bank]";
  for (const auto& [k, v] : *bank) {
    static const std::set<std::string> known{"level", "levels", "order_max", "target", "metric", "sampling", "store_lut", "lut_float32", "holdout_pairs",
                                             "representations", "reciprocal", "max_bytes", "on_miss"};
    if (!known.count(std::string(k.str()))) fail(s, w, "unknown key '" + quoted_text(std::string(k.str())) + "'");
    (void)v;
  }
  s.level = get_or(s, *bank, w, "level", s.level);
  s.order_max = get_or(s, *bank, w, "order_max", s.order_max);
  s.target = get_or(s, *bank, w, "target", s.target);
  const std::string sampling = get_or(s, *bank, w, "sampling", to_string(s.sampling));
  s.metric = metric_or(s, *bank, w, s.metric);
  s.store_lut = get_or(s, *bank, w, "store_lut", s.store_lut);
  s.lut_float32 = get_or(s, *bank, w, "lut_float32", s.lut_float32);
  s.holdout_pairs = get_or(s, *bank, w, "holdout_pairs", s.holdout_pairs);
  s.reciprocal = get_or(s, *bank, w, "reciprocal", s.reciprocal);
  s.max_bytes = max_bytes_or(s, *bank, w, s.max_bytes);
  s.on_miss = on_miss_or(s, *bank, w, s.on_miss);
  if (const auto* lv = bank->get("levels")) {
    const auto* arr = lv->as_array();
    if (!arr || arr->empty()) fail(s, w, "'levels' expected a non-empty array of integers");
    s.levels.clear();
    for (const auto& e : *arr) {
      if (!e.value<int64_t>()) fail(s, w, "'levels' expected integers");
      s.levels.push_back(checked_int(s, w, "levels", *e.value<int64_t>()));
    }
  }
  if (const auto* rv = bank->get("representations")) {
    static const std::set<std::string> allowed{"modes", "half-angle", "hybrid"};
    const auto* arr = rv->as_array();
    if (!arr || arr->empty()) fail(s, w, "'representations' expected a non-empty array of \"modes\", \"half-angle\", \"hybrid\"");
    s.representations.clear();
    for (const auto& e : *arr) {
      const auto name = e.value<std::string>();
      if (!name || !allowed.count(*name))
        fail(s, w, "'representations' entries expected \"modes\", \"half-angle\" or \"hybrid\", found " +
                       (name ? "\"" + quoted_text(*name) + "\"" : std::string("a non-string")));
      if (std::find(s.representations.begin(), s.representations.end(), *name) != s.representations.end())
        fail(s, w, "'representations' lists \"" + quoted_text(*name) + "\" twice");
      s.representations.push_back(*name);
    }
  }
  if (s.level < 0 || s.level > 8) fail(s, w, "'level' expected in [0, 8], found " + std::to_string(s.level));
  for (int l : s.levels)
    if (l < 0 || l > 8) fail(s, w, "'levels' entries expected in [0, 8], found " + std::to_string(l));
  for (std::size_t k = 1; k < s.levels.size(); ++k)  // tried in order, the last is "the finest tried"
    if (s.levels[k] <= s.levels[k - 1])
      fail(s, w, "'levels' expected strictly increasing levels, found " + std::to_string(s.levels[k - 1]) + " before " +
                     std::to_string(s.levels[k]));
  if (s.order_max < 0 || s.order_max > 128) fail(s, w, "'order_max' expected in [0, 128], found " + std::to_string(s.order_max));
  if (!(s.target > 0)) fail(s, w, "'target' expected > 0");
  if (sampling != "centre" && sampling != "average") fail(s, w, "'sampling' expected \"centre\" or \"average\", found \"" + quoted_text(sampling) + "\"");
  s.sampling = sampling == "average" ? LutSampling::CellAverage : LutSampling::CellCentre;
  if (s.holdout_pairs < 16 || s.holdout_pairs > kMaxErrorPairs)
    fail(s, w, "'holdout_pairs' expected in [16, " + std::to_string(kMaxErrorPairs) + "], found " + std::to_string(s.holdout_pairs));
  if (s.store_lut)  // LUTs are stored on the bank's grid; a one-channel LUT is the smallest
    if (const std::string p = lut_size_problem(equal_area_cells(s.level), 1, s.lut_float32); !p.empty())
      fail(s, w, "'store_lut' on the level-" + std::to_string(s.level) + " bank grid: " + p);
}

// One [[material]] table, `w` naming it until its name is known; `names` holds the names seen so far.
SceneMaterial read_material_table(const Scene& s, const toml::table* t, std::string w, std::set<std::string>& names) {
  SceneMaterial m;
  m.name = get_or<std::string>(s, *t, w, "name", "");
  if (!valid_name(m.name)) fail(s, w, "'name' expected 1-64 characters of [A-Za-z0-9_-], found \"" + quoted_text(m.name) + "\"");
  w = "material '" + m.name + "'";
  if (!names.insert(m.name).second) fail(s, w, "duplicate name");
  m.source = get_or<std::string>(s, *t, w, "source", "");
  if (m.source.empty()) fail(s, w, "'source' is required");
  if (const std::string p = source_text_problem(m.source); !p.empty()) fail(s, w, "'source': " + p);
  m.target = get_or(s, *t, w, "target", s.target);
  if (!(m.target > 0)) fail(s, w, "'target' expected > 0");
  m.metric = metric_or(s, *t, w, s.metric);
  if (const auto* iso = t->get("isotropic")) {
    if (auto b = iso->value<bool>()) m.isotropic = *b ? IsotropicChoice::Always : IsotropicChoice::Never;
    else if (auto str = iso->value<std::string>(); str && *str == "auto") m.isotropic = IsotropicChoice::Auto;
    else fail(s, w, "'isotropic' expected \"auto\", true or false");
  }
  m.order = get_or(s, *t, w, "order", -1);
  m.level = get_or(s, *t, w, "level", -1);
  if (m.order != -1 && (m.order < 0 || m.order > 128)) fail(s, w, "'order' expected in [0, 128], found " + std::to_string(m.order));
  if (m.level != -1 && (m.level < 0 || m.level > 8)) fail(s, w, "'level' expected in [0, 8], found " + std::to_string(m.level));
  m.prune = get_or(s, *t, w, "prune", true);
  m.reciprocal = get_or(s, *t, w, "reciprocal", s.reciprocal);
  m.max_bytes = max_bytes_or(s, *t, w, s.max_bytes);
  m.on_miss = on_miss_or(s, *t, w, s.on_miss);
  if (const auto* inc = t->get("incidence")) {
    const auto* arr = inc->as_array();
    if (!arr || arr->size() != 2 || !(*arr)[0].value<double>() || !(*arr)[1].value<double>())
      fail(s, w, "'incidence' expected [min, max] in degrees");
    m.incidence_min = *(*arr)[0].value<double>();
    m.incidence_max = *(*arr)[1].value<double>();
    if (!(m.incidence_min >= 0 && m.incidence_min < m.incidence_max && m.incidence_max <= 90))
      fail(s, w, "'incidence' expected 0 <= min < max <= 90");
  }
  m.lights = directions(s, *t, w, "lights");
  m.cameras = directions(s, *t, w, "cameras");
  if (m.lights.empty() != m.cameras.empty()) fail(s, w, "'lights' and 'cameras' go together: give both or neither");
  // The cosine metric weighs a pair by cos(theta_i) cos(theta_r): with every light (or camera) on the horizon
  // every weight is 0 (to rounding) and no error can be measured; refused here, before any fit.
  const auto on_horizon = [](const std::vector<std::pair<double, double>>& d) {
    return !d.empty() && std::all_of(d.begin(), d.end(), [](const auto& x) { return x.first == 90.0; });
  };
  for (const char* key : {"lights", "cameras"})
    if (m.metric == ErrorMetric::Cosine && on_horizon(std::string(key) == "lights" ? m.lights : m.cameras))
      fail(s, w, std::string("every one of '") + key + "' lies on the horizon (theta = 90), where the cosine metric weighs every pair "
                 "by 0: the error cannot be measured; use theta < 90 or metric = \"f\"");
  if (static_cast<double>(m.lights.size()) * static_cast<double>(m.cameras.size()) > static_cast<double>(kMaxErrorPairs))
    fail(s, w, "'lights' x 'cameras' expected at most " + std::to_string(kMaxErrorPairs) + " pairs, found " + std::to_string(m.lights.size()) +
                   " x " + std::to_string(m.cameras.size()));
  return m;
}

}  // namespace

Scene read_scene(const std::string& path) {
  Scene s;
  s.path = path;
  toml::table root;
  try {
    root = toml::parse_file(path);
  } catch (const toml::parse_error& e) {
    const auto& src = e.source();
    throw InputError(printable_text(path + ":" + std::to_string(src.begin.line) + ":" + std::to_string(src.begin.column) + ": " +
                                    std::string(e.description())));
  }
  if (const auto* bank = root["bank"].as_table()) read_bank_table(s, *bank);
  for (const auto& [k, v] : root) {
    if (k.str() != "bank" && k.str() != "material") fail(s, "top level", "unknown table '" + quoted_text(std::string(k.str())) + "'");
    (void)v;
  }
  const auto* mats = root["material"].as_array();
  if (!mats || mats->empty()) fail(s, "top level", "expected at least one [[material]] table");
  std::set<std::string> names;
  for (size_t i = 0; i < mats->size(); ++i) {
    const auto* t = (*mats)[i].as_table();
    std::string w = "material " + std::to_string(i + 1);
    if (!t) fail(s, w, "expected a table");
    static const std::set<std::string> known{"name", "source", "target", "metric", "isotropic", "order", "level", "incidence", "lights", "cameras", "prune", "reciprocal", "max_bytes", "on_miss"};
    for (const auto& [k, v] : *t) {
      if (!known.count(std::string(k.str()))) fail(s, w, "unknown key '" + quoted_text(std::string(k.str())) + "'");
      (void)v;
    }
    s.materials.push_back(read_material_table(s, t, w, names));
  }
  return s;
}

}  // namespace icobrdf
