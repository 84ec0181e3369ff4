// Discrete engine: sampled basis, projection, reconstruction, smoothing, delta LUTs, reciprocity,
// rotation, reflection. Expected values are derived in the comments from the definitions
// (icobrdf/core/projection/discrete_basis.hpp, icobrdf/core/projection/projection.hpp), never taken from the code's output.
#include <gtest/gtest.h>

#include <Eigen/QR>

#include <cmath>
#include <omp.h>
#include <random>

#include "icobrdf/core/models/brdf_model.hpp"
#include "icobrdf/core/basis/direction.hpp"
#include "icobrdf/core/projection/discrete_basis.hpp"
#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/basis/hemisphere_basis.hpp"
#include "icobrdf/core/projection/lut.hpp"
#include "icobrdf/core/projection/projection.hpp"
#include "icobrdf/core/grid/reference_grids.hpp"
#include "icobrdf/core/projection/reflection.hpp"
#include "icobrdf/core/spectrum/spectrum_ops.hpp"
#include "icobrdf/core/projection/streaming_projection.hpp"
#include "icobrdf/core/basis/isotropic_modes.hpp"
#include "icobrdf/core/fit/spectral_fit.hpp"
#include "tests/support/unity_id.hpp"

using namespace icobrdf;

namespace ICOBRDF_UNITY_ID {

// Products of matrices with O(100) to O(1000) terms of size O(1): 1e-12 covers their rounding.
constexpr double kAlgebraTol = 1e-12;
// The polar Gauss grid integrates K_a K_b exactly; its Gram matrix differs from I by rounding only.
constexpr double kExactQuadratureTol = 1e-13;
// The exact-span recoveries go through G^-1 of a grid whose condition number is ~1.1: 1e-10 covers the
// rounding of the solve and of the quadrature reference.
constexpr double kSpanRecoveryTol = 1e-10;
// Evaluating a rotated order-5 spectrum sums ~400 products of O(1) terms: 1e-11 covers it.
constexpr double kEvaluationTol = 1e-11;
// A lat-long grid's Gram error is O(1e-3); anything above 1e-6 shows G is not the identity.
constexpr double kNotIdentity = 1e-6;
// The two sides of the adjoint identity sum ~1e6 products in different orders: 1e-10 relative.
constexpr double kAdjointTol = 1e-10;
// f = (1 + x_i)/pi has an antisymmetric part of order 0.1 of its norm; 0.01 separates it from rounding.
constexpr double kClearlyNonReciprocal = 0.01;
// C = D G^-1 differs from D by (G^-1 - I), whose entries are at most a small multiple of the Gram error to
// first order (the 3 covers second-order terms on this small grid).
constexpr double kFirstOrderFactor = 3.0;
// A filter weight is one elementary function of an exact fraction: a few ulps.
constexpr double kWeightTol = 1e-15;

// f = 1/pi: unit-albedo Lambert.
struct ConstantModel final : BrdfModel {
  double value;
  explicit ConstantModel(double v) : value(v) {}
  using BrdfModel::eval;
  void eval(const RowMatrix3d&, const RowMatrix3d&, Eigen::Ref<Eigen::MatrixXd> out) const override {
    out.setConstant(value);
  }
  std::string spec() const override { return "constant"; }
};

// Minnaert with k = 3: f = (k+1)/(2 pi) (cos_i cos_r)^(k-1) = 2/pi (cos_i cos_r)^2, a polynomial of degree 2
// in rho^2 in each direction (cos = 1 - rho^2), hence in the span of K up to order 4.
struct Minnaert3 final : BrdfModel {
  using BrdfModel::eval;
  void eval(const RowMatrix3d& wi, const RowMatrix3d& wr, Eigen::Ref<Eigen::MatrixXd> out) const override {
    out.col(0) = (2.0 / M_PI) * (wi.col(2).array() * wr.col(2).array()).square().matrix();
  }
  std::string spec() const override { return "minnaert3"; }
};

// A deliberately non-reciprocal f = (1 + x_i) / pi (depends on the incident direction only).
struct NonReciprocal final : BrdfModel {
  using BrdfModel::eval;
  void eval(const RowMatrix3d& wi, const RowMatrix3d&, Eigen::Ref<Eigen::MatrixXd> out) const override {
    out.col(0) = ((1.0 + wi.col(0).array()) / M_PI).matrix();
  }
  bool is_reciprocal() const override { return false; }
  std::string spec() const override { return "nonreciprocal"; }
};

struct DeltaModel final : BrdfModel {
  DeltaPart part;
  explicit DeltaModel(DeltaPart p) : part(p) {}
  using BrdfModel::eval;
  void eval(const RowMatrix3d&, const RowMatrix3d&, Eigen::Ref<Eigen::MatrixXd> out) const override { out.setZero(); }
  std::vector<DeltaPart> delta_parts() const override { return {part}; }
  std::string spec() const override { return "delta"; }
};

// (-1)^l on the diagonal: the K-basis matrix of the rotation by pi (K_n^l(phi + pi) = (-1)^l K_n^l, eq. 7).
Eigen::MatrixXd parity_diagonal(int order) {
  const int m = hemisphere_basis_count(order);
  Eigen::MatrixXd d = Eigen::MatrixXd::Zero(m, m);
  for (int j = 0; j < m; ++j) d(j, j) = (ansi_to_nl(j).l % 2) ? -1.0 : 1.0;
  return d;
}

Eigen::MatrixXd random_symmetric(int m, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> n01;
  Eigen::MatrixXd a(m, m);
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < m; ++j) a(i, j) = n01(rng);
  return 0.5 * (a + a.transpose());
}

