#pragma once
// Exports of any SOURCE (an analytic model, a bank material of any representation, measured data) to the
// files renderers load, each read back by this program's own reader and compared with the source:
//   rgl   the RGB tensor file of Dupuy & Jakob 2018 (Mitsuba 3's and pbrt-v4's `measured` BSDF;
//         icobrdf/io/rgl_export.hpp writes it, icobrdf/io/rgl_bsdf.hpp reads it back);
//   merl  MERL's 90 x 90 x 180 half/difference table of doubles (icobrdf/io/merl.hpp write_merl / read_merl:
//         the source at the bin centres divided by the channel scales; 1 channel goes to R, G and B;
//         negative values, which a modes fit may leave near grazing, are written as 0 and counted).
// Both formats are isotropic: a source is refused (ArgumentError, one line) when a turn about the normal
// changes its values by more than kExportIsotropyTolerance (relative L2 over kIsotropyCheckPairs pairs turned
// by two angles; analytic models that declare isotropy are taken at their word), and when it has a delta
// part (an ideal mirror has no tabulated value). A source of other than 1 or 3 channels is refused too.
//
// Agreement (what the report states): the file read back, against the source at kAgreementPairs pairs
// uniform in solid angle (both directions; splitmix64 draws, fixed seed), as the cosine-weighted relative L2
//   |cos_i cos_r (f_file - f_source)| / |cos_i cos_r f_source|   over pairs and channels
// (a 1-channel source against each of R, G, B). For MERL also the largest relative difference at
// kMerlNodesChecked table nodes (bin centres; doubles are stored, so this is rounding), and the cosine L2
// is then the table's own resolution (its lookup is constant over each bin). A file that fails to read back is removed.
#include <nlohmann/json.hpp>

#include <string>

#include "icobrdf/io/rgl_export.hpp"

namespace icobrdf {

// A turn about the normal changes an isotropic source's values by rounding only (the bank's representations
// and the analytic models evaluate in double precision; 1e-6 leaves six orders for the evaluation paths).
inline constexpr double kExportIsotropyTolerance = 1e-6;
inline constexpr int kIsotropyCheckPairs = 512;
// Pairs of the agreement figure: 20,000 uniform pairs put the sampling noise of a relative L2 of 0.01-0.03
// at a few percent of itself for lobes of alpha >= 0.1.
inline constexpr int kAgreementPairs = 20000;
inline constexpr int kMerlNodesChecked = 20000;

struct RendererExport {
  std::string source, format, output;
  long long bytes = 0;
  double cosine_l2 = 0.0;        // agreement of the file read back, as above
  double node_max_rel = 0.0;     // MERL: largest relative difference at the nodes checked
  long long negatives_zeroed = 0;  // MERL: node values < 0 written as 0
  RglExportSummary rgl;          // RGL: the tables written
};

// format "rgl" or "merl" (ArgumentError otherwise). The output is written atomically.
RendererExport export_for_renderer(const std::string& source, const std::string& format, const std::string& output,
                                   const RglExportOptions& rgl_options = {});

nlohmann::json renderer_export_json(const RendererExport& e);
// Two lines: what was written, and the agreement read back.
std::string renderer_export_text(const RendererExport& e);

}  // namespace icobrdf
