#include "icobrdf/core/fit/spectral_fit.hpp"

#include <string>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/basis/hemisphere_basis.hpp"
#include "icobrdf/core/spectrum/spectrum_ops.hpp"
#include "icobrdf/core/projection/streaming_projection.hpp"

namespace icobrdf {
namespace {

double anisotropy(const Eigen::MatrixXd& c, const Eigen::MatrixXd& iso) {
  const double total = c.squaredNorm();
  return total == 0.0 ? 0.0 : (c - iso).squaredNorm() / total;
}

Spectrum finish(std::vector<Eigen::MatrixXd> channels, const std::string& source, const ProjectionContext& ctx,
                const FitOptions& o, bool cosine) {
  Spectrum s;
  s.order = ctx.basis.order;
  s.cosine = cosine;
  s.isotropic = o.isotropic;
  s.source = source;
  s.filter = o.filter.name();
  s.level = ctx.grid->level;
  s.grid_kind = to_string(ctx.grid->kind);
  s.gram_error = ctx.basis.gram_error;
  double asym = 0.0, aniso = 0.0;
  for (auto& c : channels) {
    asym = std::max(asym, coefficient_asymmetry(c));
    if (!cosine && o.reciprocal) c = 0.5 * (c + c.transpose());
    const Eigen::MatrixXd iso = isotropic_part(c, s.order);
    aniso = std::max(aniso, anisotropy(c, iso));
    if (o.isotropic) c = iso;
    if (o.filter.kind != LowPassFilter::Kind::None) c = filter_coefficients(c, s.order, o.filter);
  }
  s.reciprocity_violation = asym;
  s.anisotropy_fraction = aniso;
  // White furnace from the spectrum at the cell directions: a(w) = K(w)^T C e (f), divided by cos(theta_i)
  // for g spectra (cells with a grazing representative direction are skipped there).
  double max_albedo = 0.0;
  for (const auto& c : channels) {
    const Eigen::VectorXd a = spectral_albedo(c, s.order, ctx.grid->directions);
    for (Eigen::Index i = 0; i < a.size(); ++i) {
      const double z = ctx.grid->directions(i, 2);
      if (cosine && z < kGrazingCellCos) continue;
      max_albedo = std::max(max_albedo, cosine ? a[i] / z : a[i]);
    }
  }
  s.max_albedo = max_albedo;
  s.channels = std::move(channels);
  return s;
}

}  // namespace

ProjectionContext make_projection_context(std::shared_ptr<const Grid> grid, int order, double gram_tolerance,
                                          ProjectionOperator::Kind kind, std::shared_ptr<const Grid> sampling_grid) {
  ProjectionContext ctx;
  ctx.sampling_grid = std::move(sampling_grid);
  ctx.basis = build_discrete_basis(*grid, order);
  check_supported(ctx.basis, gram_tolerance);
  ctx.projection = make_projection(ctx.basis, kind);
  ctx.grid = std::move(grid);
  return ctx;
}

ProjectionContext make_split_projection_context(std::shared_ptr<const Grid> grid, int order, double gram_tolerance, RowSplitExchange& exchange) {
  ProjectionContext ctx;
  auto ops = std::make_shared<SplitOperators>(split_operators(*grid, order, gram_tolerance, exchange));
  ctx.basis = ops->basis;
  ctx.split = std::move(ops);
  ctx.grid = std::move(grid);
  return ctx;
}

Spectrum fit_model(const BrdfModel& model, const ProjectionContext& ctx, const FitOptions& o) {
  const bool cosine = o.cosine || !model.delta_parts().empty();
  std::vector<Eigen::MatrixXd> channels;
  if (ctx.split) {
    if (!o.share || !o.share->rows)
      throw ArgumentError("fit of '" + quoted_text(model.spec()) + "': the operators are split by rows, but no row exchange was given");
    channels = row_split_projection(model, *ctx.grid, *ctx.split, cosine, o.sampling, ctx.sampling_grid.get(), *o.share->rows, o.share->every);
  } else {
    channels = streaming_projection(model, *ctx.grid, ctx.projection, cosine, o.sampling, ctx.sampling_grid.get(), o.share.get());
  }
  return finish(std::move(channels), model.spec(), ctx, o, cosine);
}

Spectrum fit_lut(const Lut& lut, const std::string& source, const ProjectionContext& ctx, const FitOptions& o) {
  if (ctx.split) throw UnsupportedError("fit of the LUT of '" + quoted_text(source) + "': its operators are split by rows over processes; a LUT needs them whole");
  std::vector<Eigen::MatrixXd> channels;
  for (const auto& f : lut.channels) channels.push_back(project_lut(ctx.projection, f));
  return finish(std::move(channels), source, ctx, o, lut.cosine);
}

Eigen::MatrixXd isotropic_part(const Eigen::MatrixXd& c, int order) {
  const int m = hemisphere_basis_count(order);
  if (c.rows() != m || c.cols() != m)
    throw ArgumentError("isotropic part: coefficient matrix is " + std::to_string(c.rows()) + " x " + std::to_string(c.cols()) +
                        ", expected " + std::to_string(m) + " x " + std::to_string(m) + " for order " + std::to_string(order));
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(m, m);
  for (int a = 0; a < m; ++a) {
    const auto na = ansi_to_nl(a);
    for (int b = 0; b < m; ++b) {
      const auto nb = ansi_to_nl(b);
      if (na.l != nb.l) continue;  // different |l| average out under rotation; l = -l' cross terms under mirroring
      if (na.l == 0) {
        out(a, b) = c(a, b);
      } else {
        // Partner entry with both azimuthal indices negated: (n^l, m^l) <-> (n^-l, m^-l).
        const int pa = ansi_index(na.n, -na.l), pb = ansi_index(nb.n, -nb.l);
        out(a, b) = 0.5 * (c(a, b) + c(pa, pb));
      }
    }
  }
  return out;
}

}  // namespace icobrdf
