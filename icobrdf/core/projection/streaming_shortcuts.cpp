#include "icobrdf/core/projection/streaming_shortcuts.hpp"

#include <string>

#include "icobrdf/core/basis/grid_symmetry.hpp"
#include "icobrdf/core/support/error.hpp"

namespace icobrdf {

StreamingShortcuts streaming_shortcuts(const BrdfModel& model, const Grid& g, const Grid& sg, bool cosine, LutSampling sampling) {
  if (sg.cells() != g.cells() || (sg.solid_angles - g.solid_angles).cwiseAbs().maxCoeff() > kSameCellsRelTol * g.solid_angles.maxCoeff())
    throw ArgumentError("projection: the sampling grid's cells differ from the projection grid's (" + std::to_string(sg.cells()) +
                        " vs " + std::to_string(g.cells()) + " cells)");
  if (!model.delta_parts().empty() && !cosine)
    throw ArgumentError("projection of '" + quoted_text(model.spec()) + "': a delta BRDF has no finite f; use the cosine-weighted form g");
  StreamingShortcuts k;
  // An isotropic model on a D2-symmetric grid has F(s i, s r) = F(i, r) for each symmetry s, so row s i of
  // F P is row i times the signs of the modes: only one incident cell per orbit is sampled (a quarter of
  // the rows), and C = sum_s D_s X D_s with X = sum over representatives i of P_i^T (F P)_i / |stabilizer
  // of i|, D_s the diagonal of mode signs. The sum over the four symmetries keeps 4 X_ab where modes a and b
  // have the same signs under all of them and zeroes the rest (entries that vanish exactly by symmetry).
  // (icobrdf/core/basis/grid_symmetry.hpp) The symmetric sampling makes F itself D2-invariant; the orbits and the
  // cell maps are those of sg, which equal g's (checked here).
  k.d2 = model.is_isotropic() && has_d2_maps(g) && has_d2_maps(sg) && g.rotate_pi == sg.rotate_pi && g.mirror_xz == sg.mirror_xz &&
         g.mirror_yz == sg.mirror_yz && sampling_is_d2_symmetric(sg, sampling == LutSampling::CellCentre);
  k.reciprocal = model.is_reciprocal() && (!cosine || sampling == LutSampling::CellCentre);
  return k;
}

}  // namespace icobrdf
