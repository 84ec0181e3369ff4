#pragma once
// BRDF sources: what a SOURCE argument names, opened behind one interface.
//
//   model:NAME[:key=value,...]   an analytic model (core/model_spec.hpp; `icobrdf models` lists them)
//   FILE.h5[#MATERIAL]           a spectrum in an icobrdf HDF5 file (spectrum file or bank); without
//                                #MATERIAL the file must hold exactly one material
// Readers of measured data (MERL, CSV samples, coefficient files) join here as further kinds.
#include <Eigen/Core>

#include <memory>
#include <string>

#include "core/grid.hpp"
#include "core/spectral_fit.hpp"
#include "core/spectrum.hpp"

namespace icobrdf {

class BrdfSource {
 public:
  virtual ~BrdfSource() = default;
  virtual std::string spec() const = 0;  // canonical SOURCE text
  virtual int channels() const = 0;
  // f [1/sr] at direction pairs (rows x 3 each): rows x channels. Delta parts of models are not included
  // (has_delta() tells); spectra of g = f cos(theta_i) are divided by cos(theta_i) (infinite at grazing).
  virtual Eigen::MatrixXd eval(const RowMatrix3d& wi, const RowMatrix3d& wr) const = 0;
  virtual bool has_delta() const { return false; }
  // The spectrum of this source for the context's grid and order.
  virtual Spectrum fit(const ProjectionContext& ctx, const FitOptions& options) const = 0;
};

// ArgumentError for an unknown kind or a malformed model spec; InputError / IoError for unreadable files.
std::unique_ptr<BrdfSource> open_source(const std::string& text);

// A source wrapping a spectrum already in memory.
std::unique_ptr<BrdfSource> spectrum_source(Spectrum spectrum);

}  // namespace icobrdf
