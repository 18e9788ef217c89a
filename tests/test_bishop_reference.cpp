// The independent Bishop reference (tests/bishop_reference.hpp) against a closed form and
// published answers, so that the tests which set skred's limit equilibrium against it
// (test_strength_reduction.cpp, test_thesis_slope.cpp) compare with something that is right.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

#include "bishop_reference.hpp"

using namespace skred::test::bishop;

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

}  // namespace

TEST(BishopReference, UndrainedCircleUnderAStraightSlopeIsMomentEquilibrium) {
  // phi = 0: Bishop's F is the moment balance c R L / (gamma A d_x) on any circle (m_i = cos
  // alpha_i, so the resisting sum is c times the arc length L). Under the straight surface
  // y = 30 - x/2 the sliding mass is a circular segment: with p the centre's distance from the
  // chord, its half-angle t = acos(p / R), L = 2 R t, A = R^2 (2t - sin 2t) / 2, its centroid
  // 2 R^3 sin^3 t / (3 A) from the centre along the chord's normal, whose horizontal part is
  // 1/sqrt(5) of it (the normal (1, 2)/sqrt(5)), towards -x: it drives the soil towards +x.
  const Soil clay{10e3, 0.0, 20e3};
  const Ground g{{{0.0, 30.0}, {60.0, 0.0}}, -100.0, {{-100.0, clay}}};
  const Circle c{30.0, 25.0, 15.0};
  const double p = (25.0 + 0.5 * 30.0 - 30.0) / std::sqrt(1.25), t = std::acos(p / c.radius);
  const double R = c.radius, L = 2 * R * t, A = R * R * (2 * t - std::sin(2 * t)) / 2;
  const double arm = 2 * R * R * R * std::pow(std::sin(t), 3) / (3 * A) / std::sqrt(5.0);
  const double expected = clay.cohesion * R * L / (clay.unit_weight * A * arm);
  const double F = factor(g, c, 1, 4000);
  std::printf("segment under a 1:2 face: F = %.6f, closed form %.6f\n", F, expected);
  EXPECT_NEAR(F, expected, 1e-5 * expected);
  EXPECT_TRUE(std::isnan(factor(g, c, -1))) << "the segment drives nothing towards -x";
}

TEST(BishopReference, AcadsSimpleSlopeHasThePublishedFactor) {
  // ACADS benchmark 1(a) (Giam & Donald 1989; as given in the verification manuals of Slide and
  // SLOPE/W): a homogeneous 2 : 1 slope 10 m high, c' = 3 kPa, phi' = 19.6 deg, gamma = 20 kN/m^3,
  // dry. Referee F = 1.00; the Bishop answers of 18 programs averaged 0.993. Drawn here with the
  // toe at (30, 25), the crest at (50, 35) and 5 m of ground under the toe's level: the face rises
  // towards +x, so the soil slides towards -x.
  const Soil soil{3e3, 19.6 * kDeg, 20e3};
  const Ground acads{{{20.0, 25.0}, {30.0, 25.0}, {50.0, 35.0}, {70.0, 35.0}}, 20.0, {{20.0, soil}}};
  const Critical r = critical_circle(acads, -1);
  std::printf("ACADS 1(a): F = %.4f on the circle centred (%.2f, %.2f) m of radius %.2f m\n", r.factor,
              r.circle.xc, r.circle.yc, r.circle.radius);
  EXPECT_NEAR(r.factor, 0.993, 0.01);
  // A toe circle: it comes out at the toe, not below the toe's level.
  EXPECT_NEAR(r.circle.yc - r.circle.radius, 25.0, 0.05);
  // The same slope mirrored, with its firm base at the toe, slides the other way with the same F.
  const Ground mirrored{{{0.0, 10.0}, {20.0, 10.0}, {40.0, 0.0}, {50.0, 0.0}}, 0.0, {{0.0, soil}}};
  EXPECT_NEAR(critical_circle(mirrored, 1).factor, r.factor, 1e-4);
}

TEST(BishopReference, UndrainedToeCircleMeetsTaylorsStabilityNumber) {
  // phi = 0, a 60 deg slope on a firm base at its toe: gamma H / c = 5.24 at F = 1 (Taylor
  // 1937's chart, as tabled in Craig's Soil Mechanics; toe circles for slopes above 53 deg).
  const Soil clay{40e3, 0.0, 20e3};
  const double H = 10.0, run = H / std::tan(60.0 * kDeg);
  const Ground g{{{0.0, H}, {30.0, H}, {30.0 + run, 0.0}, {80.0, 0.0}}, 0.0, {{0.0, clay}}};
  const Critical r = critical_circle(g, 1);
  const double expected = 5.24 * clay.cohesion / (clay.unit_weight * H);
  std::printf("Taylor, 60 deg: F = %.4f, chart %.4f\n", r.factor, expected);
  EXPECT_NEAR(r.factor, expected, 0.01 * expected);
}
