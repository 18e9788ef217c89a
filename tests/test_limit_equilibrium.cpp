// Bishop's simplified method (post/limit_equilibrium.hpp) against published slope-stability
// answers: the ACADS benchmark 1(a) (Giam & Donald 1989; referee factor of safety 1.00),
// Griffiths & Lane's (1999) first example against Bishop & Morgenstern's charts, the infinite
// slope's tan(phi) / tan(beta), Taylor's stability numbers, and one circle whose factor follows by hand.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "post/limit_equilibrium.hpp"
#include "run/slope_stability.hpp"
#include "scenario/scenario.hpp"
#include "slope_texts.hpp"

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

// The same from a scenario's points: a sand slope at 30 deg, phi = 35 deg (F = tan(phi) / tan(beta)
// = 1.213 for a slip parallel to the face). The points' tops step by half a cell, up to 45 deg
// between column centres; a sliver under the steepest step gave F = 0.70 on 1 m cells and 0.93 on
// 0.5 m. Circles at least a cell deep (GroundProfile::min_depth) give 1.217 and 1.224.
TEST(LimitEquilibrium, CohesionlessSlopeOfPointsHasTheInfiniteSlopesFactor) {
  const double infinite = std::tan(35.0 * kDeg) / std::tan(30.0 * kDeg);
  for (const double h : {1.0, 0.5}) {
    const std::string text =
        "[grid]\nsize = [60.0, 16.0]\ncell_size = " + std::to_string(h) +
        "\n[[material]]\nname = \"sand\"\nmodel = \"mohr-coulomb\"\ndensity = 2000.0\nyoung = 2e7\n"
        "poisson = 0.3\nfriction = 35.0\ncohesion = 0.0\n"
        "[[body]]\nname = \"ground\"\nmaterial = \"sand\"\nshape = \"polygon\"\n"
        "vertices = [[0, 0], [60, 0], [60, 2], [37.3205, 2], [20, 12], [0, 12]]\n"
        "[gravity]\nacceleration = [0.0, -9.81]\n[boundary]\ny_min = \"fixed\"\n[solver]\nend_time = 1.0\n";
    const SlopeStability r = slope_stability(parse_scenario(text, "sand.toml"));
    ASSERT_TRUE(r.computed) << r.why_not;
    EXPECT_NEAR(r.critical.factor, infinite, 0.015 * infinite) << "h = " << h;
  }
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

// Layers in cells of the columns' width x `row_height` from y = 0: soil 0 above `boundary`,
// soil 1 below it (horizontal layers), none where a column has no ground.
void layer(GroundProfile& g, double row_height, int rows, double boundary) {
  g.rows = rows, g.row0 = 0.0, g.row_height = row_height;
  g.soil.assign(g.top.size() * static_cast<std::size_t>(rows), GroundProfile::kNoSoil);
  for (std::size_t j = 0; j < g.top.size(); ++j)
    for (int k = 0; k < rows; ++k)
      if (std::isfinite(g.top[j]) && k * row_height < g.top[j])
        g.soil[j * rows + k] = (k + 0.5) * row_height > boundary ? 0 : 1;
}

TEST(LimitEquilibrium, LayeredQuarterDiscByHand) {
  // phi = 0, the quarter disc of OneCircleByHand (centre (10, 10) on the face's top edge,
  // R = 5) in two layers meeting at y = 10 - R/2: soil 0 (c1, gamma1) above, soil 1 below.
  // The arc runs through soil 0 for R pi/6 (from 60 deg off the vertical) and through soil 1 for
  // R pi/3. The driving moment is the integral of gamma |x - 10| over the disc: gamma1 - gamma2
  // over the strip of depth R/2, integral_0^{R/2} (R^2 - d^2)/2 dd = 11 R^3 / 48, and gamma2 R^3/3
  // over the whole. F = R^2 (c1 pi/6 + c2 pi/3) / M.
  GroundProfile g;
  g.x0 = 0.0, g.width = 0.01, g.base = 0.0;
  for (double x = 0.005; x < 30.0; x += 0.01) g.top.push_back(x < 10.0 ? 10.0 : NAN);
  const double R = 5.0, c1 = 5e3, c2 = 20e3, gamma1 = 16e3, gamma2 = 22e3;
  layer(g, 0.5, 24, 10.0 - R / 2);
  const double pi = std::numbers::pi;
  const double moment = gamma2 * R * R * R / 3 + (gamma1 - gamma2) * 11 * R * R * R / 48;
  const double expected = R * R * (c1 * pi / 6 + c2 * pi / 3) / moment;
  const std::vector<SoilStrength> soils{{c1, 0.0, gamma1}, {c2, 0.0, gamma2}};
  EXPECT_NEAR(bishop_factor(g, soils, {10.0, 10.0, R}, 1, 2000), expected, 1e-3 * expected);
  // The same layers of one soil are the homogeneous ground's answer.
  const std::vector<SoilStrength> same{{c1, 0.0, gamma1}, {c1, 0.0, gamma1}};
  EXPECT_NEAR(bishop_factor(g, same, {10.0, 10.0, R}, 1, 400),
              c1 * (pi * R / 2) * R / (gamma1 * pi * R * R / 4 * (4 * R / (3 * pi))), 1e-3);
  // A layer index beyond the soils given is refused.
  EXPECT_TRUE(std::isnan(bishop_factor(g, std::vector<SoilStrength>{soils[0]}, {10.0, 10.0, R}, 1)));
}

TEST(LimitEquilibrium, LayersOfOneSoilAreTheHomogeneousGround) {
  // ACADS 1(a)'s slope cut into two layers of the same soil: the same critical circle and F.
  GroundProfile g = slope(10.0, std::atan(0.5) / kDeg, 5.0, 0.1, 60.0);
  const SoilStrength soil{3e3, 19.6 * kDeg, 20e3};
  const CriticalCircle one = critical_circle(g, soil);
  layer(g, 0.1, 160, 7.0);
  const CriticalCircle two = critical_circle(g, std::vector<SoilStrength>{soil, soil});
  EXPECT_NEAR(two.factor, one.factor, 1e-9);
  EXPECT_NEAR(two.circle.radius, one.circle.radius, 1e-6);
}

TEST(LimitEquilibrium, AWeakLayerDrawsTheCircleAndFirmGroundStopsIt) {
  // The same slope over a 5 m foundation. A weak layer 1 m thick at the foundation's top
  // (c = 1 kPa, phi = 10 deg) lowers F, and the critical circle reaches down into it.
  GroundProfile g = slope(10.0, std::atan(0.5) / kDeg, 5.0, 0.1, 60.0);
  const SoilStrength soil{3e3, 19.6 * kDeg, 20e3};
  const CriticalCircle homogeneous = critical_circle(g, soil);
  layer(g, 0.1, 160, 5.0);  // soil 1 is the foundation, y < 5
  for (std::size_t j = 0; j < g.top.size(); ++j)
    for (int k = 40; k < 50; ++k) g.soil[j * 160 + k] = 2;  // 4 m < y < 5 m: the weak layer
  const CriticalCircle weak = critical_circle(g, {soil, soil, {1e3, 10.0 * kDeg, 20e3}});
  EXPECT_LT(weak.factor, 0.8 * homogeneous.factor);
  const double lowest = weak.circle.yc - weak.circle.radius;
  EXPECT_GT(lowest, 4.0 - 1e-9);
  EXPECT_LT(lowest, 5.0) << "the circle reaches into the weak layer";
  // Undrained clay (phi = 0) on a 2 : 1 slope fails on deep circles (Taylor: base circles below
  // 53 deg); a firm foundation holds them at its top, and F rises.
  for (std::size_t j = 0; j < g.top.size(); ++j)
    for (int k = 40; k < 50; ++k) g.soil[j * 160 + k] = 1;
  const SoilStrength clay{20e3, 0.0, 20e3};
  SoilStrength firm = clay;
  firm.firm = true;
  const CriticalCircle deep = critical_circle(g, {clay, clay});
  const CriticalCircle held = critical_circle(g, {clay, firm});
  EXPECT_LT(deep.circle.yc - deep.circle.radius, 4.0) << "the clay's circle reaches deep";
  EXPECT_GT(held.circle.yc - held.circle.radius, 5.0 - 1e-9) << "no circle cuts the firm foundation";
  EXPECT_GT(held.factor, deep.factor);
}

TEST(SlopeStability, TwoBodiesOfOneSoilAreOneAndAnElasticBaseIsFirm) {
  const std::string file = std::string(SKRED_SOURCE_DIR) + "/examples/slope_collapse.toml";
  const SlopeStability one = slope_stability(parse_scenario(read_scenario_text(file), file));
  ASSERT_TRUE(one.computed) << one.why_not;
  const std::string soil = test::mohr_coulomb_material("base", 18.0, 5000.0);
  const SlopeStability two = slope_stability(parse_scenario(test::two_body_slope(soil), "two_bodies.toml"));
  ASSERT_TRUE(two.computed) << two.why_not;
  EXPECT_NEAR(two.critical.factor, one.critical.factor, 1e-9);
  EXPECT_EQ(two.materials, (std::vector<std::string>{"soil", "base"}));
  EXPECT_NE(slope_stability_line(two).find("the strengths of soil, base in stage 'slide'"),
            std::string::npos);
  const std::string rock =
      "[[material]]\nname = \"base\"\nmodel = \"linear-elastic\"\ndensity = 2000.0\nyoung = 40.0e6\n"
      "poisson = 0.42\n";
  const SlopeStability firm =
      slope_stability(parse_scenario(test::two_body_slope(rock), "elastic_base.toml"));
  ASSERT_TRUE(firm.computed) << firm.why_not;
  EXPECT_EQ(firm.materials, std::vector<std::string>{"soil"});
  EXPECT_GT(firm.critical.circle.yc - firm.critical.circle.radius, 4.0 - 1e-9)
      << "a circle cut the elastic base";
  EXPECT_GE(firm.critical.factor, one.critical.factor - 1e-9);
}

}  // namespace
}  // namespace skred
