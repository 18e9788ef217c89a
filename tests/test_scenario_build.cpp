// Material point generation from a scenario (scenario/build.hpp).
#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <string>
#include <utility>

#include "scenario/build.hpp"
#include "scenario/scenario.hpp"

using namespace skred;

namespace {

Scenario grid_scenario(double lx, double ly, double h) {
  Scenario s;
  s.source = "mem.toml";
  s.cell_size = h;
  s.cells = {static_cast<int>(std::lround(lx / h)), static_cast<int>(std::lround(ly / h))};
  Material m;
  m.name = "m";
  m.density = 2000.0;
  m.elastic = {1e7, 0.3};
  s.materials.push_back(m);
  return s;
}

Body body(Shape shape, int n) {
  return Body{.name = std::string("b"), .shape = std::move(shape), .particles_per_cell = n};
}

}  // namespace

TEST(BuildParticles, RectangleOfTwoCellsWithFourPointsEach) {
  Scenario s = grid_scenario(4.0, 2.0, 1.0);
  s.origin = Vec<2>(10.0, -1.0);
  Body b = body(Rectangle{Vec<2>(11.0, 0.0), Vec<2>(13.0, 1.0)}, 2);
  b.velocity = Vec<2>(1.0, -2.0);
  s.bodies.push_back(b);
  const Particles<2> p = build_particles(s);
  ASSERT_EQ(p.size(), 8u);
  const double expected[8][2] = {{11.25, 0.25}, {11.75, 0.25}, {11.25, 0.75}, {11.75, 0.75},
                                 {12.25, 0.25}, {12.75, 0.25}, {12.25, 0.75}, {12.75, 0.75}};
  double mass = 0.0;
  for (std::size_t k = 0; k < 8; ++k) {
    EXPECT_DOUBLE_EQ(p.x[k][0], expected[k][0]) << k;
    EXPECT_DOUBLE_EQ(p.x[k][1], expected[k][1]) << k;
    EXPECT_EQ(p.x_ref[k], p.x[k]);
    EXPECT_EQ(p.v[k], Vec<2>(1.0, -2.0));
    EXPECT_DOUBLE_EQ(p.volume0[k], 0.25);
    EXPECT_EQ(p.half0[k], Vec<2>(0.25, 0.25));
    EXPECT_EQ(p.material[k], 0);
    EXPECT_EQ(p.body[k], 0);
    EXPECT_EQ(p.F[k], Mat<2>::Identity());
    mass += p.mass[k];
  }
  EXPECT_NEAR(mass, 2000.0 * 2.0, 1e-12 * 4000.0);
}

TEST(BuildParticles, DiscMassIsCloseToTheExactMass) {
  Scenario s = grid_scenario(4.0, 4.0, 0.05);
  s.bodies.push_back(body(Disc{Vec<2>(2.0, 2.0), 1.3}, 2));
  const Particles<2> p = build_particles(s);
  double mass = 0.0;
  for (std::size_t k = 0; k < p.size(); ++k) {
    mass += p.mass[k];
    EXPECT_LT((p.x[k] - Vec<2>(2.0, 2.0)).norm(), 1.3);
  }
  const double exact = 2000.0 * M_PI * 1.3 * 1.3;
  EXPECT_NEAR(mass, exact, 0.02 * exact);
}

TEST(BuildParticles, PolygonMassMatchesAreaForAnyOrientation) {
  Scenario s = grid_scenario(4.0, 4.0, 0.1);
  Polygon ccw{{Vec<2>(0.5, 0.5), Vec<2>(3.5, 0.5), Vec<2>(0.5, 3.5)}};
  Polygon cw{{Vec<2>(0.5, 0.5), Vec<2>(0.5, 3.5), Vec<2>(3.5, 0.5)}};
  EXPECT_DOUBLE_EQ(polygon_area(ccw), 4.5);
  EXPECT_DOUBLE_EQ(polygon_area(cw), -4.5);
  s.bodies.push_back(body(ccw, 2));
  s.bodies.push_back(body(cw, 2));
  EXPECT_EQ(count_points(s, s.bodies[0]), count_points(s, s.bodies[1]));
  const Particles<2> p = build_particles(s);
  double mass = 0.0;
  for (std::size_t k = 0; k < p.size(); ++k)
    if (p.body[k] == 0) mass += p.mass[k];
  EXPECT_NEAR(mass, 2000.0 * 4.5, 0.02 * 2000.0 * 4.5);
}