TEST(DiscreteBasis, ExactQuadratureGivesIdentityGram) {
  // Order 6: rings >= 3.5 and n_phi >= 13 make the product rule exact (icobrdf/core/grid/reference_grids.hpp).
  const auto g = build_polar_gauss_grid(4, 14);
  const auto b = build_discrete_basis(g, 6);
  EXPECT_EQ(b.B.rows(), g.cells());
  EXPECT_EQ(b.B.cols(), 28);
  EXPECT_LT(b.gram_error, kExactQuadratureTol);
  EXPECT_LT(b.condition, 1.0 + kAlgebraTol);
  EXPECT_NO_THROW(check_supported(b));
}

TEST(DiscreteBasis, RefusesOrdersTheGridCannotResolveAndNamesTheLimit) {
  // 3 rings x 8 azimuths = 24 nodes cannot carry the 36 functions of order 7: G is singular.
  const auto g = build_polar_gauss_grid(3, 8);
  const auto b = build_discrete_basis(g, 7);
  try {
    check_supported(b);
    FAIL() << "order 7 on 24 nodes accepted";
  } catch (const UnsupportedError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("order 7"), std::string::npos) << msg;
    EXPECT_NE(msg.find("largest supported order is"), std::string::npos) << msg;
    // 8 azimuths integrate trigonometric polynomials of degree <= 7 exactly, so the block of order 3 is
    // exact (3 rings suffice for t-degree 3). At order 4, cos^2(4 phi_m) = 1 and sin(4 phi_m) = 0 at every
    // node phi_m = 2 pi m/8, so G has 2 and 0 where I has 1: Gram error 1 > 0.1. Largest supported: 3.
    EXPECT_EQ(largest_supported_order(b), 3);
  }
}

TEST(Projection, RoundTripExactForLutsInTheSpanOnAnInexactGrid) {
  // On the lat-long grid G != I, but F = B C B^T gives P^T F P = G^-1 B^T W B C B^T W B G^-1 = C.
  const int order = 4;
  const auto g = build_lat_long_grid(8, 16, 3);
  const auto b = build_discrete_basis(g, order);
  EXPECT_GT(b.gram_error, kNotIdentity) << "the test needs a grid whose Gram matrix is not I";
  const auto p = make_projection(b);
  const auto c = random_symmetric(b.modes(), 11);
  const Eigen::MatrixXd f = reconstruct_lut(b, c);
  EXPECT_LT((project_lut(p, f) - c).cwiseAbs().maxCoeff(), kAlgebraTol);
  // Smoothing with plain truncation leaves a LUT in the span unchanged: S F S^T = B C B^T = F.
  EXPECT_LT((smooth_lut(b, p, f, LowPassFilter{}) - f).cwiseAbs().maxCoeff(), kAlgebraTol * f.cwiseAbs().maxCoeff());
}

