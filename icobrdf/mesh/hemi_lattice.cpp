#include "icobrdf/mesh/hemi_lattice.hpp"

#include <stdexcept>
#include <string>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/mesh/icosahedron.hpp"

namespace icobrdf {

HemiLattice::HemiLattice(int level) : level_(level), n_(0) {
  if (level < 0 || level > kMaxLevel)
    throw ArgumentError("tessellation level " + std::to_string(level) + " out of range: expected 0 <= level <= " +
                        std::to_string(kMaxLevel));
  n_ = 1 << level;
  const auto& faces = hemi_icosahedron_faces();
  const int per_face = n_ * n_;
  table_.assign(faces.size() * per_face, -1);
  cells_.reserve(10 * static_cast<size_t>(per_face) + 2 * n_);
  for (int f = 0; f < static_cast<int>(faces.size()); ++f) {
    const bool bis = faces[f].bisected;
    const int up = faces[f].upper_corner;
    for (int j = 0; j < n_; ++j)
      for (int i = 0; i + j <= n_ - 1; ++i)
        for (int down = 0; down < 2; ++down) {
          if (down && i + j > n_ - 2) continue;
          // Upper side of the equator: l_upper >= l_lower, i.e. i >= j (upper corner 1) or j >= i (corner 2).
          const bool below = bis && (up == 1 ? i < j : j < i);
          if (below) continue;
          table_[static_cast<size_t>(f) * per_face + lattice_index(n_, i, j, down)] = static_cast<int>(cells_.size());
          cells_.push_back({f, i, j, down == 1, bis && i == j});
        }
    if (bis)  // lattice triangles below the equator point to their mirror image (i <-> j)
      for (int j = 0; j < n_; ++j)
        for (int i = 0; i + j <= n_ - 1; ++i)
          for (int down = 0; down < 2; ++down) {
            if (down && i + j > n_ - 2) continue;
            int& t = table_[static_cast<size_t>(f) * per_face + lattice_index(n_, i, j, down)];
            if (t < 0) t = table_[static_cast<size_t>(f) * per_face + lattice_index(n_, j, i, down)];
          }
  }
}

std::vector<HemiLattice::Point> HemiLattice::polygon(int c) const {
  const Cell& cl = cells_[c];
  const std::int64_t s6 = 6, n = n_;
  auto pt = [&](std::int64_t a, std::int64_t b) { return Point{s6 * (n - a - b), s6 * a, s6 * b}; };
  const std::int64_t i = cl.i, j = cl.j;
  std::vector<Point> poly = cl.down ? std::vector<Point>{pt(i + 1, j), pt(i + 1, j + 1), pt(i, j + 1)}
                                    : std::vector<Point>{pt(i, j), pt(i + 1, j), pt(i, j + 1)};
  if (cl.half) {
    const int up = hemi_icosahedron_faces()[cl.face].upper_corner;
    poly = clip_median(poly, up, 3 - up);
  }
  return poly;
}

std::vector<HemiLattice::Point> clip_median(const std::vector<HemiLattice::Point>& poly, int a, int b) {
  std::vector<HemiLattice::Point> out;
  const size_t m = poly.size();
  for (size_t k = 0; k < m; ++k) {
    const auto& p = poly[k];
    const auto& q = poly[(k + 1) % m];
    const std::int64_t fp = p[a] - p[b], fq = q[a] - q[b];
    if (fp >= 0) out.push_back(p);
    if ((fp > 0 && fq < 0) || (fp < 0 && fq > 0)) {
      HemiLattice::Point x;
      const std::int64_t den = fp - fq;
      for (int c = 0; c < 3; ++c) {
        const std::int64_t num = (q[c] - p[c]) * fp;
        if (num % den != 0) throw std::logic_error("clip_median: intersection is not a lattice point");
        x[c] = p[c] + num / den;
      }
      out.push_back(x);
    }
  }
  return out;
}

std::int64_t barycentric_det(const HemiLattice::Point& p, const HemiLattice::Point& q, const HemiLattice::Point& r) {
  return p[0] * (q[1] * r[2] - q[2] * r[1]) - p[1] * (q[0] * r[2] - q[2] * r[0]) + p[2] * (q[0] * r[1] - q[1] * r[0]);
}

}  // namespace icobrdf
