#pragma once
// LUT files of one material (icobrdf/io/lut_file.hpp): a SOURCE sampled into a cells x cells LUT on the
// equal-area grid, stored with its spectrum (`icobrdf lut`); a LUT smoothed to S F S^T (`icobrdf smooth`); and
// a LUT's directional albedo per channel with the white-furnace check (`icobrdf albedo`). Negative f or albedo
// are reported, or refused when strict (icobrdf/pipeline/reflectance_check.hpp); Inf and NaN are refused.
#include <nlohmann/json.hpp>

#include <ostream>
#include <string>

#include "icobrdf/core/projection/lut.hpp"

namespace icobrdf {

struct LutRequest {
  std::string source;       // SOURCE text (a model, a bank material of any representation, measured data)
  std::string output;       // LUT file to write
  std::string name = "lut"; // material name in the file
  int level = 4;            // equal-area tessellation level
  int order = 8;            // order of the spectrum stored with the LUT
  bool cosine = false;      // tabulate g = f cos(theta_i) (forced for delta models)
  bool float32 = false;     // store the LUT as float32 (the rounding error is recorded)
  bool strict = false;      // negative f or albedo is an error, not a warning on `warnings`
  LutSampling sampling = LutSampling::CellAverage;  // cell averages (degree-2 rule on the same cells) or centres
};

struct LutWritten {
  std::string label;         // the SOURCE's label
  int cells = 0;             // of the grid (the LUT is cells x cells)
  bool cosine = false;       // g = f cos(theta_i) was tabulated
  double max_albedo = 0.0;   // largest directional albedo of the first channel
};

// Samples, checks (estimates of storage and memory first), fits and writes the LUT of `request`.
LutWritten write_source_lut(const LutRequest& request, std::ostream* warnings);
// The line `icobrdf lut` prints: "<output>: 2562 x 2562 LUT of <label> (f), max directional albedo 0.93".
std::string lut_written_text(const LutWritten& w, const std::string& output);

// Smooths every channel of the LUT at `input` to `order` with `filter` (S F S^T) and writes it, with its
// spectrum, to `output`. Returns the name of the material smoothed and of the filter.
struct SmoothedLut {
  std::string name, filter;
};
SmoothedLut write_smoothed_lut(const std::string& input, const std::string& output, int order, const std::string& filter, bool float32);
// The line `icobrdf smooth` prints: "<output>: LUT '<name>' smoothed to order 8 with filter <filter>".
std::string smoothed_lut_text(const SmoothedLut& s, const std::string& output, int order);

// The LUT at `input`: checked (strict: negative values refused, else warned on `warnings`), and per channel
// its directional albedo: max_albedo, min_albedo, mean_albedo, worst_cell with worst_theta_deg and
// worst_phi_deg (its direction in degrees), energy_conserving (max <= 1). JSON {file, material, cells, channels}.
nlohmann::json lut_albedo_json(const std::string& input, bool strict, std::ostream* warnings);

}  // namespace icobrdf
