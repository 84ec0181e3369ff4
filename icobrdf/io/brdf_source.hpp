#pragma once
// BRDF sources: what a SOURCE argument names, opened behind one interface. Every command that takes a SOURCE
// (fit, eval, lut, plot, bank scenes) opens it here.
//
//   model:NAME[:key=value,...]   an analytic model (icobrdf/core/models/model_registry.hpp; `icobrdf models` lists them)
//   FILE.h5[#MATERIAL]           a spectrum in an icobrdf HDF5 file (spectrum file or bank); without
//                                #MATERIAL the file must hold exactly one material
//   MERL tables, RGL materials, CSV samples, SCATMECH coefficient files (icobrdf/io/measured_sources.hpp)
// A new kind of SOURCE is one more BrdfSource and one more branch of open_source.
#include <Eigen/Core>

#include <memory>
#include <string>
#include <vector>

#include "icobrdf/core/grid/grid.hpp"
#include "icobrdf/core/fit/spectral_fit.hpp"
#include "icobrdf/core/spectrum/spectrum.hpp"

namespace icobrdf {

class BrdfSource {
 public:
  virtual ~BrdfSource() = default;
  virtual std::string spec() const = 0;  // canonical SOURCE text
  virtual int channels() const = 0;
  // Names of the channels ("r", "g", "b"; "550nm"), one per channel, or empty when the source names none.
  virtual std::vector<std::string> channel_names() const { return {}; }
  // f [1/sr] at direction pairs (rows x 3 each): rows x channels. Delta parts of models are not included
  // (has_delta() tells); spectra of g = f cos(theta_i) are divided by cos(theta_i) (infinite at grazing).
  virtual Eigen::MatrixXd eval(const RowMatrix3d& wi, const RowMatrix3d& wr) const = 0;
  virtual bool has_delta() const { return false; }
  // Remarks on the values of eval() for a reader (e.g. that a delta part is not representable pointwise).
  virtual std::vector<std::string> notes() const { return {}; }
  // The spectrum of this source for the context's grid and order.
  virtual Spectrum fit(const ProjectionContext& ctx, const FitOptions& options) const = 0;
};

// ArgumentError for an unknown kind or a malformed model spec; InputError / IoError for unreadable files.
std::unique_ptr<BrdfSource> open_source(const std::string& text);

// Names of eval()'s columns: "f" for 1 channel, "f_r,f_g,f_b" for 3, "f_0".."f_{n-1}" otherwise.
std::vector<std::string> channel_column_names(int channels);
// "f_" + name per channel when the source names its channels, else channel_column_names(channels).
std::vector<std::string> channel_column_names(const BrdfSource& source);

// A source wrapping a spectrum already in memory.
std::unique_ptr<BrdfSource> spectrum_source(Spectrum spectrum);

}  // namespace icobrdf