TEST(Projection, AdjointIdentity) {
  // <P^T F P, X> = trace((P^T F P)^T X) = trace(F^T P X P^T) = <F, P X P^T> for any F, X.
  const auto g = build_lat_long_grid(4, 8, 2);
  const auto b = build_discrete_basis(g, 3);
  const auto p = make_projection(b);
  std::mt19937_64 rng(3);
  std::normal_distribution<double> n01;
  Eigen::MatrixXd f(g.cells(), g.cells()), x(b.modes(), b.modes());
  for (auto i = 0; i < f.size(); ++i) f.data()[i] = n01(rng);
  for (auto i = 0; i < x.size(); ++i) x.data()[i] = n01(rng);
  const double lhs = (project_lut(p, f).array() * x.array()).sum();
  const double rhs = (f.array() * (p.P * x * p.P.transpose()).array()).sum();
  EXPECT_NEAR(lhs, rhs, kAdjointTol * std::abs(lhs));
}

TEST(Projection, LambertSpectrumIsTwoAtDcOnAnyGrid) {
  // K_0^0 = 1/sqrt(2 pi) is constant, so 1 = sqrt(2 pi) B e_0 and P^T 1 = sqrt(2 pi) e_0 exactly:
  // C = (1/pi) (P^T 1)(1^T P) = 2 e_0 e_0^T (SPEC-NOTES: a_00^0 = 2).
  const auto g = build_lat_long_grid(6, 12, 2);
  const auto b = build_discrete_basis(g, 4);
  const auto lut = build_lut(ConstantModel(1.0 / M_PI), g, false);
  const Eigen::MatrixXd c = project_lut(make_projection(b), lut.channels[0]);
  Eigen::MatrixXd expected = Eigen::MatrixXd::Zero(b.modes(), b.modes());
  expected(0, 0) = 2.0;
  EXPECT_LT((c - expected).cwiseAbs().maxCoeff(), kAlgebraTol);
}

TEST(Projection, MinnaertIntegerExponentIsExactBecauseItIsInTheSpan) {
  // The cell average of a separable product K_a(w_i) K_b(w_r) over a cell pair is B_ia B_rb, so the
  // cell-averaged LUT of f = sum C_ab K_a K_b is exactly B C B^T and projects back to C on any grid.
  // C itself is computed independently with the exact polar Gauss rule (order 4 needs rings >= 3).
  const auto ref = build_polar_gauss_grid(6, 16);
  const Eigen::MatrixXd kref = hemisphere_basis_matrix(4, ref.directions);  // nodes x 15
  const Eigen::VectorXd cosr = ref.directions.col(2);
  // f = 2/pi c_i^2 c_r^2 => C = 2/pi v v^T with v_a = integral cos^2 K_a dOmega.
  const Eigen::VectorXd v = kref.transpose() * (ref.solid_angles.array() * cosr.array().square()).matrix();
  const Eigen::MatrixXd c_exact = (2.0 / M_PI) * v * v.transpose();
  const auto g = build_lat_long_grid(8, 16, 4);  // degree 7 cubature: exact cell averages of order-4 products in cos
  const auto b = build_discrete_basis(g, 6);      // order 6 > 4: the tail must come out zero
  const auto c = project_lut(make_projection(b), build_lut(Minnaert3(), g, false).channels[0]);
  Eigen::MatrixXd padded = Eigen::MatrixXd::Zero(b.modes(), b.modes());
  padded.topLeftCorner(15, 15) = c_exact;
  EXPECT_LT((c - padded).cwiseAbs().maxCoeff(), kSpanRecoveryTol) << "max |C - C_exact|";
}

