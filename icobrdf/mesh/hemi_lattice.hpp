#pragma once
// HemiLattice: the cell layout of the hemi-icosahedral tessellation at level L, shared by the grid
// builders and the cell locator so that both number the cells identically.
//
// Each of the 12 hemi-icosahedron faces (hemi_icosahedron_faces(), in that order) carries the aperture-4
// lattice with n = 2^L: points with barycentric coordinates (n - i - j, i, j) / n. Lattice triangles:
//   up   (i, j), i + j <= n - 1: corners (i, j), (i+1, j), (i, j+1)      [(l1, l2) times n]
//   down (i, j), i + j <= n - 2: corners (i+1, j), (i+1, j+1), (i, j+1)
// both listed counter-clockwise. Within a face they are indexed row by row:
//   index(i, j, down) = 2 n j - j^2 + 2 i + down   (0 .. n^2 - 1).
// On a bisected face the equator is the median l1 = l2; lattice triangles with i = j are cut in half along
// their own median (the upper half is the cell), those entirely below the equator are not cells.
//
// Cell numbering (deterministic): faces in order, then lattice index; cells below the equator skipped.
// Count: 8 whole faces x 4^L + 4 x ((4^L - 2^L)/2 whole + 2^L half) = 10 4^L + 2^(L+1).
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace icobrdf {

class HemiLattice {
 public:
  static constexpr int kMaxLevel = 8;
  // Throws ArgumentError unless 0 <= level <= kMaxLevel.
  explicit HemiLattice(int level);

  struct Cell {
    int face;     // hemi-icosahedron face (0..11)
    int i, j;     // lattice triangle
    bool down;    // down-pointing lattice triangle
    bool half;    // cut in half by the equator
  };
  // Integer barycentric coordinates scaled by scale() = 6 n, so that edge midpoints and the face centre
  // (the centroid of the central cell) are integer points; components sum to scale().
  using Point = std::array<std::int64_t, 3>;

  int level() const { return level_; }
  int n() const { return n_; }
  std::int64_t scale() const { return 6 * static_cast<std::int64_t>(n_); }
  int cells() const { return static_cast<int>(cells_.size()); }
  const Cell& cell(int c) const { return cells_[c]; }

  static int lattice_index(int n, int i, int j, int down) { return 2 * n * j - j * j + 2 * i + down; }
  // Cell id of lattice triangle `index` of `face`; triangles below the equator give their mirror image
  // across the equator (the cell containing the reflection of their points).
  int cell_at(int face, int index) const { return table_[static_cast<std::size_t>(face) * n_ * n_ + index]; }
  const std::vector<int>& table() const { return table_; }

  // Counter-clockwise polygon (a triangle) of cell c in scaled integer barycentric coordinates of its face.
  std::vector<Point> polygon(int c) const;

 private:
  int level_, n_;
  std::vector<Cell> cells_;
  std::vector<int> table_;
};

// Sutherland-Hodgman clip of a convex polygon (scaled integer barycentric) to the half-plane
// l[a] - l[b] >= 0. Intersections are exact (throws std::logic_error if one is not a lattice point of the
// scaled coordinates, which cannot happen for the polygons of HemiLattice cut by face medians).
std::vector<HemiLattice::Point> clip_median(const std::vector<HemiLattice::Point>& poly, int a, int b);

// det[p; q; r] of three scaled barycentric points: the signed area of triangle (p, q, r) as a fraction of
// the face is det / scale^3 (positive for counter-clockwise order).
std::int64_t barycentric_det(const HemiLattice::Point& p, const HemiLattice::Point& q, const HemiLattice::Point& r);

}  // namespace icobrdf
