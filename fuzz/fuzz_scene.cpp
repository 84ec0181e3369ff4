// libFuzzer target: the scene reader (icobrdf/io/scene.hpp read_scene), on the input bytes as a TOML file. It
// returns a scene or throws InputError with a one-line message naming the file and the place. A returned
// scene must hold what the reader promises: settings within their documented ranges, at least one
// material, unique valid names, a non-empty source, lights and cameras together; and each material's
// "model:" source must parse or fail with a one-line ArgumentError (as `bank build` would report it).
#include <cmath>
#include <set>

#include "icobrdf/core/models/model_registry.hpp"
#include "fuzz/fuzz_support.hpp"
#include "icobrdf/io/scene.hpp"

using namespace icobrdf;

namespace {

bool valid_name(const std::string& n) {
  if (n.empty() || n.size() > 64) return false;
  for (char ch : n)
    if (!(std::isalnum(static_cast<unsigned char>(ch)) || ch == '_' || ch == '-')) return false;
  return true;
}

void check_scene(const Scene& s) {
  if (s.level < 0 || s.level > 8) fuzz::finding("bank level out of [0, 8]");
  if (s.levels.empty()) fuzz::finding("no levels");
  for (int l : s.levels)
    if (l < 0 || l > 8) fuzz::finding("a level out of [0, 8]");
  if (s.order_max < 0 || s.order_max > 128) fuzz::finding("order_max out of [0, 128]");
  if (!(s.target > 0)) fuzz::finding("bank target not > 0");
  if (s.holdout_pairs < 16 || s.holdout_pairs > 1000000) fuzz::finding("holdout_pairs out of range");
  if (s.materials.empty()) fuzz::finding("a scene without materials");
  std::set<std::string> names;
  for (const auto& m : s.materials) {
    if (!valid_name(m.name)) fuzz::finding("invalid material name accepted");
    if (!names.insert(m.name).second) fuzz::finding("duplicate material name accepted");
    if (m.source.empty()) fuzz::finding("empty source accepted");
    if (!(m.target > 0)) fuzz::finding("material target not > 0");
    if (m.metric != ErrorMetric::F && m.metric != ErrorMetric::Cosine) fuzz::finding("unknown metric accepted");
    if (m.order < -1 || m.order > 128 || m.level < -1 || m.level > 8) fuzz::finding("material order or level out of range");
    if (!(m.incidence_min >= 0 && m.incidence_min < m.incidence_max && m.incidence_max <= 90))
      fuzz::finding("incidence range out of [0, 90]");
    if (m.lights.empty() != m.cameras.empty()) fuzz::finding("lights without cameras or cameras without lights");
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, size_t size) {
  static const fuzz::InputFile file("scene", ".toml");
  file.write(data, size);
  Scene scene;
  bool read = false;
  fuzz::expect_input_errors_only([&] {
    scene = read_scene(file.path());
    read = true;
  });
  if (!read) return 0;
  check_scene(scene);
  for (const auto& m : scene.materials)
    if (is_model_source(m.source)) fuzz::expect_user_errors_only([&] { parse_model_source(m.source); });
  return 0;
}