TEST(DeltaLuts, MirrorAndRetroreflectorSpectraFollowTheGram) {
  // Mirror g LUT: F = Pi W^-1 with Pi the rotation-by-pi permutation. Since B_{m(i)} = B_i D (eq. 7),
  // B^T W Pi B = G D, so C = G^-1 G D G^-1 = D G^-1: C G = D exactly. Retroreflector: F = W^-1, C = G^-1.
  const int order = 5;
  const auto g = build_lat_long_grid(10, 20, 3);
  const auto b = build_discrete_basis(g, order);
  const auto p = make_projection(b);
  const auto mirror = project_lut(p, build_lut(DeltaModel({DeltaPart::Mirror, 1.0}), g, true).channels[0]);
  const auto retro = project_lut(p, build_lut(DeltaModel({DeltaPart::Retroreflector, 1.0}), g, true).channels[0]);
  EXPECT_LT((mirror * b.G - parity_diagonal(order)).cwiseAbs().maxCoeff(), kAlgebraTol);
  EXPECT_LT((retro * b.G - Eigen::MatrixXd::Identity(b.modes(), b.modes())).cwiseAbs().maxCoeff(), kAlgebraTol);
  // And C equals the analytic D (mirror) / I (retro) up to the Gram error of the grid (first order in G - I).
  EXPECT_LT((mirror - parity_diagonal(order)).cwiseAbs().maxCoeff(), kFirstOrderFactor * b.gram_error);
  // f form of a delta is refused (it has no finite f).
  EXPECT_THROW(build_lut(DeltaModel({DeltaPart::Mirror, 1.0}), g, false), ArgumentError);
}

TEST(DeltaLuts, ExactQuadratureGridGivesTheAnalyticMirrorSpectrum) {
  const auto g = build_polar_gauss_grid(5, 20);  // exact to order 9 in t... order 8: rings >= 4.5, n_phi >= 17
  const auto b = build_discrete_basis(g, 8);
  const auto c = project_lut(make_projection(b), build_lut(DeltaModel({DeltaPart::Mirror, 1.0}), g, true).channels[0]);
  EXPECT_LT((c - parity_diagonal(8)).cwiseAbs().maxCoeff(), kAlgebraTol);
}

TEST(Reciprocity, SymmetrizedLutIsTheClosestReciprocalLutByLeastSquares) {
  const auto g = build_lat_long_grid(3, 4, 2);  // 12 cells, half-size-free but unequal solid angles
  const Eigen::MatrixXd f = build_lut(NonReciprocal(), g, false).channels[0];
  const double v = reciprocity_violation(f, g.solid_angles);
  EXPECT_GT(v, kClearlyNonReciprocal);
  // Direct weighted least squares over symmetric S (parameters: upper triangle), weights Omega_i Omega_r.
  const int n = g.cells(), p = n * (n + 1) / 2;
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(n * n, p);
  Eigen::VectorXd y(n * n);
  int col = 0;
  Eigen::MatrixXi idx(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = i; j < n; ++j) idx(i, j) = idx(j, i) = col++;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const double w = std::sqrt(g.solid_angles[i] * g.solid_angles[j]);
      a(i * n + j, idx(i, j)) = w;
      y[i * n + j] = w * f(i, j);
    }
  const Eigen::VectorXd s = a.colPivHouseholderQr().solve(y);
  const Eigen::MatrixXd sym = symmetrize(f);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) EXPECT_NEAR(sym(i, j), s[idx(i, j)], kAlgebraTol);
  EXPECT_LT(reciprocity_violation(sym, g.solid_angles), kAlgebraTol);
  EXPECT_LT(reciprocity_violation(build_lut(Minnaert3(), g, false).channels[0], g.solid_angles), kAlgebraTol)
      << "a reciprocal model gives a symmetric LUT up to the summation order of its cell averages";
}

