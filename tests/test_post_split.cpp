// The multiplicative split F = Fe Fp (Post eq. 67-74) and the stress recomputed from Fe
// (eq. 75-77).
#include <gtest/gtest.h>

#include <fmt/format.h>
#include <Eigen/LU>

#include <cmath>

#include "post/elastic_plastic_split.hpp"
#include "post/strain_measures.hpp"

using namespace skred;

namespace {

// Strain increment of a deformation-gradient increment, as the solver forms it:
// d_eps = sym(dF) - I (small-strain increment of one step).
Sym3 strain_increment(const Mat3& dF) { return to_voigt(dF - Mat3::Identity()); }

double max_abs(const Mat3& m) { return m.cwiseAbs().maxCoeff(); }

// A deterministic sequence of plane-strain deformation increments of size ~5e-3.
Mat3 increment(int k, bool with_spin) {
  const double a = 5e-3 * std::sin(0.3 * k), b = 4e-3 * std::cos(0.17 * k), g = 3e-3 * std::sin(0.05 * k + 1);
  const double w = with_spin ? 2e-3 : 0.0;
  Mat<2> d;
  d << 1 + a, g + w, g - w, 1 + b;
  return deformation3<2>(d);
}

ElasticConstants soil() { return ElasticConstants(ElasticParams{20e6, 0.25}); }

}  // namespace

TEST(PostSplit, FeTimesFpReconstructsFToRoundOff) {
  // A path with spin whose increments are only partly elastic (the rest plastic, eq. 71):
  // whatever Fe is, Fe Fp = F (eq. 67, 74).
  Mat3 F = Mat3::Identity(), Fe = Mat3::Identity();
  double worst = 0.0;
  for (int k = 0; k < 2000; ++k) {
    const Mat3 dF = increment(k, true);
    F = dF * F;
    const Sym3 deps = strain_increment(dF);
    Sym3 deps_e = 0.6 * deps;
    deps_e[2] += 2e-4;                  // plastic flow leaves an out-of-plane elastic strain
    Fe = update_elastic_F(Fe, deps_e);  // eq. 72-73
    const Mat3 Fp = plastic_F(Fe, F);   // eq. 74
    worst = std::max(worst, max_abs(Fe * Fp - F));
  }
  EXPECT_LT(worst, 1e-14);
  EXPECT_GT(max_abs(plastic_F(Fe, F) - Mat3::Identity()), 1e-2);  // the path was plastic
  RecordProperty("max_abs_Fe_Fp_minus_F", fmt::format("{:.3g}", worst));
}

TEST(PostSplit, PurelyElasticIrrotationalPathHasFpEqualIdentity) {
  // Without spin dF is symmetric, so dFe = d_eps + I = dF (eq. 72) and Fe follows F exactly.
  Mat3 F = Mat3::Identity(), Fe = Mat3::Identity();
  for (int k = 0; k < 2000; ++k) {
    const Mat3 dF = increment(k, false);
    F = dF * F;
    Fe = update_elastic_F(Fe, strain_increment(dF));
  }
  EXPECT_GT(max_abs(F - Mat3::Identity()), 1e-2);
  EXPECT_LT(max_abs(plastic_F(Fe, F) - Mat3::Identity()), 1e-14);
}

TEST(PostSplit, ElasticFIncrementIsSymmetricStrainPlusIdentity) {
  const Sym3 d = (Sym3() << 1e-3, -2e-3, 5e-4, 3e-4, -1e-4, 2e-4).finished();
  const Mat3 dFe = elastic_F_increment(d);
  EXPECT_EQ(dFe, to_matrix(d) + Mat3::Identity());
  EXPECT_EQ(dFe, dFe.transpose());
  EXPECT_LT((elastic_strain_from_F(dFe) - d).cwiseAbs().maxCoeff(),
            2.3e-16);  // eq. 75 undoes eq. 72 (to an ulp of 1)
}

TEST(PostSplit, StressFromFeMatchesTheIncrementalElasticStress) {
  const ElasticConstants e = soil();
  const double M = e.lambda + e.two_g;  // constrained modulus, the largest stiffness
  const Sym3 s0 = (Sym3() << -30e3, -60e3, -30e3, 0, 0, 0).finished();  // K0-like initial stress
  // One step: sigma_0 + E : d_eps (eq. 75-77), to round-off of 1 + d - 1.
  const Sym3 d = (Sym3() << 1e-3, -2e-3, 0, 5e-4, 0, 0).finished();
  const Sym3 one = stress_from_elastic_F(s0, update_elastic_F(Mat3::Identity(), d), e);
  EXPECT_LT((one - (s0 + elastic_increment(e, d))).cwiseAbs().maxCoeff(), 1e-16 * M * 10);
  // n equal (coaxial) elastic steps: Fe = (I + d)^n exactly (eq. 73), and the stress from Fe is
  // sigma_0 + E : ((I + d)^n - I). The incremental stress sigma_0 + n E : d differs from it by
  // the second-order term, about M eps^2 / 2 with eps = n |d|.
  const int n = 100;
  const Sym3 step = (Sym3() << 1e-4, -5e-5, 0, 3e-5, 0, 0).finished();
  Mat3 Fe = Mat3::Identity(), power = Mat3::Identity();
  Sym3 incremental = s0;
  for (int k = 0; k < n; ++k) {
    Fe = update_elastic_F(Fe, step);
    power *= elastic_F_increment(step);
    incremental += elastic_increment(e, step);
  }
  const Sym3 from_fe = stress_from_elastic_F(s0, Fe, e);
  const Sym3 exact = s0 + elastic_increment(e, to_voigt(power - Mat3::Identity()));
  EXPECT_LT((from_fe - exact).cwiseAbs().maxCoeff(), 1e-12 * 60e3);
  const double eps = n * step.cwiseAbs().maxCoeff();
  const double diff = (from_fe - incremental).cwiseAbs().maxCoeff();
  EXPECT_LT(diff, M * eps * eps);
  RecordProperty("stress_from_Fe_minus_incremental_Pa", fmt::format("{:.4g}", diff));
  RecordProperty("M_eps2_Pa", fmt::format("{:.4g}", M * eps * eps));
}
