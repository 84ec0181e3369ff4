// Chandrasekhar's H function for isotropic scattering, as used by the Hapke model.
#include <gtest/gtest.h>

#include <cmath>

#include "icobrdf/core/models/hapke.hpp"
#include "tests/core/brdf_quadrature.hpp"
#include "tests/support/unity_id.hpp"

using namespace icobrdf;

namespace ICOBRDF_UNITY_ID {
// Identities of the exact H hold for the Nystrom solution to its quadrature accuracy.
constexpr double kIdentityTol = 1e-11;
// Chandrasekhar's tabulated H for conservative isotropic scattering (Radiative Transfer, 1950) has 5 decimals.
constexpr double kTableTol = 1e-5;
// Interpolated table vs the direct Nystrom formula: 4-point Lagrange in sqrt(mu) on 4096 intervals;
// the mu ln(mu) behaviour at 0 limits it to ~1e-8 on the first intervals.
constexpr double kInterpolationTol = 1e-8;

TEST(ChandrasekharH, ValuesFromChandrasekharsTable) {
  // Conservative isotropic scattering (w = 1): H(0) = 1, H(0.5) = 2.01278, H(1) = 2.90781.
  const ChandrasekharH h(1.0);
  EXPECT_NEAR(h.exact(0.0), 1.0, kIdentityTol);
  EXPECT_NEAR(h.exact(0.5), 2.01278, kTableTol);
  EXPECT_NEAR(h.exact(1.0), 2.90781, kTableTol);
}

TEST(ChandrasekharH, MomentIdentities) {
  // Zeroth moment: integrating H = 1 + (w/2) mu H(mu) int H(mu')/(mu+mu') dmu' over mu and symmetrizing
  // (mu/(mu+mu') + mu'/(mu+mu') = 1) gives alpha_0 = 1 + (w/4) alpha_0^2, so alpha_0 = (2/w)(1 - sqrt(1 - w)).
  // For w = 1 the first moment is alpha_1 = 2/sqrt(3) (Chandrasekhar 1950, conservative case). Integrated
  // here with an independent Gauss-Legendre rule graded towards mu = 0.
  const auto g = test::gauss_legendre_gw(24);
  for (double w : {0.1, 0.5, 0.9, 0.99, 1.0}) {
    const ChandrasekharH h(w);
    double a0 = 0.0, a1 = 0.0;
    double lo = 0.0;
    for (double hi : {1e-8, 1e-6, 1e-4, 1e-3, 1e-2, 0.1, 0.3, 0.6, 1.0}) {
      for (std::size_t k = 0; k < g.x.size(); ++k) {
        const double mu = 0.5 * (lo + hi) + 0.5 * (hi - lo) * g.x[k], wt = 0.5 * (hi - lo) * g.w[k];
        a0 += wt * h.exact(mu);
        a1 += wt * mu * h.exact(mu);
      }
      lo = hi;
    }
    EXPECT_NEAR(a0, 2.0 / w * (1.0 - std::sqrt(1.0 - w)), kIdentityTol) << w;
    if (w == 1.0) {
      EXPECT_NEAR(a1, 2.0 / std::sqrt(3.0), kIdentityTol);
    }
  }
}

TEST(ChandrasekharH, SatisfiesTheOriginalIntegralEquation) {
  // H(mu) = 1 + (w/2) mu H(mu) integral_0^1 H(mu')/(mu + mu') dmu' (the form not used by the solver),
  // integrated with an independent graded Gauss rule.
  const auto g = test::gauss_legendre_gw(24);
  for (double w : {0.4, 1.0}) {
    const ChandrasekharH h(w);
    for (double mu : {1e-3, 0.05, 0.3, 0.77, 1.0}) {
      double integral = 0.0, lo = 0.0;
      for (double hi : {1e-9, 1e-7, 1e-5, 1e-4, 1e-3, 3e-3, 1e-2, 3e-2, 0.1, 0.3, 0.6, 1.0}) {
        for (std::size_t k = 0; k < g.x.size(); ++k) {
          const double m = 0.5 * (lo + hi) + 0.5 * (hi - lo) * g.x[k];
          integral += 0.5 * (hi - lo) * g.w[k] * h.exact(m) / (mu + m);
        }
        lo = hi;
      }
      EXPECT_NEAR(h.exact(mu), 1.0 + 0.5 * w * mu * h.exact(mu) * integral, 1e-10) << w << " " << mu;
    }
  }
}

TEST(ChandrasekharH, TableInterpolationMatchesTheDirectFormula) {
  for (double w : {0.0, 0.3, 0.95, 1.0}) {
    const ChandrasekharH h(w);
    double worst = 0.0;
    for (int k = 0; k <= 20000; ++k) {
      const double mu = std::pow(k / 20000.0, 3.0);  // dense near 0
      worst = std::max(worst, std::abs(h(mu) - h.exact(mu)));
    }
    EXPECT_LT(worst, kInterpolationTol) << w;
  }
  EXPECT_EQ(ChandrasekharH(0.0).exact(0.37), 1.0);  // no scattering: H = 1
}

}  // namespace ICOBRDF_UNITY_ID