TEST(Rotation, RotatedSpectrumEqualsTheRotatedBrdf) {
  const int order = 5;
  const auto c = random_symmetric(hemisphere_basis_count(order), 5);
  const double angle = 0.7;
  const auto r = rotation_matrix(order, angle);
  EXPECT_LT((r * r.transpose() - Eigen::MatrixXd::Identity(r.rows(), r.cols())).cwiseAbs().maxCoeff(), kAlgebraTol);
  const auto cr = rotate_coefficients(c, order, angle);
  // f'(w_i, w_r) = f(R^-1 w_i, R^-1 w_r).
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> th(0, M_PI / 2), ph(-M_PI, M_PI);
  RowMatrix3d wi(50, 3), wr(50, 3), wi0(50, 3), wr0(50, 3);
  for (int k = 0; k < 50; ++k) {
    const double ti = th(rng), pi = ph(rng), tr = th(rng), pr = ph(rng);
    wi.row(k) = direction_from_angles(ti, pi).transpose();
    wr.row(k) = direction_from_angles(tr, pr).transpose();
    wi0.row(k) = direction_from_angles(ti, pi - angle).transpose();
    wr0.row(k) = direction_from_angles(tr, pr - angle).transpose();
  }
  EXPECT_LT((evaluate_coefficients(cr, order, wi, wr) - evaluate_coefficients(c, order, wi0, wr0)).cwiseAbs().maxCoeff(), kEvaluationTol);
}

TEST(Reflection, LambertAlbedoAndSpectralAlbedo) {
  // f = a/pi: directional albedo = a/pi * integral cos dOmega = a for every incident direction;
  // spectrally, C = 2a e_0 e_0^T and K(w)^T C e = 2a K_0^0 e_0 = 2a (1/sqrt(2 pi)) (pi/sqrt(2 pi)) = a.
  const double albedo = 0.8;
  const auto g = build_lat_long_grid(8, 16, 3);
  const auto lut = build_lut(ConstantModel(albedo / M_PI), g, false);
  const auto a = directional_albedo(lut.channels[0], false, g);
  EXPECT_LT((a.array() - albedo).abs().maxCoeff(), kAlgebraTol);
  const auto wf = white_furnace(lut.channels[0], false, g);
  EXPECT_NEAR(wf.max_albedo, albedo, kAlgebraTol);
  Eigen::MatrixXd c = Eigen::MatrixXd::Zero(6, 6);
  c(0, 0) = 2 * albedo;
  EXPECT_LT((spectral_albedo(c, 2, g.directions).array() - albedo).abs().maxCoeff(), kAlgebraTol);
  // Mirror in g form: every incident cell's albedo is 1 (the image cell has the same mean cosine).
  const auto m = build_lut(DeltaModel({DeltaPart::Mirror, 1.0}), g, true);
  EXPECT_LT((directional_albedo(m.channels[0], true, g).array() - 1.0).abs().maxCoeff(), kAlgebraTol);
  // Uniform sky of radiance 1 on a white Lambertian surface reflects radiance 1 (f form and g form agree).
  const Eigen::VectorXd lo = reflect_radiance(build_lut(ConstantModel(1 / M_PI), g, false).channels[0], false, g, Eigen::VectorXd::Ones(g.cells()));
  EXPECT_LT((lo.array() - 1.0).abs().maxCoeff(), kAlgebraTol);
  const Eigen::VectorXd lo_g = reflect_radiance(build_lut(ConstantModel(1 / M_PI), g, true).channels[0], true, g, Eigen::VectorXd::Ones(g.cells()));
  EXPECT_LT((lo_g - lo).cwiseAbs().maxCoeff(), kAlgebraTol);
}

