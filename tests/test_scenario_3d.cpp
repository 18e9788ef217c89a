// 3D scenario files (scenario/parser.cpp, parser_geometry.cpp, parser_shapes3.cpp): every 3D
// key parses, the bodies fill with n x n x n points per cell, the K0 stress sums the
// overburden per (x, z) column (Thesis eq. 5.6-5.7), and bad 3D input names file, line and key.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>

#include "scenario/build.hpp"
#include "scenario/initial_stress.hpp"
#include "scenario/scenario.hpp"

using namespace skred;

namespace {

const std::string kSource = std::string(SKRED_SOURCE_DIR);

Scenario3 load3(const std::string& path) {
  const AnyScenario any = load_any_scenario(path);
  EXPECT_TRUE(std::holds_alternative<Scenario3>(any)) << path;
  return std::get<Scenario3>(any);
}

// Volume of the points of body b: count x (h/n)^3.
double filled_volume(const Scenario3& s, std::size_t b) {
  const double q = s.cell_size / s.bodies[b].particles_per_cell;
  return static_cast<double>(count_points(s, s.bodies[b])) * q * q * q;
}

}  // namespace

TEST(Scenario3D, EveryKeyParses) {
  const Scenario3 s = load3(kSource + "/tests/data3d/full3d.toml");
  EXPECT_EQ(s.title, "Every 3D key");
  EXPECT_EQ(s.origin, Vec<3>(-1.0, 0.0, -2.0));
  EXPECT_EQ(s.cells, (std::array<int, 3>{32, 16, 16}));
  EXPECT_EQ(s.cell_count(), 32L * 16 * 16);
  ASSERT_EQ(s.bodies.size(), 4u);

  const Body3& block = s.bodies[0];
  EXPECT_EQ(block.particles_per_cell, 3);
  EXPECT_EQ(block.velocity, Vec<3>(0.5, 0.0, -0.25));
  EXPECT_EQ(block.velocity_sine.amplitude, Vec<3>(0.0, 0.0, 0.1));
  EXPECT_EQ(block.velocity_sine.axis, 2);
  EXPECT_EQ(block.velocity_sine.origin, -2.0);
  ASSERT_TRUE(std::holds_alternative<Box>(block.shape));
  EXPECT_EQ(std::get<Box>(block.shape).max, Vec<3>(1.0, 2.0, 1.0));

  ASSERT_TRUE(std::holds_alternative<ExtrudedPolygon>(s.bodies[1].shape));
  const auto& wedge = std::get<ExtrudedPolygon>(s.bodies[1].shape);
  EXPECT_EQ(wedge.section.vertices.size(), 3u);
  EXPECT_EQ(wedge.z_min, -2.0);
  EXPECT_EQ(wedge.z_max, 0.5);

  ASSERT_TRUE(std::holds_alternative<Cylinder>(s.bodies[2].shape));
  const auto& pipe = std::get<Cylinder>(s.bodies[2].shape);
  EXPECT_EQ(pipe.axis, Vec<3>(0.0, 0.0, 1.0));  // normalised
  EXPECT_EQ(pipe.radius, 0.5);
  EXPECT_EQ(pipe.length, 3.0);

  ASSERT_TRUE(std::holds_alternative<Sphere>(s.bodies[3].shape));
  EXPECT_EQ(std::get<Sphere>(s.bodies[3].shape).center, Vec<3>(6.0, 3.0, 1.0));

  EXPECT_EQ(s.initial_stress.rule, K0Rule::Jaky);
  EXPECT_EQ(s.gravity, Vec<3>(0.0, -9.81, 0.0));
  const BoundaryKind kinds[6] = {BoundaryKind::Roller, BoundaryKind::Fixed,  BoundaryKind::Friction,
                                 BoundaryKind::Free,   BoundaryKind::Roller, BoundaryKind::Roller};
  for (int k = 0; k < 6; ++k) EXPECT_EQ(s.boundaries[k].kind, kinds[k]) << k;
  EXPECT_EQ(s.boundaries[2].friction, 0.4);

  // The bodies hold their volumes: the box and the prism exactly, the round ones to a few %.
  EXPECT_DOUBLE_EQ(filled_volume(s, 0), 1.0 * 2.0 * 2.0);
  EXPECT_DOUBLE_EQ(filled_volume(s, 1), 0.5 * 2.0 * 1.0 * 2.5);
  EXPECT_NEAR(filled_volume(s, 2), M_PI * 0.25 * 3.0, 0.05 * M_PI * 0.25 * 3.0);
  EXPECT_NEAR(filled_volume(s, 3), 4.0 / 3.0 * M_PI * 0.125, 0.08 * 4.0 / 3.0 * M_PI * 0.125);

  const Particles<3> P = build_particles(s);
  const double q = 0.25 / 3;
  EXPECT_EQ(P.x[0], Vec<3>(q / 2, q / 2, -1.0 + q / 2));  // x fastest, then y, then z
  EXPECT_EQ(P.x[1], Vec<3>(1.5 * q, q / 2, -1.0 + q / 2));
  EXPECT_DOUBLE_EQ(P.volume0[0], q * q * q);
  EXPECT_DOUBLE_EQ(P.mass[0], 2000.0 * q * q * q);
  EXPECT_EQ(P.half0[0], Vec<3>::Constant(q / 2));
  // The sine along z: v_z = -0.25 + 0.1 sin(2 pi (z + 2) / 2).
  EXPECT_NEAR(P.v[0][2], -0.25 + 0.1 * std::sin(M_PI * (P.x[0][2] + 2.0)), 1e-15);
  EXPECT_NE(describe(s).find("grid (3D): 32 x 16 x 16 cells"), std::string::npos) << describe(s);
}

