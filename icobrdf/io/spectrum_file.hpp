#pragma once
// Materials <-> the /materials/<name> groups of an icobrdf HDF5 bank (schema: docs/file-format.md).
//
// A MaterialRecord is a Spectrum plus optional data computed elsewhere and stored beside it:
//   ibsss          channels x K   isotropic (IBSSS) coefficients [1], with
//   ibsss_indices  K x 3          (n, m, l) of each column, n >= m >= l >= 0, n - l and m - l even, n <= order
//   lut            channels x (cells x cells)  the BRDF per (incident cell, remitted cell) [1/sr]
//   lobe           a half-angle factorized lobe (icobrdf/core/models/half_angle_factors.hpp, icobrdf/io/half_angle_file.hpp) added to
//                  the modes: f = sum_ab C_ab K_a(w_i) K_b(w_r) + lobe(w_i, w_r). Representation "half-angle"
//                  when C is all zero (a lobe alone), "hybrid" otherwise; "modes" without a lobe.
// The writer stores the LUT as float32 when lut_float32 is set, recording the largest
// |float32(x) - x| as the material attribute lut_max_abs_rounding_error [1/sr] (relative rounding <= 2^-24).
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "icobrdf/core/grid/grid.hpp"
#include "icobrdf/core/models/half_angle_factors.hpp"
#include "icobrdf/core/spectrum/spectrum.hpp"
#include "icobrdf/io/grid_file.hpp"
#include "icobrdf/io/h5_file.hpp"

namespace icobrdf {

struct MaterialRecord {
  std::string name;
  Spectrum spectrum;
  Eigen::MatrixXd ibsss;      // channels x K; empty when absent
  RowMatrix3i ibsss_indices;  // K x 3 (n, m, l)
  std::optional<HalfAngleFactors> lobe;  // half-angle lobe added to the modes; absent for "modes"
  std::vector<Eigen::MatrixXd> lut;  // one cells x cells matrix per channel; empty when absent
  bool lut_float32 = false;          // write: store as float32; read: it was stored as float32
  // Largest |float32(x) - x| over the LUT [1/sr]; set by the writer (float32 only) and by the reader.
  double lut_max_rounding_error = std::numeric_limits<double>::quiet_NaN();
  // How the material was chosen (bank builds): numbers and texts stored as attributes of the subgroup
  // `choice` (names: [A-Za-z0-9_], listed in its attributes `figures` and `labels`, comma-separated).
  std::map<std::string, double> figures;
  std::map<std::string, std::string> labels;
};

// "modes", "half-angle" (a lobe and an all-zero C) or "hybrid" (a lobe and modes).
std::string representation_name(const MaterialRecord& rec);

// Longest material name accepted.
inline constexpr std::size_t kMaxMaterialNameLength = 255;
// Longest SOURCE text stored with a material. It is the HDF5 attribute "source", and an attribute lives
// in one object-header message of at most 65,535 bytes with its name, datatype and dataspace; 60,000
// leaves room for those. Longer texts are refused up front (scene, fit) and by the writer.
inline constexpr std::size_t kMaxSourceLength = 60000;
// Largest order accepted in a file (M = 501501 basis functions): a sanity bound against overflow; the
// dataset size limit of the read applies first in practice.
inline constexpr int kMaxFileOrder = 1000;

// Material names: non-empty, at most kMaxMaterialNameLength bytes of printable ASCII, no '/' and no '.'.
// Returns an empty string when valid, else the reason.
std::string material_name_problem(const std::string& name);
// Throws ArgumentError when the name is invalid.
void validate_material_name(const std::string& name);
// Reason the SOURCE text cannot be stored with a material (longer than kMaxSourceLength), or "".
std::string source_text_problem(const std::string& source);
// Throws ArgumentError with that reason: commands that store their SOURCE call it before any work.
void require_storable_source(const std::string& source);

// Cells of the equal-area grid of `level`: 10 4^L + 2^(L+1).
std::int64_t equal_area_cells(int level);

// A LUT dataset holds channels x cells x cells values of 8 bytes (4 with float32) and may not exceed the
// readers' limit h5::kDefaultMaxDatasetBytes (4 GiB: level 5 with 3 float64 channels is 2.5 GB, level 6 with
// one float32 channel already 6.75 GB). Reason a LUT of this size cannot be stored, or "".
std::string lut_size_problem(std::int64_t cells, int channels, bool float32);
// Throws UnsupportedError with that reason prefixed by `what`: commands call it before sampling a LUT, and the
// writer before writing one, so no file is written that its own readers refuse.
void require_storable_lut(std::int64_t cells, int channels, bool float32, const std::string& what);

// True when the spectrum carries a sample-fit record that describes it (same modes and channels). A spectrum
// truncated, padded or made isotropic after its fit (the bank builder's order search) keeps a record of
// another estimate; the writer stores the group `sample_fit` only when this holds.
bool sample_fit_record_matches(const Spectrum& s);

// Writes `rec` as the new group `materials/<rec.name>`. ArgumentError when the record is inconsistent
// (C not M x M for the order, channels not 1 or 3, LUT not square, IBSSS tables disagreeing, a float32 LUT
// value beyond float32 range); IoError on write failure. Finiteness is checked before the file is opened
// (require_finite_material, called by write_bank for every material).
void write_material(h5::Group& materials, const MaterialRecord& rec);

// Reads `materials/<name>` with every check of docs/file-format.md. When `grid` is given (the bank's
// /grid attributes) and the material's level and grid kind match it, the LUT must have its cell count.
// `read_lut` false skips the LUT (its metadata is still validated).
// UnsupportedError (icobrdf/core/support/finite_values.hpp) naming `file`, the material and the dataset or attribute when C,
// ibsss, the LUT or the lobe factors hold Inf or NaN, or a figure (gram_error, ..., max_albedo) is infinite
// (NaN there means "not measured"). Every bank writer runs it before anything is written.
void require_finite_material(const std::string& file, const MaterialRecord& rec);

MaterialRecord read_material(const h5::Group& materials, const std::string& name, const h5::ReadLimits& limits,
                             bool read_lut = true, const std::optional<GridSummary>& grid = std::nullopt);

// Convenience wrappers over icobrdf/io/bank_file.hpp: a bank with one material (and optionally its grid).
void write_spectrum_file(const std::string& path, const Spectrum& spectrum, const Grid* grid = nullptr,
                         const std::string& name = "spectrum");
// The consumers that take a material's Zernike modes alone (a Spectrum: SCATMECH export, the coefficient
// plot, Python's read_spectrum) read it here. Material `name`, or the first in name order when `name` is
// empty. A material with a half-angle lobe ("half-angle" or "hybrid") is refused with UnsupportedError in one
// line naming FILE#MATERIAL, its representation and `consumer` (what the consumer takes and what to use
// instead): its modes alone are not the material (none at all for "half-angle").
Spectrum read_spectrum_file(const std::string& path, const std::string& name = "",
                            const std::string& consumer = "a spectrum holds Zernike modes only; open FILE.h5#MATERIAL as a "
                                                          "SOURCE (eval, lut, albedo, sample, plot slice) to use every part");
// "a half-angle lobe (no modes)" or "a hybrid of modes and a half-angle lobe"; "" for modes alone.
std::string lobe_representation_phrase(const MaterialRecord& rec);

}  // namespace icobrdf
