#pragma once
// Lookup tables: a BRDF on a tessellation, one cells x cells matrix per channel.
//
// Row i = incident cell, column r = remitted cell. Entry = the average of f (or of g = f cos theta_i when
// `cosine`) over the pair of cells, computed with the cells' cubature (cell-averaged sampling) or at the
// cells' representative directions (centre sampling, faster, O(h^2) less accurate). Units 1/sr.
// Delta BRDFs (ideal mirror, retroreflector) exist only in g form: their cell average is
//   g_ir = weight * [r = image(i)] / Omega_r,
// image = the rotation by pi about the normal (mirror) or the identity (retroreflector), exact because the
// equal-area grid maps cells onto cells under these symmetries.
// A Helmholtz-reciprocal f gives a symmetric LUT; for g = f cos theta_i, f reciprocal means g D^-1
// symmetric with D the cell-mean cosines.
#include <Eigen/Core>

#include <optional>
#include <string>
#include <vector>

#include "icobrdf/core/models/brdf_model.hpp"
#include "icobrdf/core/grid/grid.hpp"

namespace icobrdf {

struct Lut {
  bool cosine = false;                    // entries are g = f cos theta_i
  std::vector<Eigen::MatrixXd> channels;  // cells x cells each
  int cells() const { return channels.empty() ? 0 : static_cast<int>(channels[0].rows()); }
};

enum class LutSampling { CellAverage, CellCentre };
// The sampling a command-line word names: "average", or "centre" (also spelt "center"); nullopt for any
// other word, so that each caller words its own error. Scene files are parsed by icobrdf/io/scene.cpp.
std::optional<LutSampling> lut_sampling_named(const std::string& word);

// Fills a block of rows [row_begin, row_end) of the LUT of `model`'s regular part (no delta parts):
// out is (row_end - row_begin) x cells for channel `channel`... for all channels: out[ch].
void sample_lut_rows(const BrdfModel& model, const Grid& grid, bool cosine, LutSampling sampling, int row_begin,
                     int row_end, std::vector<Eigen::MatrixXd>& out);
// The same for an arbitrary list of incident cells: out[ch] row k is the LUT row of cell row_cells[k]
// (ArgumentError for a cell outside the grid).
void sample_lut_rows(const BrdfModel& model, const Grid& grid, bool cosine, LutSampling sampling,
                     const std::vector<int>& row_cells, std::vector<Eigen::MatrixXd>& out);
// The same rows restricted to the first `col_end` remitted cells: out[ch] is row_cells.size() x col_end
// (ArgumentError unless 0 <= col_end <= cells). With a grid whose cells are reordered this samples any
// subset of columns, e.g. one triangle of a symmetric LUT (icobrdf/core/projection/streaming_projection.cpp).
void sample_lut_block(const BrdfModel& model, const Grid& grid, bool cosine, LutSampling sampling,
                      const std::vector<int>& row_cells, int col_end, std::vector<Eigen::MatrixXd>& out);
// The same block transposed: out[ch] is col_end x row_cells.size(), column k the LUT row of cell
// row_cells[k] (each row contiguous, as icobrdf/core/projection/projection_tile.hpp reads LUT columns). The same values,
// bit for bit.
void sample_lut_columns(const BrdfModel& model, const Grid& grid, bool cosine, LutSampling sampling,
                        const std::vector<int>& row_cells, int col_end, std::vector<Eigen::MatrixXd>& out);

// The whole LUT: regular part by blocks of rows (threads over rows; deterministic), plus delta parts in g
// form. A model with delta parts requires cosine = true (ArgumentError otherwise: f is singular).
Lut build_lut(const BrdfModel& model, const Grid& grid, bool cosine, LutSampling sampling = LutSampling::CellAverage);

// Adds weight * delta LUT (g form) of the given kind to `lut` (cells x cells).
void add_delta_lut(const DeltaPart& part, const Grid& grid, Eigen::MatrixXd& lut);

// Helmholtz reciprocity of an f LUT: ||F - F^T||_W / ||F||_W / 2, the relative norm of the antisymmetric
// part, with the solid-angle weighted norm ||F||_W^2 = sum Omega_i Omega_r F_ir^2 (the discrete L2 norm).
double reciprocity_violation(const Eigen::MatrixXd& lut, const Eigen::VectorXd& solid_angles);

// The closest reciprocal LUT in that norm: (F + F^T) / 2 (the weights Omega_i Omega_r are symmetric).
Eigen::MatrixXd symmetrize(const Eigen::MatrixXd& lut);

// Mean of cos theta over each cell (from its cubature): the D of the g <-> f conversion.
Eigen::VectorXd cell_mean_cosines(const Grid& grid);

}  // namespace icobrdf