TEST(Scenario3D, K0StressFromTheOverburdenOfEachColumn) {
  // Two boxes of different density stacked on part of the floor: sigma_yy = -g (weight above
  // per unit area + half the point's own), sigma_xx = sigma_zz = K0 sigma_yy (eq. 5.6-5.7).
  const AnyScenario any = parse_any_scenario(R"(
[grid]
size = [2.0, 2.0, 2.0]
cell_size = 0.5
[[material]]
name = "a"
model = "linear-elastic"
density = 2000
young = 1e7
poisson = 0.25
[[material]]
name = "b"
model = "linear-elastic"
density = 1000
young = 1e7
poisson = 0.25
[[body]]
material = "a"
shape = "box"
min = [0, 0, 0]
max = [1, 1, 2]
[[body]]
material = "b"
shape = "box"
min = [0, 1, 0]
max = [1, 1.5, 1]
[initial_stress]
k0 = "poisson"
[gravity]
acceleration = [0, -10, 0]
[solver]
end_time = 1
)",
                                             "k0.toml");
  const Scenario3& s = std::get<Scenario3>(any);
  Particles<3> P = build_particles(s);
  apply_initial_stress(s, P);
  const double k0 = 0.25 / 0.75;
  for (std::size_t p = 0; p < P.size(); ++p) {
    const Vec<3>& x = P.x[p];
    double expected;
    if (P.body[p] == 1)
      expected = -10.0 * 1000 * (1.5 - x[1]);
    else
      expected = -10.0 * (2000 * (1.0 - x[1]) + (x[2] < 1.0 ? 1000 * 0.5 : 0.0));
    ASSERT_NEAR(P.stress[p][1], expected, 1e-9) << p;
    EXPECT_NEAR(P.stress[p][0], k0 * expected, 1e-9);
    EXPECT_NEAR(P.stress[p][2], k0 * expected, 1e-9);
    EXPECT_EQ(P.stress[p][3], 0.0);
    EXPECT_EQ(P.stress[p][4], 0.0);
    EXPECT_EQ(P.stress[p][5], 0.0);
  }
}

