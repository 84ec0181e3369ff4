#include "icobrdf/io/lut_file.hpp"

#include "icobrdf/core/support/error.hpp"

namespace icobrdf {

std::pair<std::shared_ptr<const Grid>, MaterialRecord> read_lut_file(const std::string& spec) {
  const auto [path, name] = split_material_ref(spec);
  BankContents b = read_bank(path);
  if (!b.grid) throw InputError(path + ": no /grid group; a LUT file needs the grid its LUT lives on");
  const MaterialRecord* rec = nullptr;
  for (const auto& m : b.materials)
    if ((name.empty() && !m.lut.empty()) || m.name == name) {
      rec = &m;
      break;
    }
  if (!rec)
    throw InputError(path + ": " + (name.empty() ? std::string("no material with a LUT") : "no material '" + quoted_text(name) + "'"));
  if (rec->lut.empty()) throw InputError(path + ": material '" + rec->name + "' has no LUT");
  auto grid = std::make_shared<const Grid>(*b.grid);
  return {grid, *rec};
}

void write_lut_file(const std::string& path, const Grid& grid, MaterialRecord rec) {
  BankContents b;
  b.grid = grid;
  b.materials.push_back(std::move(rec));
  write_bank(path, b);
}

}  // namespace icobrdf
