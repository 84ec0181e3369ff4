#pragma once
// Report section "baselines" (`bench sweep`, also `bench baselines`):
// 1. How many cells each hemisphere grid needs to resolve an order (icobrdf/lab/grid_comparison.hpp): for the
//    equal-area grid at every level (cell averages with its degree-9 cubature, and centre sampling), the
//    geodesic grid of the same level (exact cell weights, degree-9 cubature), a latitude-longitude grid with
//    about the same cell count (n_theta x 4 n_theta cells, 5 x 5 Gauss points per cell: degree 9 as well) and
//    the polar-Gauss product rule with about the same node count (r rings x 4r azimuths, exact to order
//    2r - 1): the Gram error max|G - I| and the condition number of G per order, the largest order each
//    supports at the tolerances 0.1, 1e-2, 1e-3, and the cells each needs for orders 4, 8, 12, 16 (smallest
//    built size meeting the tolerance, and the log-log interpolation between the two built sizes around it;
//    for the polar-Gauss rule the smallest ring count found by search with 2n + 1 azimuths).
// 2. Direct quadrature without matrices against the matrix path (icobrdf/lab/direct_vs_matrix.hpp).
#include "icobrdf/lab/report_section.hpp"

namespace icobrdf::lab {

// Largest order measured on the baseline grids (the sweep may ask for more).
inline constexpr int kMaxBaselineOrder = 32;

// Runs the section; ArgumentError without a level or an order.
ReportSection run_baselines(const SectionOptions& o);

}  // namespace icobrdf::lab