TEST(Scenario3D, BadInputNamesFileLineAndKey) {
  int n = 0;
  for (const auto& e : std::filesystem::directory_iterator(kSource + "/tests/bad_scenarios")) {
    const std::string name = e.path().filename().string();
    if (name.rfind("3d_", 0) != 0) continue;
    SCOPED_TRACE(name);
    std::ifstream in(e.path());
    std::string first;
    std::getline(in, first);
    const std::string key = first.substr(std::string("# expect: ").size());
    try {
      load_any_scenario(e.path().string());
      ADD_FAILURE() << "accepted";
    } catch (const ScenarioError& err) {
      const std::regex form("^" + std::regex_replace(e.path().string(), std::regex(R"([.\[\]])"), R"(\$&)") +
                            R"(:[0-9]+:[0-9]+: key ')" +
                            std::regex_replace(key, std::regex(R"([.\[\]])"), R"(\$&)") + "': .+");
      EXPECT_TRUE(std::regex_match(std::string(err.what()), form)) << err.what();
    }
    ++n;
  }
  EXPECT_GE(n, 10);
}

TEST(Scenario3D, TwoDimensionalEntryPointsRejectA3DFileAndViceVersa) {
  const std::string path = kSource + "/tests/data3d/full3d.toml";
  try {
    load_scenario(path);
    FAIL() << "load_scenario accepted a 3D file";
  } catch (const ScenarioError& e) {
    EXPECT_NE(std::string(e.what()).find("key 'grid.size': this is a 3D scenario"), std::string::npos)
        << e.what();
  }
  // A 2D file stays 2D, and a z side in it is an unknown key, as before 3D existed.
  EXPECT_TRUE(std::holds_alternative<Scenario>(load_any_scenario(kSource + "/tests/data/full.toml")));
  try {
    parse_any_scenario(R"([grid]
size = [2.0, 1.0]
cell_size = 0.5
[[material]]
name = "m"
model = "linear-elastic"
density = 1
young = 1
poisson = 0
[[body]]
material = "m"
shape = "rectangle"
min = [0, 0]
max = [1, 1]
[boundary]
z_min = "roller"
[solver]
end_time = 1
)",
                       "two.toml");
    FAIL() << "accepted z_min in 2D";
  } catch (const ScenarioError& e) {
    EXPECT_EQ(std::string(e.what()),
              "two.toml:16:1: key 'boundary.z_min': unknown key; allowed keys "
              "here: x_min, x_max, y_min, y_max");
  }
}

TEST(Scenario3D, TheThreeDimensionalExamplesAreValid) {
  const Scenario3 slab = load3(kSource + "/examples/column_slab_3d.toml");
  EXPECT_EQ(build_particles(slab).size(), 12800u);  // 20 x 40 x 2 cells, 8 points each
  EXPECT_EQ(slab.boundaries[4].kind, BoundaryKind::Roller);
  EXPECT_EQ(slab.boundaries[5].kind, BoundaryKind::Roller);
  const Scenario3 square = load3(kSource + "/examples/column_3d.toml");
  EXPECT_EQ(build_particles(square).size(), 18432u);  // 12 x 16 x 12 cells
}

TEST(Scenario3D, SweepOverridesApplyToThreeDimensionalFiles) {
  const std::string text = R"([grid]
size = [2.0, 1.0, 1.0]
cell_size = 0.5
[[material]]
name = "m"
model = "linear-elastic"
density = 1
young = 1
poisson = 0
[[body]]
material = "m"
shape = "sphere"
center = [1, 0.5, 0.5]
radius = 0.4
[solver]
end_time = 1
)";
  const AnyScenario any =
      parse_any_scenario(text, "sweep.toml", {{"grid.cell_size", 0.25}, {"body[0].radius", 0.3}});
  const Scenario3& s = std::get<Scenario3>(any);
  EXPECT_EQ(s.cells, (std::array<int, 3>{8, 4, 4}));
  EXPECT_EQ(std::get<Sphere>(s.bodies[0].shape).radius, 0.3);
}
