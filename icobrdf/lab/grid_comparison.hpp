#pragma once
// How many cells each hemisphere grid needs to resolve an order: the equal-area grid of a level (cell
// averages with its degree-9 cubature, and centre sampling), the geodesic grid of the same level, a
// latitude-longitude grid and the polar-Gauss product rule of about the same cell count. Each grid samples
// the hemisphere basis K (B, cells x modes) and forms G = B^T W B; G = I for the continuous basis, so the
// Gram error max|G - I| per order says how faithfully the grid represents it.
#include <Eigen/Core>
#include <functional>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "icobrdf/core/projection/discrete_basis.hpp"
#include "icobrdf/core/grid/grid.hpp"

namespace icobrdf::lab {

// Gram-error tolerances of the "largest order" and "cells needed" tables: the library's default (10%) and
// two stricter ones.
inline constexpr double kBaselineTolerances[] = {1e-1, 1e-2, 1e-3};
// Gauss points per direction in a lat-long cell: degree 2*5-1 = 9 in cos(theta) and phi, as the degree-9
// rule of the icosahedral cells.
inline constexpr int kLatLongPoints = 5;
// The grid kinds in table order.
inline const std::vector<std::string> kGridKinds = {"equal-area", "equal-area-centre", "geodesic", "lat-long", "polar-gauss"};

struct GridRun {
  std::string kind;   // one of kGridKinds
  std::string size;   // "level 3" or "rings x azimuths"
  int level = 0;      // tessellation level whose cell count it matches
  int cells = 0;
  int rings = 0, azimuths = 0;  // lat-long bands x sectors, polar-gauss rings x azimuths (0 for the others)
  Eigen::Index points = 0;
  double grid_seconds = 0.0, basis_seconds = 0.0;
  std::vector<double> gram;           // max|G - I| per order 0..max order
  std::map<int, double> condition;    // lambda_max / lambda_min of G, at the requested orders
  std::vector<int> largest;           // largest supported order per tolerance of kBaselineTolerances
};

// max|G - I| of the leading block of order n, for n = 0..b.order.
std::vector<double> gram_errors(const DiscreteBasis& b);

// lambda_max / lambda_min of the leading block of G of order n (inf when singular).
double condition_of_block(const DiscreteBasis& b, int n);

// Builds the grid (timed), its basis to `order` (timed) and the figures of a GridRun.
GridRun measure_grid(const std::string& kind, const std::string& size, int level, const std::function<Grid()>& build, int order,
                     const std::vector<int>& condition_orders);

// The five grids of every level, in level order then kGridKinds order: lat-long and polar-gauss with
// k x 4k cells, k = round(sqrt(cells / 4)) of the level's equal-area grid.
std::vector<GridRun> measure_matched_grids(const std::vector<int>& levels, int order, const std::vector<int>& condition_orders);

// Polar-Gauss rule with 2n + 1 azimuths: the smallest ring count whose Gram error at order n is <= tol
// (search upward; exactness predicts rings = ceil((n + 1)/2)).
struct PolarSearch {
  int rings = 0, cells = 0;  // rings = 0: not found (cannot happen for an exact rule; reported as such)
  double gram = 0.0, gram_one_ring_less = std::numeric_limits<double>::quiet_NaN();
};
PolarSearch polar_gauss_search(int n, double tol);

// Cells for Gram error `tol` at order n from a family of sizes (ascending cells): the first size meeting it,
// and the log-log interpolation between it and the size before (the Gram error of cell averages falls as a
// power of the cell size). NaN interpolation when the first size already meets it or none does.
struct CellsNeeded {
  int smallest_built = -1;  // -1: none of the built sizes meets the tolerance
  double interpolated = std::numeric_limits<double>::quiet_NaN();
};
CellsNeeded cells_needed(const std::vector<const GridRun*>& family, int n, double tol);

}  // namespace icobrdf::lab
