// Equal-area and geodesic hemi-icosahedral grids: cell counts, exact solid angles measured independently
// (spherical-polygon area of the refined curved cell boundary with Richardson extrapolation), the grid
// invariants, the OpenMesh mesh checker, neighbours, the equator, symmetry permutations and hierarchy.
#include <gtest/gtest.h>

#include <OpenMesh/Tools/Utils/MeshCheckerT.hh>

#include <Eigen/Geometry>

#include <cmath>
#include <cstdio>
#include <map>
#include <set>
#include <sstream>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/mesh/cell_locator.hpp"
#include "icobrdf/mesh/hemi_lattice.hpp"
#include "icobrdf/mesh/icosahedron.hpp"
#include "icobrdf/mesh/snyder_projection.hpp"
#include "icobrdf/mesh/tessellation.hpp"
#include "icobrdf/mesh/tessellation_mesh.hpp"
#include "tests/support/unity_id.hpp"

using namespace icobrdf;

namespace ICOBRDF_UNITY_ID {
// Sum of up to 655872 exactly rounded solid angles, accumulated in long double: 1e-13 is the required bound.
constexpr double kSumTol = 1e-13;
// Independent area measurement: Romberg-extrapolated polygon areas (K = 128, 256, 512 points per edge)
// converge like K^-6; for the cells around a face centre (where the map's derivatives are largest) the
// remaining error is ~1e-13 (measured: 7.8e-12 with K = 64..256, 1.2e-13 with 128..512). Required: 1e-12.
constexpr double kAreaRelTol = 1e-12;
// Positions of symmetric points computed through different faces agree to rounding.
constexpr double kPointTol = 1e-14;

long double accurate_sum(const Eigen::VectorXd& v) {
  long double s = 0;
  for (Eigen::Index i = 0; i < v.size(); ++i) s += v[i];
  return s;
}

std::array<Eigen::Vector3d, 3> corners(int f) {
  const auto& v = icosahedron_vertices();
  const auto& h = hemi_icosahedron_faces()[f];
  return {v[h.v[0]], v[h.v[1]], v[h.v[2]]};
}

// Signed solid angle of the geodesic triangle (a, b, c), Van Oosterom-Strackee. The triple product is
// evaluated as a . ((b - a) x (c - b)): for the thin fan triangles (b, c adjacent boundary samples) this
// avoids the cancellation of crossing two nearly parallel vectors.
double tri_area(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const double num = a.dot((b - a).cross(c - b));
  const double den = 1.0 + a.dot(b) + b.dot(c) + c.dot(a);
  return 2.0 * std::atan2(num, den);
}

// Area of the curved cell c: its planar boundary sampled with K points per edge, each mapped to the sphere
// by the inverse projection, and the resulting spherical polygon's area (fan from the cell direction).
// This measures the area geometrically and does not use the projection's equal-area property.
double polygon_area(const HemiLattice& lat, const SnyderProjection& p, int c, const Eigen::Vector3d& centre, int k) {
  const auto poly = lat.polygon(c);
  const double s = static_cast<double>(lat.scale());
  std::vector<Eigen::Vector3d> ring;
  for (size_t e = 0; e < poly.size(); ++e) {
    const auto& a = poly[e];
    const auto& b = poly[(e + 1) % poly.size()];
    for (int t = 0; t < k; ++t) {
      const double u = static_cast<double>(t) / k;
      const Eigen::Vector3d l((a[0] + u * (b[0] - a[0])) / s, (a[1] + u * (b[1] - a[1])) / s, (a[2] + u * (b[2] - a[2])) / s);
      ring.push_back(p.inverse(l));
    }
  }
  long double area = 0;
  for (size_t i = 0; i < ring.size(); ++i) area += tri_area(centre, ring[i], ring[(i + 1) % ring.size()]);
  return static_cast<double>(area);
}

// Romberg: areas with K, 2K, 4K samples per edge (error expansion in K^-2, K^-4, ...). Edges are sampled so
// that the kinks of the map (where an edge crosses a face median: at edge midpoints) are sample points.
double extrapolated_area(const HemiLattice& lat, const SnyderProjection& p, int c, const Eigen::Vector3d& centre) {
  const double a1 = polygon_area(lat, p, c, centre, 128), a2 = polygon_area(lat, p, c, centre, 256),
               a3 = polygon_area(lat, p, c, centre, 512);
  const double r1 = (4 * a2 - a1) / 3, r2 = (4 * a3 - a2) / 3;
  return (16 * r2 - r1) / 15;
}

// Expected cell count at level L. Per face the aperture-4 lattice has 4^L triangles. The 8 whole upper
// faces give 8 4^L. A bisected face is cut by the median l1 = l2, which passes through the lattice points
// (i, i) and bisects exactly the 2^L lattice triangles with i = j (up: 2i <= n-1, down: 2i <= n-2, n = 2^L,
// i.e. n/2 each for n even and 1 up for n = 1); the remaining 4^L - 2^L triangles split evenly between the
// two sides (the median is a mirror line). So each bisected face gives (4^L - 2^L)/2 whole + 2^L half
// cells, and the total is 8 4^L + 4 ((4^L - 2^L)/2 + 2^L) = 10 4^L + 2^(L+1).
long long expected_cells(int level) { return 10LL * (1LL << (2 * level)) + (2LL << level); }

TEST(Tessellation, CellCountsMatchFormulaForAllLevels) {
  for (int level = 0; level <= 8; ++level) {
    const HemiLattice lat(level);
    EXPECT_EQ(lat.cells(), expected_cells(level)) << level;
    int half = 0;
    for (int c = 0; c < lat.cells(); ++c) half += lat.cell(c).half;
    EXPECT_EQ(half, 4 << level) << level;  // 2^L half cells on each of the 4 bisected faces
  }
  EXPECT_EQ(expected_cells(8), 655872);
  for (int level = 0; level <= 5; ++level) {
    EXPECT_EQ(build_equal_area_grid(level, 3).cells(), expected_cells(level));
    EXPECT_EQ(build_geodesic_grid(level, 3).cells(), expected_cells(level));
  }
}

TEST(Tessellation, RejectsBadArguments) {
  EXPECT_THROW(build_equal_area_grid(-1), ArgumentError);
  EXPECT_THROW(build_equal_area_grid(9), ArgumentError);
  EXPECT_THROW(build_geodesic_grid(9), ArgumentError);
  EXPECT_THROW(build_equal_area_grid(2, 0), ArgumentError);
  EXPECT_THROW(build_hemi_icosahedral_grid(2, "cubed-sphere"), ArgumentError);
}

TEST(Tessellation, SolidAnglesSumToTwoPiAndGridsValidate) {
  for (int level = 0; level <= 6; ++level) {
    for (const char* kind : {"equal-area", "geodesic"}) {
      const Grid g = build_hemi_icosahedral_grid(level, kind, level <= 4 ? 9 : 1);
      EXPECT_NO_THROW(validate(g)) << kind << " " << level;
      EXPECT_NEAR(static_cast<double>(accurate_sum(g.solid_angles) - 2 * static_cast<long double>(M_PI)), 0.0, kSumTol)
          << kind << " " << level;
      EXPECT_STREQ(to_string(g.kind), kind);
      EXPECT_EQ(g.level, level);
    }
  }
}

TEST(Tessellation, LevelEightBuildsAndValidates) {
  const Grid g = build_equal_area_grid(8, 1);  // 1-point rule keeps the test light; the layout is the same
  EXPECT_EQ(g.cells(), 655872);
  EXPECT_NO_THROW(validate(g));
  EXPECT_NEAR(static_cast<double>(accurate_sum(g.solid_angles) - 2 * static_cast<long double>(M_PI)), 0.0, kSumTol);
  const double whole = 4 * M_PI / (20.0 * 65536.0);
  for (int c = 0; c < g.cells(); c += 97) EXPECT_NEAR(g.solid_angles[c], g.is_half[c] ? whole / 2 : whole, 1e-16 * whole);
}

TEST(Tessellation, EveryCellAreaMeasuredIndependentlyIsExact) {
  // All cells at levels 0..3, a sample at levels 5 and 8.
  double worst = 0;
  int measured = 0;
  for (int level : {0, 1, 2, 3, 5, 8}) {
    const HemiLattice lat(level);
    std::vector<SnyderProjection> proj;
    for (int f = 0; f < 12; ++f) proj.emplace_back(corners(f));
    const double whole = 4 * M_PI / (20.0 * std::pow(4.0, level));
    const int step = level <= 3 ? 1 : (level == 5 ? 37 : 2011);
    for (int c = 0; c < lat.cells(); c += step) {
      const auto& cl = lat.cell(c);
      const auto poly = lat.polygon(c);
      Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
      for (const auto& q : poly) centroid += Eigen::Vector3d(q[0], q[1], q[2]);
      const Eigen::Vector3d centre = proj[cl.face].inverse(centroid / centroid.sum());
      const double area = extrapolated_area(lat, proj[cl.face], c, centre);
      const double expect = cl.half ? whole / 2 : whole;
      worst = std::max(worst, std::abs(area / expect - 1));
      ++measured;
    }
  }
  std::printf("independent cell areas: %d cells, max relative deviation from 4pi/(20 4^L) %.3g\n", measured, worst);
  RecordProperty("max_relative_area_error", std::to_string(worst));
  EXPECT_LT(worst, kAreaRelTol);
}

TEST(Tessellation, GeodesicBaselineAreasAndRatio) {
  // Geodesic cells are geodesic triangles: check their solid angles against L'Huilier's theorem
  // (independent of the Van Oosterom-Strackee formula used by the grid) and report max/min.
  for (int level = 0; level <= 5; ++level) {
    const Grid g = build_geodesic_grid(level, 1);
    double mn = 1e9, mx = 0;
    for (int c = 0; c < g.cells(); ++c) {
      const Eigen::Vector3d a = g.vertices.row(g.faces(c, 0)), b = g.vertices.row(g.faces(c, 1)), d = g.vertices.row(g.faces(c, 2));
      auto arc = [](const Eigen::Vector3d& p, const Eigen::Vector3d& q) { return std::atan2(p.cross(q).norm(), p.dot(q)); };
      const double x = arc(b, d), y = arc(d, a), z = arc(a, b), s = (x + y + z) / 2;
      const double e = 4 * std::atan(std::sqrt(std::tan(s / 2) * std::tan((s - x) / 2) * std::tan((s - y) / 2) * std::tan((s - z) / 2)));
      EXPECT_NEAR(g.solid_angles[c], e, 1e-10 * e) << level << " " << c;  // L'Huilier loses digits on thin triangles
      if (!g.is_half[c]) {
        mn = std::min(mn, g.solid_angles[c]);
        mx = std::max(mx, g.solid_angles[c]);
      }
    }
    std::printf("geodesic level %d: whole-cell solid angle max/min = %.6f\n", level, mx / mn);
    RecordProperty("geodesic_ratio_level_" + std::to_string(level), std::to_string(mx / mn));
    if (level >= 1) {
      EXPECT_GT(mx / mn, 1.1);  // the baseline is not equal-area
    }
  }
}

TEST(Tessellation, OpenMeshCheckerPassesAndMeshIsADisk) {
  for (int level = 0; level <= 5; ++level)
    for (const char* kind : {"equal-area", "geodesic"}) {
      const auto tm = build_tessellation_mesh(level, kind);
      std::ostringstream log;
      OpenMesh::Utils::MeshCheckerT<TessellationTriMesh> checker(tm->mesh);
      EXPECT_TRUE(checker.check(OpenMesh::Utils::MeshCheckerT<TessellationTriMesh>::CHECK_ALL, log)) << log.str();
      const auto& m = tm->mesh;
      // A disk: Euler characteristic 1; 6 * 2^L boundary edges (derivation in EquatorIsTheBoundary).
      EXPECT_EQ(static_cast<long>(m.n_vertices()) - static_cast<long>(m.n_edges()) + static_cast<long>(m.n_faces()), 1);
      int boundary = 0;
      for (auto e : m.edges()) boundary += m.is_boundary(e);
      EXPECT_EQ(boundary, 6 << level);
      for (auto f : m.faces()) EXPECT_EQ(m.property(tm->cell_id, f), f.idx());
    }
}

TEST(Tessellation, EquatorIsTheBoundaryAndNeighboursAreConsistent) {
  // The equator consists of 2 whole icosahedron edges (n lattice edges each) and 4 medians of bisected
  // faces (n half-cell edges each): 6 n boundary edges, 6 n boundary vertices, all on z = 0, going once
  // around (total arc 2 pi).
  for (int level = 0; level <= 5; ++level)
    for (const char* kind : {"equal-area", "geodesic"}) {
      const Grid g = build_hemi_icosahedral_grid(level, kind, 1);
      const int n = 1 << level;
      int minus = 0;
      double arc = 0;
      for (int c = 0; c < g.cells(); ++c)
        for (int k = 0; k < 3; ++k) {
          const int nb = g.neighbours(c, k);
          const int a = g.faces(c, (k + 1) % 3), b = g.faces(c, (k + 2) % 3);
          if (nb < 0) {
            ++minus;
            EXPECT_NEAR(g.vertices(a, 2), 0.0, kPointTol);
            EXPECT_NEAR(g.vertices(b, 2), 0.0, kPointTol);
            const Eigen::Vector3d pa = g.vertices.row(a), pb = g.vertices.row(b);
            arc += std::atan2(pa.cross(pb).norm(), pa.dot(pb));
            continue;
          }
          // The neighbour shares the edge (a, b) and points back.
          std::set<int> vs{g.faces(nb, 0), g.faces(nb, 1), g.faces(nb, 2)};
          EXPECT_TRUE(vs.count(a) && vs.count(b));
          EXPECT_TRUE(g.neighbours(nb, 0) == c || g.neighbours(nb, 1) == c || g.neighbours(nb, 2) == c);
        }
      EXPECT_EQ(minus, 6 * n);
      EXPECT_NEAR(arc, 2 * M_PI, 1e-12);
      // Every half cell has exactly one edge on the equator; faces are counter-clockwise from outside.
      for (int c = 0; c < g.cells(); ++c) {
        const Eigen::Vector3d a = g.vertices.row(g.faces(c, 0)), b = g.vertices.row(g.faces(c, 1)), d = g.vertices.row(g.faces(c, 2));
        EXPECT_GT((b - a).cross(d - a).dot(a + b + d), 0.0);
        if (g.is_half[c]) {
          EXPECT_EQ((g.neighbours.row(c).array() < 0).count(), 1);
        }
      }
    }
}

TEST(Tessellation, DirectionsLieInTheirCells) {
  for (int level = 0; level <= 6; ++level)
    for (const char* kind : {"equal-area", "geodesic"}) {
      const Grid g = build_hemi_icosahedral_grid(level, kind, 1);
      const CellLocator loc(level, kind);
      for (int c = 0; c < g.cells(); ++c) ASSERT_EQ(loc.locate(Eigen::Vector3d(g.directions.row(c))), c) << kind << level;
    }
}

TEST(Tessellation, SymmetryPermutationsAreExact) {
  for (int level = 0; level <= 4; ++level)
    for (const char* kind : {"equal-area", "geodesic"}) {
      const Grid g = build_hemi_icosahedral_grid(level, kind, 9);
      const CellLocator loc(level, kind);
      const std::array<const Eigen::VectorXi*, 3> perms{&g.rotate_pi, &g.mirror_xz, &g.mirror_yz};
      const std::array<Eigen::Vector3d, 3> signs{Eigen::Vector3d(-1, -1, 1), Eigen::Vector3d(1, -1, 1), Eigen::Vector3d(-1, 1, 1)};
      for (int s = 0; s < 3; ++s) {
        const auto& p = *perms[s];
        for (int c = 0; c < g.cells(); ++c) {
          ASSERT_EQ(p[p[c]], c);  // involution
          EXPECT_NEAR(g.solid_angles[p[c]], g.solid_angles[c], 1e-15);
          EXPECT_EQ(g.is_half[p[c]], g.is_half[c]);
          // Images of every cubature point land in the partner cell.
          for (auto r = g.cubature_offsets[c]; r < g.cubature_offsets[c + 1]; ++r) {
            const Eigen::Vector3d q = Eigen::Vector3d(g.cubature_points.row(r)).cwiseProduct(signs[s]);
            ASSERT_EQ(loc.locate(q), p[c]) << kind << " level " << level << " symmetry " << s << " cell " << c;
          }
          // The partner's vertices are the images of the cell's vertices.
          for (int k = 0; k < 3; ++k) {
            const Eigen::Vector3d im = Eigen::Vector3d(g.vertices.row(g.faces(c, k))).cwiseProduct(signs[s]);
            double best = 1e9;
            for (int kk = 0; kk < 3; ++kk) best = std::min(best, (Eigen::Vector3d(g.vertices.row(g.faces(p[c], kk))) - im).norm());
            EXPECT_LT(best, kPointTol);
          }
        }
      }
    }
}

TEST(Tessellation, ChildrenTileTheirParent) {
  for (int level = 0; level <= 4; ++level) {
    const Grid parent = build_equal_area_grid(level, 5);
    const Grid child = build_equal_area_grid(level + 1, 5);
    const CellLocator loc(level);
    std::vector<double> sum(parent.cells(), 0.0);
    std::vector<int> count(parent.cells(), 0);
    for (int c = 0; c < child.cells(); ++c) {
      const int p = loc.locate(Eigen::Vector3d(child.directions.row(c)));
      sum[p] += child.solid_angles[c];
      ++count[p];
      for (auto r = child.cubature_offsets[c]; r < child.cubature_offsets[c + 1]; ++r)
        ASSERT_EQ(loc.locate(Eigen::Vector3d(child.cubature_points.row(r))), p) << level << " " << c;
    }
    for (int p = 0; p < parent.cells(); ++p) {
      EXPECT_EQ(count[p], parent.is_half[p] ? 3 : 4);  // a half parent: 1 whole + 2 half children
      EXPECT_NEAR(sum[p], parent.solid_angles[p], 1e-15 * parent.solid_angles[p] * 4);
    }
  }
}

}  // namespace ICOBRDF_UNITY_ID
