#pragma once
// BRDF samples given as arrays instead of a CSV file (the Python module's icobrdf.Source.from_samples): the
// same BrdfSamples as a CSV file gives (icobrdf/io/sample_csv.hpp) and the same SOURCE and fit as a CSV SOURCE
// (icobrdf/io/measured_sources.hpp: order and model class by 5-fold cross-validation when no order is given,
// Tikhonov lambda by GCV, the fallbacks and the scale check; the spectrum carries the fit's record), so samples
// read from a file and handed over as arrays fit as the file does.
//
//   wi, wr    S x 3 unit vectors, pair by pair: +z the normal, z >= 0, w_i toward the light
//             (icobrdf/io/unit_directions.hpp checks them)
//   values    S x channels (1 or more), f in 1/sr, finite (negative values are accepted as noise and counted)
//   weights   S, finite and >= 0 (a sample of weight 0 takes no part in the fit); empty: every weight 1
// Rows naming the same pair (equal vectors) are merged as a CSV file's duplicate rows are: value = the weighted
// mean, weight = the sum of the weights, in the order of first appearance (the folds of the cross-validation
// are dealt by the index of a sample). Errors: ArgumentError naming the array, the row and what was expected.
#include <Eigen/Core>

#include <memory>
#include <string>

#include "icobrdf/core/fit/sample_fit.hpp"
#include "icobrdf/io/brdf_source.hpp"
#include "icobrdf/io/sample_csv.hpp"

namespace icobrdf {

// The samples of the arrays (BrdfSamples::path "arrays", lines = row + 1 of each sample's first row).
BrdfSamples samples_from_arrays(const RowMatrix3d& wi, const RowMatrix3d& wr, const Eigen::MatrixXd& values,
                                const Eigen::VectorXd& weights);

// What a CSV SOURCE's options (FILE.csv#tikhonov=...,power=...,rank-tol=...) say, for samples given as arrays.
struct SampleArrayFit {
  SampleFitOptions fit;        // tikhonov (lambda >= 0), tikhonov_power (>= 0), rank_tolerance (< 0: the default)
  bool tikhonov_auto = false;  // lambda by GCV (tikhonov=auto); a chosen order chooses lambda too unless one is given
};

// The SOURCE fitting `samples` as a CSV SOURCE does, named `spec` (its canonical text and the spectrum's source).
// ArgumentError for a negative or non-finite lambda or power. Defined with the CSV SOURCE in measured_sources.cpp.
std::unique_ptr<BrdfSource> open_sample_arrays(BrdfSamples samples, const SampleArrayFit& options, const std::string& spec);

}  // namespace icobrdf
