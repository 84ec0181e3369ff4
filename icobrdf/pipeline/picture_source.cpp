#include "icobrdf/pipeline/picture_source.hpp"

#include <sys/stat.h>

#include <memory>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/models/model_registry.hpp"
#include "icobrdf/io/bank_file.hpp"
#include "icobrdf/io/brdf_source.hpp"
#include "icobrdf/io/material_eval.hpp"
#include "icobrdf/io/spectrum_file.hpp"
#include "icobrdf/pipeline/fit_source.hpp"

namespace icobrdf {
namespace {

constexpr unsigned long long kBankReadLimitBytes = 1ull << 31;  // largest material read from a bank

bool is_regular_file(const std::string& p) {
  struct stat st{};
  return ::stat(p.c_str(), &st) == 0 && S_ISREG(st.st_mode);
}

bool ends_with_h5(const std::string& s) { return s.size() > 3 && s.compare(s.size() - 3, 3, ".h5") == 0; }

// The material FILE.h5[#material] as stored (its source named by `text` when it names none), read once.
MaterialRecord read_picture_record(const std::string& text, const MaterialRef& ref) {
  if (!is_regular_file(ref.path)) throw InputError(ref.path + ": no such file (SOURCE '" + quoted_text(text) + "')");
  MaterialRecord rec = read_bank_material(ref.path, ref.name, ReadOptions{h5::kDefaultMaxDatasetBytes, false});
  if (rec.spectrum.source.empty()) rec.spectrum.source = text;
  return rec;
}

}  // namespace

PictureMaterial load_picture_material(const std::string& text, int order, int level, bool values_only, bool fit_allowed) {
  PictureMaterial m;
  m.name = text;
  const MaterialRef ref = split_material_ref(text);
  if (!is_model_source(text) && ends_with_h5(ref.path)) {
    MaterialRecord rec = read_picture_record(text, ref);
    m.spectrum = std::move(rec.spectrum);
    if (!rec.lobe) return m;
  }
  // Models, measured data, and stored materials with a half-angle lobe (whose modes alone are not the
  // material): the values themselves are exact, the spectrum is their projection at `order`.
  std::shared_ptr<const BrdfSource> source = open_source(text);
  const bool stored = m.spectrum.has_value();
  const bool exact = stored || (!source->has_delta() && !source->values_only_at_samples());
  if (exact) {
    m.exact = [source](const RowMatrix3d& wi, const RowMatrix3d& wr) { return source->eval(wi, wr); };
    m.exact_channels = source->channels();
    m.exact_kind = stored ? "stored" : is_model_source(text) ? "model" : "measured";
    if (values_only) return m;
  }
  if (!fit_allowed) return m;
  FitRequest r;
  r.level = level;
  r.order = order;
  r.grid_kind = GridKind::EqualArea;
  r.sampling = LutSampling::CellAverage;
  r.cosine = source->has_delta();
  m.spectrum = fit_source(*source, r).spectrum;
  return m;
}

std::vector<std::string> several_bank_materials(const std::string& text) {
  if (is_model_source(text) || text.find('#') != std::string::npos || !ends_with_h5(text)) return {};
  if (!is_regular_file(text)) throw InputError(text + ": no such file (SOURCE '" + quoted_text(text) + "')");
  auto names = bank_material_names(text);
  if (names.size() < 2) names.clear();
  return names;
}

PictureMaterial stored_bank_material(const std::string& bank, const std::string& name) {
  PictureMaterial m;
  m.name = name;
  MaterialRecord rec = read_bank_material(bank, name, ReadOptions{kBankReadLimitBytes, false});
  if (!rec.lobe) {
    m.spectrum = std::move(rec.spectrum);
    return m;
  }
  // A material with a lobe is shaded from its values (its modes alone are not the material).
  auto shared = std::make_shared<const MaterialRecord>(std::move(rec));
  m.exact = [shared](const RowMatrix3d& wi, const RowMatrix3d& wr) { return evaluate_material(shared->spectrum, shared->lobe, wi, wr); };
  m.exact_channels = shared->spectrum.channel_count();
  return m;
}

void add_stored_values(PictureMaterial& m) {
  if (m.exact || !m.spectrum) return;
  auto sp = std::make_shared<const Spectrum>(*m.spectrum);
  m.exact = [sp](const RowMatrix3d& wi, const RowMatrix3d& wr) { return evaluate_material(*sp, std::nullopt, wi, wr); };
  m.exact_channels = sp->channel_count();
  m.exact_kind = "stored";
}

}  // namespace icobrdf
