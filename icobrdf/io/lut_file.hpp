#pragma once
// A LUT file: a bank holding the grid and one material with its LUT (cells x cells per channel) and the
// LUT's spectrum (written by `icobrdf lut` and `icobrdf smooth`, read by `smooth` and `albedo`).
#include <memory>
#include <string>
#include <utility>

#include "icobrdf/io/bank_file.hpp"

namespace icobrdf {

// The grid and the material of LUT.h5[#MATERIAL]: the named material, or the first with a LUT.
// InputError when the file has no /grid, no such material, or the material has no LUT.
std::pair<std::shared_ptr<const Grid>, MaterialRecord> read_lut_file(const std::string& spec);

// Writes `grid` and `rec` as a LUT file (write_bank: atomic, every check of the writer).
void write_lut_file(const std::string& path, const Grid& grid, MaterialRecord rec);

}  // namespace icobrdf
