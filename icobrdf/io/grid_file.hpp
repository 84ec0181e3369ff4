#pragma once
// Grid <-> the /grid group of an icobrdf HDF5 file (schema: docs/file-format.md).
//
// Every member of Grid is stored: attributes kind, level, cells, cubature_degree; datasets directions (C x 3),
// solid_angles (C) [sr], cubature_offsets (C + 1), cubature_points (Q x 3), cubature_weights (Q) [sr], and,
// when non-empty, vertices (V x 3), faces (C x 3), neighbours (C x 3), is_half (C), rotate_pi, mirror_xz,
// mirror_yz (C). Absent optional datasets read back as empty members, so a round trip is exact.
#include <string>

#include "icobrdf/core/grid/grid.hpp"
#include "icobrdf/io/h5_file.hpp"

namespace icobrdf {

// Attributes of a stored grid, readable without loading its arrays.
struct GridSummary {
  std::string kind;
  int level = 0;
  int cells = 0;
};

// Writes `grid` as the new group `parent/name`. ArgumentError when validate(grid) fails; IoError on write failure.
void write_grid(h5::Group& parent, const Grid& grid, const std::string& name = "grid");

// Reads the group written by write_grid: checks every dataset's type and shape against the cells attribute
// before reading, every float is finite, the offsets increasing, indices in range, then validate().
// InputError naming the file and object on any disagreement.
Grid read_grid(const h5::Group& grid_group, const h5::ReadLimits& limits);

// Reads and range-checks only the attributes.
GridSummary read_grid_summary(const h5::Group& grid_group);

}  // namespace icobrdf
