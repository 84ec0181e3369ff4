// CellLocator: O(1) direction -> cell. Checked against an independent reference (Newton inversion of the
// inverse projection, which never calls the forward map), on cubature points and directions of every
// cell, on every vertex and on points of every cell edge, at the pole and on the equator; batch = single;
// bad input rejected.
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <cmath>
#include <random>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/mesh/cell_locator.hpp"
#include "icobrdf/mesh/gnomonic_projection.hpp"
#include "icobrdf/mesh/hemi_lattice.hpp"
#include "icobrdf/mesh/icosahedron.hpp"
#include "icobrdf/mesh/snyder_projection.hpp"
#include "icobrdf/mesh/tessellation.hpp"
#include "tests/support/unity_id.hpp"

using namespace icobrdf;

namespace ICOBRDF_UNITY_ID {
// Newton reference converges to rounding (~1e-16); points whose scaled lattice coordinates are within
// 1e-9 of a lattice line are ambiguous for any floating-point classification and are skipped.
constexpr double kNewtonTol = 1e-15;
constexpr double kAmbiguous = 1e-9;
// Vertex positions and points on the equator: rounding-sized offsets.
constexpr double kPointTol = 1e-14;

std::array<Eigen::Vector3d, 3> corners(int f) {
  const auto& v = icosahedron_vertices();
  const auto& h = hemi_icosahedron_faces()[f];
  return {v[h.v[0]], v[h.v[1]], v[h.v[2]]};
}

Eigen::Vector3d random_direction(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double z = u(rng), phi = 2 * M_PI * u(rng), s = std::sqrt(1 - z * z);
  return Eigen::Vector3d(s * std::cos(phi), s * std::sin(phi), z);
}

// Planar barycentric coordinates of d on face f by Newton's method on the inverse projection only.
Eigen::Vector3d newton_forward(const SnyderProjection& p, const GnomonicProjection& g, const Eigen::Vector3d& d) {
  Eigen::Vector2d x = g.forward(d).tail<2>();  // start: gnomonic coordinates
  auto inv = [&](const Eigen::Vector2d& y) { return p.inverse(Eigen::Vector3d(1 - y[0] - y[1], y[0], y[1])); };
  for (int it = 0; it < 60; ++it) {
    const Eigen::Vector3d r = d - inv(x);
    if (r.norm() < kNewtonTol) break;
    const double h = 1e-7;
    Eigen::Matrix<double, 3, 2> j;
    for (int k = 0; k < 2; ++k) {
      Eigen::Vector2d e = Eigen::Vector2d::Zero();
      e[k] = h;
      j.col(k) = (inv(x + e) - inv(x - e)) / (2 * h);
    }
    x += j.colPivHouseholderQr().solve(r);
  }
  return Eigen::Vector3d(1 - x[0] - x[1], x[0], x[1]);
}

int nearest_face(const Eigen::Vector3d& d) {
  const auto& hf = hemi_icosahedron_faces();
  int best = 0;
  for (int f = 1; f < 12; ++f)
    if (hf[f].centre.dot(d) > hf[best].centre.dot(d)) best = f;
  return best;
}

bool cell_has_vertex(const Grid& g, int c, int v) { return g.faces(c, 0) == v || g.faces(c, 1) == v || g.faces(c, 2) == v; }

TEST(CellLocator, RandomDirectionsMatchNewtonReference) {
  std::mt19937_64 rng(2024);
  for (int level : {0, 1, 3, 5, 8}) {
    const HemiLattice lat(level);
    const CellLocator loc(level);
    const int n = lat.n();
    int compared = 0;
    for (int k = 0; k < 1500; ++k) {
      const Eigen::Vector3d d = random_direction(rng);
      const int f = nearest_face(d);
      const SnyderProjection p(corners(f));
      const GnomonicProjection gp(corners(f));
      const Eigen::Vector3d l = newton_forward(p, gp, d);
      ASSERT_LT((p.inverse(l) - d).norm(), 1e-14);
      const double a = l[1] * n, b = l[2] * n;
      const double fa = a - std::floor(a), fb = b - std::floor(b), fs = fa + fb;
      if (fa < kAmbiguous || fa > 1 - kAmbiguous || fb < kAmbiguous || fb > 1 - kAmbiguous || std::abs(fs - 1) < kAmbiguous) continue;
      const int i = static_cast<int>(std::floor(a)), j = static_cast<int>(std::floor(b));
      const int expect = lat.cell_at(f, HemiLattice::lattice_index(n, i, j, fs > 1 ? 1 : 0));
      ASSERT_EQ(loc.locate(d), expect) << "level " << level << " direction " << d.transpose();
      ++compared;
    }
    EXPECT_GT(compared, 1400) << level;
  }
}

TEST(CellLocator, CubaturePointsAndDirectionsRoundTrip) {
  for (int level = 0; level <= 5; ++level)
    for (const char* kind : {"equal-area", "geodesic"}) {
      const Grid g = build_hemi_icosahedral_grid(level, kind);
      const CellLocator loc(level, kind);
      ASSERT_EQ(loc.cells(), g.cells());
      Eigen::VectorXi got;
      loc.locate(g.cubature_points, got);
      for (int c = 0; c < g.cells(); ++c)
        for (auto r = g.cubature_offsets[c]; r < g.cubature_offsets[c + 1]; ++r) ASSERT_EQ(got[r], c) << kind << level;
      loc.locate(g.directions, got);
      for (int c = 0; c < g.cells(); ++c) ASSERT_EQ(got[c], c);
    }
}

TEST(CellLocator, VerticesAndEdgePointsGiveAnAdjacentCell) {
  for (int level = 0; level <= 5; ++level)
    for (const char* kind : {"equal-area", "geodesic"}) {
      const Grid g = build_hemi_icosahedral_grid(level, kind, 1);
      const CellLocator loc(level, kind);
      const HemiLattice lat(level);
      // Every vertex: the located cell has it as a corner.
      for (int v = 0; v < g.vertices.rows(); ++v) {
        const int c = loc.locate(Eigen::Vector3d(g.vertices.row(v)));
        ASSERT_TRUE(cell_has_vertex(g, c, v)) << kind << " level " << level << " vertex " << v;
      }
      // Points on every cell edge (planar fractions 1/2 and 1/3 mapped to the sphere): a cell sharing the edge.
      const bool ea = std::string(kind) == "equal-area";
      for (int c = 0; c < g.cells(); ++c) {
        const int f = lat.cell(c).face;
        const SnyderProjection sp(corners(f));
        const GnomonicProjection gp(corners(f));
        const auto poly = lat.polygon(c);
        const double s = static_cast<double>(lat.scale());
        for (size_t e = 0; e < 3; ++e) {
          const auto& a = poly[e];
          const auto& b = poly[(e + 1) % 3];
          for (double t : {0.5, 1.0 / 3.0}) {
            const Eigen::Vector3d l((a[0] + t * (b[0] - a[0])) / s, (a[1] + t * (b[1] - a[1])) / s, (a[2] + t * (b[2] - a[2])) / s);
            Eigen::Vector3d d = ea ? sp.inverse(l) : gp.inverse(l);
            if (d.z() < 0) d.z() = 0;  // equator points may round to -1e-17
            const int got = loc.locate(d);
            // The cells sharing this edge: c, and the cells having both of its end vertices (the neighbour
            // across it). Half cells: the polygon's equator edge belongs to c alone.
            int va = -1, vb = -1;
            for (int k = 0; k < 3; ++k) {
              const Eigen::Vector3d pv = g.vertices.row(g.faces(c, k));
              const Eigen::Vector3d la(a[0] / s, a[1] / s, a[2] / s), lb(b[0] / s, b[1] / s, b[2] / s);
              if ((pv - (ea ? sp.inverse(la) : gp.inverse(la))).norm() < kPointTol) va = g.faces(c, k);
              if ((pv - (ea ? sp.inverse(lb) : gp.inverse(lb))).norm() < kPointTol) vb = g.faces(c, k);
            }
            ASSERT_TRUE(va >= 0 && vb >= 0);
            const bool ok = got == c || (cell_has_vertex(g, got, va) && cell_has_vertex(g, got, vb));
            ASSERT_TRUE(ok) << kind << " level " << level << " cell " << c << " edge " << e << " t " << t;
          }
        }
      }
    }
}

TEST(CellLocator, PoleIsLocatedInACellTouchingIt) {
  const Eigen::Vector3d pole(0, 0, 1);
  for (int level = 0; level <= 8; ++level)
    for (const char* kind : {"equal-area", "geodesic"}) {
      const CellLocator loc(level, kind);
      const int c = loc.locate(pole);
      EXPECT_EQ(c, loc.locate(pole));  // deterministic
      if (level > 6) continue;
      const Grid g = build_hemi_icosahedral_grid(level, kind, 1);
      // The pole is the midpoint of the top icosahedron edge: a grid vertex for L >= 1, an edge point at L = 0.
      int pole_vertex = -1;
      for (int v = 0; v < g.vertices.rows(); ++v)
        if ((Eigen::Vector3d(g.vertices.row(v)) - pole).norm() < kPointTol) pole_vertex = v;
      if (level == 0) {
        ASSERT_EQ(pole_vertex, -1);
        // Both top cells contain the edge (0, +-1, phi); either is valid.
        const auto& v = icosahedron_vertices();
        int hits = 0;
        for (int k = 0; k < 3; ++k) {
          const Eigen::Vector3d p = g.vertices.row(g.faces(c, k));
          hits += ((p - v[0]).norm() < kPointTol) + ((p - v[2]).norm() < kPointTol);
        }
        EXPECT_EQ(hits, 2);
      } else {
        ASSERT_GE(pole_vertex, 0) << level;
        EXPECT_TRUE(cell_has_vertex(g, c, pole_vertex)) << kind << " " << level;
      }
    }
}

TEST(CellLocator, EquatorPointsLandInBoundaryCellsContainingThem) {
  std::mt19937_64 rng(99);
  std::uniform_real_distribution<double> u(0.0, 2 * M_PI);
  for (int level : {0, 2, 4})
    for (const char* kind : {"equal-area", "geodesic"}) {
      const Grid g = build_hemi_icosahedral_grid(level, kind, 1);
      const CellLocator loc(level, kind);
      for (int k = 0; k < 2000; ++k) {
        const double phi = u(rng);
        const Eigen::Vector3d d(std::cos(phi), std::sin(phi), 0.0);
        const int c = loc.locate(d);
        // c has an edge on the equator whose arc contains d.
        bool found = false;
        for (int e = 0; e < 3; ++e) {
          if (g.neighbours(c, e) >= 0) continue;
          const Eigen::Vector3d a = g.vertices.row(g.faces(c, (e + 1) % 3)), b = g.vertices.row(g.faces(c, (e + 2) % 3));
          auto ang = [](const Eigen::Vector3d& p, const Eigen::Vector3d& q) { return std::atan2(p.cross(q).norm(), p.dot(q)); };
          found = found || std::abs(ang(a, d) + ang(d, b) - ang(a, b)) < 1e-12;
        }
        ASSERT_TRUE(found) << kind << " level " << level << " phi " << phi;
      }
    }
}

TEST(CellLocator, BatchEqualsSingleAndIsDeterministic) {
  std::mt19937_64 rng(5);
  RowMatrix3d d(1003, 3);  // not a multiple of the block size
  for (int k = 0; k < d.rows(); ++k) d.row(k) = random_direction(rng).transpose();
  d.row(0) << 0, 0, 1;
  d.row(1) << 1, 0, 0;
  d.row(2) = icosahedron_vertices()[4].transpose();
  for (const char* kind : {"equal-area", "geodesic"}) {
    const CellLocator a(6, kind), b(6, kind);
    Eigen::VectorXi ca, cb;
    a.locate(d, ca);
    b.locate(d, cb);
    EXPECT_TRUE((ca.array() == cb.array()).all());
    for (int k = 0; k < d.rows(); ++k) ASSERT_EQ(a.locate(Eigen::Vector3d(d.row(k))), ca[k]);
  }
}

TEST(CellLocator, RejectsBadInput) {
  const CellLocator loc(3);
  EXPECT_THROW(loc.locate(Eigen::Vector3d(0, std::sqrt(1 - 1e-18), -1e-9)), ArgumentError);  // below the horizon
  EXPECT_NO_THROW(loc.locate(Eigen::Vector3d(1, 0, -1e-13)));                                   // rounding-sized
  EXPECT_THROW(loc.locate(Eigen::Vector3d(2, 0, 0)), ArgumentError);                             // not unit
  EXPECT_THROW(loc.locate(Eigen::Vector3d(std::nan(""), 0, 1)), ArgumentError);
  RowMatrix3d d(2, 3);
  d << 0, 0, 1, 0, 0, -1;
  Eigen::VectorXi c;
  EXPECT_THROW(loc.locate(d, c), ArgumentError);
  EXPECT_THROW(CellLocator(9), ArgumentError);
  EXPECT_THROW(CellLocator(-1), ArgumentError);
  EXPECT_THROW(CellLocator(2, "healpix"), ArgumentError);
}

}  // namespace ICOBRDF_UNITY_ID