TEST(BuildParticles, TouchingShapesNeverSharePoints) {
  // The shared edge x = 0.75 runs through a column of sub-cell centres.
  Scenario s = grid_scenario(2.0, 2.0, 1.0);
  s.bodies.push_back(body(Rectangle{Vec<2>(0.0, 0.0), Vec<2>(0.75, 2.0)}, 2));
  s.bodies.push_back(body(Rectangle{Vec<2>(0.75, 0.0), Vec<2>(2.0, 0.75)}, 2));
  s.bodies.push_back(body(Rectangle{Vec<2>(0.75, 0.75), Vec<2>(2.0, 2.0)}, 2));
  // Two triangles sharing the diagonal y = x, which passes through sub-cell centres.
  Scenario t = grid_scenario(2.0, 2.0, 1.0);
  t.bodies.push_back(body(Polygon{{Vec<2>(0, 0), Vec<2>(2, 0), Vec<2>(2, 2)}}, 2));
  t.bodies.push_back(body(Polygon{{Vec<2>(2, 2), Vec<2>(0, 2), Vec<2>(0, 0)}}, 2));
  for (const Scenario* sc : {&s, &t}) {
    const Particles<2> p = build_particles(*sc);
    std::set<std::pair<double, double>> seen;
    for (std::size_t k = 0; k < p.size(); ++k)
      EXPECT_TRUE(seen.insert({p.x[k][0], p.x[k][1]}).second)
          << "point (" << p.x[k][0] << ", " << p.x[k][1] << ") claimed twice";
    EXPECT_EQ(p.size(), 16u);  // the union covers the whole 2 x 2 grid exactly once
  }
  EXPECT_EQ(count_points(s, s.bodies[0]), 4u);
  EXPECT_EQ(count_points(t, t.bodies[0]) + count_points(t, t.bodies[1]), 16u);
}

TEST(BuildParticles, BodiesAreNumberedInOrder) {
  Scenario s = grid_scenario(4.0, 2.0, 0.5);
  Material m2 = s.materials[0];
  m2.name = "m2";
  m2.density = 1000.0;
  s.materials.push_back(m2);
  s.bodies.push_back(body(Rectangle{Vec<2>(0.0, 0.0), Vec<2>(1.0, 1.0)}, 1));
  Body b2 = body(Rectangle{Vec<2>(2.0, 0.0), Vec<2>(3.0, 1.0)}, 3);
  b2.material = 1;
  s.bodies.push_back(b2);
  const Particles<2> p = build_particles(s);
  ASSERT_EQ(p.size(), 4u + 36u);
  EXPECT_EQ(p.body[3], 0);
  EXPECT_EQ(p.body[4], 1);
  EXPECT_EQ(p.material[4], 1);
  EXPECT_DOUBLE_EQ(p.mass[4], 1000.0 * (0.5 / 3) * (0.5 / 3));
  EXPECT_DOUBLE_EQ(p.half0[4][0], 0.5 / 6);
}

TEST(BuildParticles, EmptyBodyIsAnError) {
  Scenario s = grid_scenario(2.0, 2.0, 1.0);
  s.bodies.push_back(body(Disc{Vec<2>(1.0, 1.0), 0.05}, 2));
  try {
    build_particles(s);
    FAIL() << "no exception";
  } catch (const ScenarioError& e) {
    EXPECT_NE(std::string(e.what()).find("body[0].shape"), std::string::npos) << e.what();
  }
}

TEST(BuildParticles, DescribeSummarisesTheScenario) {
  // One literal: GCC 12 gave a false -Warray-bounds on the concatenated temporary (PCH build,
  // a source folder of 11 characters).
  const Scenario s = load_scenario(SKRED_SOURCE_DIR "/tests/data/full.toml");
  const std::string d = describe(s);
  for (const char* part : {"48 x 16 cells", "sand", "clay", "column", "body-1", "boulder", "gimp-quadrature",
                           "usl", "friction (mu = 0.6)", "roller"})
    EXPECT_NE(d.find(part), std::string::npos) << part << " missing in:\n" << d;
}
