// Bishop's simplified method (post/limit_equilibrium.hpp) against published slope-stability
// answers: the ACADS benchmark 1(a) (Giam & Donald 1989; referee factor of safety 1.00),
// Griffiths & Lane's (1999) first example against Bishop & Morgenstern's charts, the infinite
// slope's tan(phi) / tan(beta), Taylor's stability numbers, and one circle whose factor follows by hand.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "post/limit_equilibrium.hpp"

namespace skred {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// A slope of height H and angle beta (the face rising towards -x) on ground that stands `toe`
// high beyond the toe, sampled in columns of `width`; the firm base at y = 0.
GroundProfile slope(double H, double beta_deg, double toe, double width, double length) {
  GroundProfile g;
  g.x0 = 0.0, g.width = width, g.base = 0.0;
  const double crest_end = 0.4 * length, run = H / std::tan(beta_deg * kDeg);
  for (double x = 0.5 * width; x < length; x += width)
    g.top.push_back(toe + std::clamp(H - (x - crest_end) * H / std::max(run, 1e-12), 0.0, H));
  return g;
}

TEST(LimitEquilibrium, UndrainedToeCirclesMeetTaylorsStabilityNumbers) {
  // phi = 0, the ground ending at the toe (an embankment on a firm base): toe circles, and
  // gamma H / c = 3.83 (beta = 90 deg), 4.57 (75 deg), 5.24 (60 deg) at F = 1 (Taylor 1937's
  // chart, as tabled in Craig's Soil Mechanics). Any method of slices is exact moment
  // equilibrium on a circle when phi = 0.
  const double H = 10.0, gamma = 20e3, c = 40e3;
  const struct { double beta, N; } cases[] = {{90.0, 3.83}, {75.0, 4.57}, {60.0, 5.24}};
  for (const auto& k : cases) {
    GroundProfile g = slope(H, k.beta, 0.0, 0.05, 80.0);
    for (double& t : g.top)
      if (t <= 0.0) t = NAN;  // no ground beyond the toe
    const CriticalCircle r = critical_circle(g, {c, 0.0, gamma});
    const double expected = k.N * c / (gamma * H);
    EXPECT_NEAR(r.factor, expected, 0.01 * expected) << "beta = " << k.beta;
  }
}

TEST(LimitEquilibrium, GriffithsAndLanesSlopeMeetsBishopAndMorgensternsChart) {
  // Griffiths & Lane (1999), example 1: 2 : 1, H = 10 m, no foundation layer (the firm base at
  // the toe, depth factor 1), phi' = 20 deg, c' / (gamma H) = 0.05: F = 1.38 from Bishop &
  // Morgenstern's (1960) charts (1.4 by their finite elements).
  const CriticalCircle r =
      critical_circle(slope(10.0, std::atan(0.5) / kDeg, 0.0, 0.05, 100.0), {10e3, 20.0 * kDeg, 20e3});
  EXPECT_NEAR(r.factor, 1.38, 0.02) << r.factor;
  EXPECT_EQ(r.direction, 1) << "the face rises towards -x, so the soil slides towards +x";
}

TEST(LimitEquilibrium, CohesionlessSlopeTendsToTheInfiniteSlope) {
  // c = 0: every slip surface has F >= tan(phi) / tan(beta), approached by shallow circles
  // under the face (the infinite slope).
  const double beta = std::atan(0.5), phi = 30.0 * kDeg;
  const CriticalCircle r = critical_circle(slope(10.0, beta / kDeg, 0.0, 0.05, 80.0), {0.0, phi, 20e3});
  const double infinite = std::tan(phi) / std::tan(beta);
  EXPECT_GE(r.factor, infinite * (1.0 - 1e-9));
  EXPECT_LT(r.factor, 1.01 * infinite);
}

TEST(LimitEquilibrium, AcadsSimpleSlopeHasTheRefereesFactor) {
  // ACADS 1(a): 10 m high, 2 : 1, c' = 3 kPa, phi' = 19.6 deg, gamma = 20 kN/m^3, firm base at
  // the toe. Referee F = 1.00; the Bishop answers of 18 programs averaged 0.993.
  const GroundProfile g = slope(10.0, std::atan(0.5) / kDeg, 0.0, 0.05, 80.0);
  const CriticalCircle r = critical_circle(g, {3e3, 19.6 * kDeg, 20e3});
  EXPECT_NEAR(r.factor, 0.993, 0.01) << r.factor;
  // The mirrored slope slides the other way with the same factor.
  GroundProfile m = g;
  std::reverse(m.top.begin(), m.top.end());
  const CriticalCircle rm = critical_circle(m, {3e3, 19.6 * kDeg, 20e3});
  EXPECT_EQ(rm.direction, -1);
  EXPECT_NEAR(rm.factor, r.factor, 2e-3);
}

TEST(LimitEquilibrium, OneCircleByHand) {
  // phi = 0: F = c L R / (gamma A d), with the arc length L, the sliding area A and its
  // centroid's lever arm d about the centre. Level ground y = 10 cut by the circle centred at
  // (20, 10), R = 5: a half disc, L = pi R, A = pi R^2 / 2 and d = 0, so it drives nothing;
  // centred at (20, 12) instead, the segment below y = 10 is symmetric too. A circle through
  // a vertical face: centre (10, 10) on its top edge, R = 5, ground for x < 10 only (a
  // quarter disc slides towards +x): L = pi R / 2, A = pi R^2 / 4, d = 4 R / (3 pi).
  GroundProfile g;
  g.x0 = 0.0, g.width = 0.01, g.base = 0.0;
  for (double x = 0.005; x < 30.0; x += 0.01) g.top.push_back(x < 10.0 ? 10.0 : NAN);
  const double c = 10e3, gamma = 20e3, R = 5.0;
  const double expected = c * (std::numbers::pi * R / 2) * R /
                          (gamma * std::numbers::pi * R * R / 4 * (4 * R / (3 * std::numbers::pi)));
  EXPECT_NEAR(bishop_factor(g, {c, 0.0, gamma}, {10.0, 10.0, R}, 1, 400), expected, 1e-3 * expected);
  EXPECT_TRUE(std::isnan(bishop_factor(g, {c, 0.0, gamma}, {10.0, 10.0, R}, -1, 400)))
      << "a quarter disc at a face rising towards -x does not slide towards -x";
  EXPECT_TRUE(std::isnan(bishop_factor(g, {c, 0.0, gamma}, {10.0, 10.0, 12.0}, 1, 400)))
      << "a circle below the firm base";
}

}  // namespace
}  // namespace skred
