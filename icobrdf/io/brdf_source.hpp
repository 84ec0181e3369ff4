#pragma once
// BRDF sources: what a SOURCE argument names, opened behind one interface. Every command that takes a SOURCE
// (fit, eval, lut, plot, bank scenes) opens it here.
//
//   model:NAME[:key=value,...]   an analytic model (icobrdf/core/models/model_registry.hpp; `icobrdf models` lists them)
//   FILE.h5[#MATERIAL]           a spectrum in an icobrdf HDF5 file (spectrum file or bank); without
//                                #MATERIAL the file must hold exactly one material
//   MERL tables, RGL materials, CSV samples, SCATMECH coefficient files (icobrdf/io/measured_sources.hpp)
// A new kind of SOURCE is one more BrdfSource and one more branch of open_source: the builder
// (icobrdf/pipeline/) asks a source what it holds of its own (the questions at the end of BrdfSource) and never
// names a kind of source.
#include <Eigen/Core>

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "icobrdf/core/grid/grid.hpp"
#include "icobrdf/core/fit/spectral_fit.hpp"
#include "icobrdf/core/spectrum/spectrum.hpp"

namespace icobrdf {

class BrdfSource;

// Pairs of directions (rows x 3 each, unit vectors, w_i towards the light) and f [1/sr] there (rows x channels).
struct PairValues {
  RowMatrix3d wi, wr;
  Eigen::MatrixXd f;
};

// A material's request for held-out pairs from a source judged at its own samples
// (icobrdf/pipeline/held_out.hpp says which pairs each kind draws).
struct HeldOutRequest {
  std::string material;    // the material's name: the draw's seed is fnv1a64("holdout|" + material)
  int pairs = 0;           // the scene's holdout_pairs
  double incidence_min_deg = 0.0, incidence_max_deg = 90.0;  // w_i's polar angle range
  bool lights_and_cameras = false;  // the scene gives the material's pairs as lights x cameras
};

// Held-out scattered samples: one in kHeldOutShare (one fold of the 5-fold cross-validation `icobrdf fit`
// uses), at most the scene's holdout_pairs.
inline constexpr int kHeldOutShare = 5;
inline long long held_out_sample_count(long long samples, int holdout_pairs) {
  return samples / kHeldOutShare < holdout_pairs ? samples / kHeldOutShare : holdout_pairs;
}

// The held-out part of such a source: the pairs with the data's values, and the source without them (its
// fits never see them).
struct OwnHeldOut {
  PairValues pairs;
  std::unique_ptr<BrdfSource> training;
};

// Node counts of a half-angle table a source holds its data on (icobrdf/core/models/half_angle_factors.hpp:
// node placement), so that a lobe is fitted to its values as they are.
struct HalfAngleNodes {
  int n_t = 0, n_phi_h = 1, n_theta_d = 0, n_phi_d = 0;
  bool centred = false;
};

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

  // What the source holds of its own (the bank builder asks; defaults: a function known everywhere).
  // Values only at its own samples: eval() has nothing between them (scattered samples; only modes fit them).
  virtual bool values_only_at_samples() const { return false; }
  // eval() may give NaN where the data have no value (a MERL table's empty bins); fits leave such pairs out.
  virtual bool may_miss_values() const { return false; }
  // Unchanged by any turn about the normal by construction (a MERL table: its lookup depends on the half and
  // difference angles alone), so no isotropy check is needed.
  virtual bool isotropic_by_construction() const { return false; }
  // f(w_i, w_r) = f(w_r, w_i) by construction wherever it has values (an analytic model that says so,
  // BrdfModel::is_reciprocal; a MERL table, whose lookup depends on the half and difference angles alone,
  // which an exchange keeps; modes and lobes). Measured data that are not: the builder judges against their
  // reciprocal part (icobrdf/pipeline/held_out.hpp).
  virtual bool reciprocal_by_construction() const { return false; }
  // Judged at its own samples (own_held_out answers for it when the scene gives no lights x cameras): pairs
  // elsewhere would measure its lookup between samples, not the data.
  virtual bool judged_at_own_samples() const { return false; }
  // eval() costs far more per pair than a table lookup or a closed form (an RGL file: an inverse warp per
  // pair), so that the builder keeps the values of the node batches its fits ask for again
  // (icobrdf/pipeline/memo_source.hpp).
  virtual bool slow_to_evaluate() const { return false; }
  // The largest order of the modes (isotropic or general) a least-squares fit of its own samples determines;
  // -1 for a source without samples of its own.
  virtual int largest_sample_order(bool isotropic) const;
  // The half-angle nodes its data sit on, when they sit on such a table.
  virtual std::optional<HalfAngleNodes> own_half_angle_nodes() const;
  // Its own held-out split, drawn as `request` names it; nullopt when the builder is to draw pairs and
  // evaluate the source there. ArgumentError / InputError when the request cannot be met (messages name the
  // material).
  virtual std::optional<OwnHeldOut> own_held_out(const HeldOutRequest& request) const;
  // The standard deviation [1/sr] of independent noise on the data's values at the pairs (rows x channels),
  // estimated from the data's own grid (icobrdf/core/tables/grid_noise.hpp: an RGL material's value tables, a
  // MERL table's theta_h slabs); nullopt when the source has no grid to estimate it on (analytic models,
  // spectra, scattered samples: CSV, CURET, SCATMECH coefficients).
  virtual std::optional<Eigen::MatrixXd> noise_sigma_at(const RowMatrix3d& wi, const RowMatrix3d& wr) const;
};

// ArgumentError for an unknown kind or a malformed model spec; InputError / IoError for unreadable files.
std::unique_ptr<BrdfSource> open_source(const std::string& text);

// Names of eval()'s columns: "f" for 1 channel, "f_r,f_g,f_b" for 3, "f_0".."f_{n-1}" otherwise.
std::vector<std::string> channel_column_names(int channels);
// "f_" + name per channel when the source names its channels, else channel_column_names(channels).
std::vector<std::string> channel_column_names(const BrdfSource& source);

// A source wrapping a spectrum already in memory.
std::unique_ptr<BrdfSource> spectrum_source(Spectrum spectrum);
// A source wrapping a model already in memory (its spec() is "model:" + the model's).
std::unique_ptr<BrdfSource> model_source(std::unique_ptr<BrdfModel> model);

}  // namespace icobrdf