TEST(StreamingProjection, MatchesTheMaterializedLutAndIsThreadInvariant) {
  const auto g = build_lat_long_grid(6, 12, 2);
  const auto b = build_discrete_basis(g, 4);
  const auto p = make_projection(b);
  const auto lut = build_lut(Minnaert3(), g, false);
  const auto direct = project_lut(p, lut.channels[0]);
  omp_set_num_threads(2);
  const auto two = streaming_projection(Minnaert3(), g, p, false);
  omp_set_num_threads(1);
  const auto one = streaming_projection(Minnaert3(), g, p, false);
  omp_set_num_threads(2);
  EXPECT_LT((two[0] - direct).cwiseAbs().maxCoeff(), kAlgebraTol);
  EXPECT_EQ((two[0] - one[0]).cwiseAbs().maxCoeff(), 0.0) << "1 and 2 threads must agree bitwise";
  // Delta parts are added exactly.
  const auto mirror_stream = streaming_projection(DeltaModel({DeltaPart::Mirror, 0.5}), g, p, true);
  const auto mirror_direct = project_lut(p, build_lut(DeltaModel({DeltaPart::Mirror, 0.5}), g, true).channels[0]);
  EXPECT_LT((mirror_stream[0] - mirror_direct).cwiseAbs().maxCoeff(), kAlgebraTol);
}

TEST(Filters, WeightsAndParsing) {
  // Fejer at N = 3: 1, 3/4, 1/2, 1/4. Hann: (1 + cos(pi n/4))/2.
  const auto f = parse_lowpass_filter("fejer").order_weights(3);
  EXPECT_NEAR(f[1], 0.75, kWeightTol);
  EXPECT_NEAR(f[3], 0.25, kWeightTol);
  EXPECT_NEAR(parse_lowpass_filter("hann").order_weights(3)[2], 0.5, kWeightTol);
  EXPECT_NEAR(parse_lowpass_filter("lanczos").order_weights(1)[1], std::sin(M_PI / 2) / (M_PI / 2), kWeightTol);
  EXPECT_NEAR(parse_lowpass_filter("gaussian:width=0.5").order_weights(1)[1], std::exp(-0.25 / 0.5), kWeightTol);
  EXPECT_THROW(parse_lowpass_filter("boxcar"), ArgumentError);
  EXPECT_THROW(parse_lowpass_filter("gaussian:width=-1"), ArgumentError);
}

TEST(IsotropicPart, AgreesWithTheIsotropicModeProjectionAndIsRotationInvariant) {
  const int order = 4;
  const auto c = random_symmetric(hemisphere_basis_count(order), 21);
  const Eigen::MatrixXd iso = isotropic_part(c, order);
  // For a symmetric C both are the orthogonal projection onto span{I_nm^l}.
  EXPECT_LT((iso - isotropic_projection(c)).cwiseAbs().maxCoeff(), kAlgebraTol);
  // An isotropic BRDF is unchanged by rotation about the normal.
  EXPECT_LT((rotate_coefficients(iso, order, 0.9) - iso).cwiseAbs().maxCoeff(), kAlgebraTol);
  // Idempotent, and it keeps asymmetry (g spectra): the part of an antisymmetric C stays antisymmetric.
  EXPECT_LT((isotropic_part(iso, order) - iso).cwiseAbs().maxCoeff(), kAlgebraTol);
  const Eigen::MatrixXd anti = c - c.transpose();
  const Eigen::MatrixXd anti_iso = isotropic_part(anti, order);
  EXPECT_LT((anti_iso + anti_iso.transpose()).cwiseAbs().maxCoeff(), kAlgebraTol);
}

TEST(Threads, LutBasisAndProjectionAreIdenticalOnOneAndTwoThreads) {
  // Every parallel loop writes disjoint rows in a fixed order, so results must agree bitwise.
  const auto g = build_lat_long_grid(6, 12, 2);
  auto run = [&](int threads) {
    omp_set_num_threads(threads);
    const auto b = build_discrete_basis(g, 4);
    const auto lut = build_lut(NonReciprocal(), g, false);
    const auto c = project_lut(make_projection(b), lut.channels[0]);
    return std::make_tuple(b.B, lut.channels[0], c);
  };
  const auto [b1, f1, c1] = run(1);
  const auto [b2, f2, c2] = run(2);
  omp_set_num_threads(2);
  EXPECT_EQ((b1 - b2).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ((f1 - f2).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ((c1 - c2).cwiseAbs().maxCoeff(), 0.0);
}

}  // namespace ICOBRDF_UNITY_ID
