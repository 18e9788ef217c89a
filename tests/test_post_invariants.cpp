// Principal stresses and direction (Post eq. 59-60), p and q (eq. 61-62) and the relative
// yield function (eq. 66) against hand-computed cases.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

#include "post/invariants.hpp"

using namespace skred;

namespace {

Sym3 voigt(double xx, double yy, double zz, double xy, double yz = 0, double xz = 0) {
  return (Sym3() << xx, yy, zz, xy, yz, xz).finished();
}

void expect_principal(const Sym3& s, double s1, double s2, double s3) {
  const PrincipalStresses p = principal_stresses(s);
  EXPECT_NEAR(p.s1, s1, 1e-12 * (1 + std::abs(s1)));
  EXPECT_NEAR(p.s2, s2, 1e-12 * (1 + std::abs(s2)));
  EXPECT_NEAR(p.s3, s3, 1e-12 * (1 + std::abs(s3)));
}

constexpr double kDeg = 180.0 / std::numbers::pi;

}  // namespace

TEST(PostInvariants, HandComputedPlaneCases) {
  // xx = 50, yy = -30, xy = 30: centre 10, radius sqrt(40^2 + 30^2) = 50 -> 60 and -40
  // (eq. 59); zz = 5 sorts between. tan 2 theta = 60 / 80 (eq. 60).
  const Sym3 s = voigt(50, -30, 5, 30);
  expect_principal(s, -40, 5, 60);
  EXPECT_NEAR(principal_angle_degrees(s), 0.5 * std::atan2(60.0, 80.0) * kDeg, 1e-12);
  EXPECT_NEAR(principal_angle_degrees(s), 18.434948822922010, 1e-12);
  // Pure shear xy = t: principal +-t at 45 degrees.
  expect_principal(voigt(0, 0, 0, 7), -7, 0, 7);
  EXPECT_NEAR(principal_angle_degrees(voigt(0, 0, 0, 7)), 45.0, 1e-12);
  EXPECT_NEAR(principal_angle_degrees(voigt(0, 0, 0, -7)), -45.0, 1e-12);
  // Uniaxial compression along x: the larger in-plane stress (0) acts along y.
  expect_principal(voigt(-100, 0, 0, 0), -100, 0, 0);
  EXPECT_NEAR(principal_angle_degrees(voigt(-100, 0, 0, 0)), 90.0, 1e-12);
  EXPECT_NEAR(principal_angle_degrees(voigt(-100, -200, 0, 0)), 0.0, 1e-12);
  // The direction is principal: rotating the stress by theta leaves no shear.
  const double t = principal_angle_degrees(s) / kDeg;
  const double shear = -0.5 * (50 - -30) * std::sin(2 * t) + 30 * std::cos(2 * t);
  EXPECT_NEAR(shear, 0.0, 1e-12);
}

TEST(PostInvariants, EqualPrincipalStresses) {
  // Hydrostatic: all equal, every direction principal (angle reported as 0), q = 0.
  const Sym3 h = voigt(-7, -7, -7, 0);
  expect_principal(h, -7, -7, -7);
  EXPECT_EQ(principal_angle_degrees(h), 0.0);
  EXPECT_NEAR(deviatoric_stress_q(principal_stresses(h)), 0.0, 1e-12);
  EXPECT_NEAR(mean_stress_p(principal_stresses(h)), -7.0, 1e-12);
  // Equal in-plane pair, different out-of-plane stress.
  const Sym3 s = voigt(-10, -10, -4, 0);
  expect_principal(s, -10, -10, -4);
  EXPECT_EQ(principal_angle_degrees(s), 0.0);
  EXPECT_NEAR(deviatoric_stress_q(principal_stresses(s)), 6.0, 1e-12);  // sqrt((0+36+36)/2)
  // K0 state (Post eq. 50-51): xx = zz.
  expect_principal(voigt(-3, -10, -3, 0), -10, -3, -3);
}

TEST(PostInvariants, GeneralThreeDimensionalStateMatchesInvariants) {
  const Sym3 s = voigt(10, -20, 5, 3, -4, 6);
  const PrincipalStresses p = principal_stresses(s);
  EXPECT_LE(p.s1, p.s2);
  EXPECT_LE(p.s2, p.s3);
  const Mat3 m = to_matrix(s);
  EXPECT_NEAR(p.s1 + p.s2 + p.s3, m.trace(), 1e-12);
  EXPECT_NEAR(p.s1 * p.s2 * p.s3, m.determinant(), 1e-9);
  EXPECT_NEAR(mean_stress_p(p), mean_stress(s), 1e-12);              // eq. 61
  EXPECT_NEAR(deviatoric_stress_q(p), deviatoric_stress(s), 1e-12);  // eq. 62 = sqrt(3 J2)
}

TEST(PostInvariants, RelativeYieldIsOneOnTheMohrCoulombSurface) {
  const double phi = 30.0 / kDeg, c = 10e3, s1 = -100e3;
  // Eq. 45 with f = 0 solved for sigma_3.
  const double s3 = (c * std::cos(phi) + 0.5 * s1 * (1 - std::sin(phi))) / (0.5 * (1 + std::sin(phi)));
  const double f45 = 0.5 * (s3 - s1) + 0.5 * (s1 + s3) * std::sin(phi) - c * std::cos(phi);
  ASSERT_NEAR(f45, 0.0, 1e-9);
  const Sym3 at_yield = voigt(s1, s3, 0.5 * (s1 + s3), 0);
  EXPECT_NEAR(relative_yield(at_yield, phi, c), 1.0, 1e-12);
  // Rotated in the plane: same principal stresses, same value.
  const double cen = 0.5 * (s1 + s3), r = 0.5 * (s3 - s1);
  EXPECT_NEAR(
      relative_yield(voigt(cen + r * std::cos(1.0), cen - r * std::cos(1.0), cen, r * std::sin(1.0)), phi, c),
      1.0, 1e-12);
  // Half the radius at the same centre: 0.5. Hydrostatic: 0.
  EXPECT_NEAR(relative_yield(voigt(cen - r / 2, cen + r / 2, cen, 0), phi, c), 0.5, 1e-12);
  EXPECT_NEAR(relative_yield(voigt(cen, cen, cen, 0), phi, c), 0.0, 1e-12);
  // Tresca (phi = 0): (s3 - s1) / 2 / c.
  EXPECT_NEAR(relative_yield(voigt(-50, -30, -40, 0), 0.0, 20.0), 0.5, 1e-12);
  // No strength: NaN. Beyond the apex (mean tension > c cot phi): +inf.
  EXPECT_TRUE(std::isnan(relative_yield(at_yield, std::nan(""), std::nan(""))));
  const double apex = c / std::tan(phi);
  EXPECT_EQ(relative_yield(voigt(2 * apex, 2 * apex, 2 * apex, 1.0), phi, c),
            std::numeric_limits<double>::infinity());
}
