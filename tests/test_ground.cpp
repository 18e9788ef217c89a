// Layered ground from profiles (docs/scenario.md, "Layered ground"): a three-layer
// stratigraphy from CSV profiles builds the same points as the polygons drawn by hand, every
// malformed profile is a located error, and overlapping bodies are refused unless the later
// one wins.
#include <fmt/core.h>
#include <gtest/gtest.h>
#include <stdlib.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "scenario/build.hpp"
#include "scenario/estimate.hpp"
#include "scenario/scenario.hpp"

using namespace skred;
namespace fs = std::filesystem;

namespace {

// A fresh folder of this test's own.
fs::path temp_dir() {
  std::string t = (fs::temp_directory_path() / "skred_ground_XXXXXX").string();
  if (!mkdtemp(t.data())) throw std::runtime_error("mkdtemp failed");
  return t;
}

void write(const fs::path& p, const std::string& text) { std::ofstream(p) << text; }

const std::string kHead = R"(
[grid]
size = [60.0, 24.0]
cell_size = 1.0

[[material]]
name = "sand"
model = "linear-elastic"
density = 1900
young = 2e7
poisson = 0.3

[[material]]
name = "clay"
model = "linear-elastic"
density = 1800
young = 1e7
poisson = 0.3

[solver]
end_time = 1.0
)";

std::string error_of(const std::string& text, const fs::path& file) {
  write(file, text);
  try {
    load_scenario(file.string());
  } catch (const ScenarioError& e) {
    return e.what();
  }
  return "";
}

double mass_of_body(const Particles<2>& p, int body) {
  double m = 0;
  for (std::size_t i = 0; i < p.size(); ++i)
    if (p.body[i] == body) m += p.mass[i];
  return m;
}

}  // namespace

TEST(Ground, ThreeLayersFromProfilesAreThePolygonsDrawnByHand) {
  const fs::path dir = temp_dir();
  // A slope: surface 20 m high on the left falling to 2 m; a clay layer on a base inclined
  // towards the beach; sand between that base and a bedrock line; bedrock below.
  write(dir / "surface.csv", "x,z\n0,20\n25,20\n45,2\n60,2\n");
  write(dir / "clay_base.csv", "# surveyed\nx, z, note\n0, 14, a\n60, 8, b\n");
  write(dir / "rock.csv", "x,z\n0,5\n60,1\n");
  const std::string layered = kHead + R"(
[ground]
surface = "surface.csv"
[[body]]
name = "clay"
material = "clay"
particles_per_cell = 3
shape = "layer"
bottom = "clay_base.csv"
[[body]]
name = "sand"
material = "sand"
particles_per_cell = 3
shape = "layer"
top = "clay_base.csv"
bottom = "rock.csv"
[[body]]
name = "rock"
material = "sand"
particles_per_cell = 3
shape = "layer"
top = "rock.csv"
)";
  write(dir / "layered.toml", layered);
  const Scenario s = load_scenario((dir / "layered.toml").string());
  const Particles<2> p = build_particles(s);

  // The same three regions as polygons: the clay base y = 14 - x/10 meets the surface
  // (20 - 0.9 (x - 25) on 25..45, 2 beyond) at x = 35.625 (y = 10.4375), where the clay
  // pinches out; the sand base y = 5 - x/15 stays below the surface everywhere.
  const std::string polygons = kHead + R"(
[[body]]
name = "clay"
material = "clay"
particles_per_cell = 3
shape = "polygon"
vertices = [[0, 14], [35.625, 10.4375], [25, 20], [0, 20]]
[[body]]
name = "sand"
material = "sand"
particles_per_cell = 3
shape = "polygon"
vertices = [[0, 5], [60, 1], [60, 2], [45, 2], [35.625, 10.4375], [0, 14]]
[[body]]
name = "rock"
material = "sand"
particles_per_cell = 3
shape = "polygon"
vertices = [[0, 0], [60, 0], [60, 1], [0, 5]]
)";
  write(dir / "polygons.toml", polygons);
  const Scenario h = load_scenario((dir / "polygons.toml").string());
  const Particles<2> q = build_particles(h);
  const double point_area = std::pow(1.0 / 3.0, 2);
  for (int b = 0; b < 3; ++b) {
    SCOPED_TRACE(s.bodies[static_cast<std::size_t>(b)].name);
    const double hand =
        std::abs(polygon_area(std::get<Polygon>(h.bodies[static_cast<std::size_t>(b)].shape)));
    const double layer = layer_area(std::get<Layer>(s.bodies[static_cast<std::size_t>(b)].shape));
    EXPECT_NEAR(layer, hand, 1e-9 * hand);  // the exact area of the layer
    const double rho = b == 0 ? 1800 : 1900;
    // The generated points cover the hand-drawn area to within about one point's area per
    // cell the boundary crosses; and profiles and polygons claim the same points.
    EXPECT_NEAR(mass_of_body(p, b) / rho, hand, 0.02 * hand);
    // A point exactly on a shared boundary may fall on either side by round-off.
    EXPECT_NEAR(mass_of_body(p, b), mass_of_body(q, b), (1.0 + 1e-9) * rho * point_area);
  }
  EXPECT_EQ(p.size(), q.size());
  // Nothing double-counted: the layers fill the ground below the surface exactly once.
  const double ground = 20 * 25 + 0.5 * (20 + 2) * 20 + 2 * 15;
  double volume = 0;
  for (std::size_t i = 0; i < p.size(); ++i) volume += p.volume0[i];
  EXPECT_NEAR(volume, ground, 0.01 * ground);
  EXPECT_NEAR(estimate_size(s).points, static_cast<double>(p.size()), 0.01 * p.size());
  fs::remove_all(dir);
}

TEST(Ground, MalformedProfilesNameTheFileAndLine) {
  const fs::path dir = temp_dir();
  const auto layer = [&](const std::string& bottom) {
    return kHead +
           "[[body]]\nmaterial = \"clay\"\nshape = \"layer\"\ntop = [[0, 20], [60, 20]]\n"
           "bottom = " +
           bottom + "\n";
  };
  const fs::path toml = dir / "s.toml";
  const std::pair<std::string, std::string> cases[] = {
      {"x,z\n0,5\n10,6\n8,7\n", "base.csv:4: x must increase strictly along a profile: 8 follows 10"},
      {"x,z\n0,5\n10,nan\n", "base.csv:3: 'nan' is not a finite number"},
      {"x,z\n0,5\n10,abc\n", "base.csv:3: 'abc' is not a finite number"},
      {"x,z\n0,5\n", "base.csv:2: a profile needs at least 2 points, got 1"},
      {"x,z\n0,5\n70,5\n", "base.csv:3: point (70, 5) lies outside the grid"},
      {"x,z\n0,5\n10,-3\n", "base.csv:3: point (10, -3) lies outside the grid"},
      {"a,b\n0,5\n10,5\n", "base.csv:1: the header must name the columns x and z"},
      {"x,z\n0,5\n10\n", "base.csv:3: expected 2 columns as in the header, got 1"},
      {"", "the file is empty"},
  };
  for (const auto& [csv, expect] : cases) {
    SCOPED_TRACE(expect);
    write(dir / "base.csv", csv);
    const std::string e = error_of(layer("\"base.csv\""), toml);
    EXPECT_NE(e.find(expect), std::string::npos) << e;
    if (!csv.empty()) {
      EXPECT_NE(e.find("profile 'body[0].bottom' of "), std::string::npos) << e;
    }
  }
  EXPECT_NE(error_of(layer("\"missing.csv\""), toml).find("key 'body[0].bottom': cannot open profile file"),
            std::string::npos);
  // A device or a directory as the profile: a clear error, not an endless read (fuzzing).
  EXPECT_NE(error_of(layer("\"/dev/zero\""), toml)
                .find("key 'body[0].bottom': cannot read profile file "
                      "'/dev/zero': it is not a regular file"),
            std::string::npos);
  EXPECT_NE(error_of(layer(fmt::format("\"{}\"", dir.string())), toml).find("it is a directory"),
            std::string::npos);
  EXPECT_NE(
      error_of(layer("[[0, 5], [10, 6], [5, 7]]"), toml).find("key 'body[0].bottom[2]': x must increase"),
      std::string::npos);
  EXPECT_NE(error_of(layer("[[0, 5]]"), toml).find("at least 2 points"), std::string::npos);
  EXPECT_NE(error_of(kHead + "[[body]]\nmaterial = \"clay\"\nshape = \"layer\"\n", toml)
                .find("key 'body[0].shape': a layer needs `top`"),
            std::string::npos);
  fs::remove_all(dir);
}

// A scenario that is not a regular file, or far larger than any scenario, is refused at once
// (fuzzing: /dev/zero and /dev/urandom hung `check` and `run`).
TEST(Ground, ScenarioFilesThatCannotEndAreRefused) {
  const auto error = [](const std::string& path) {
    try {
      load_any_scenario(path);
    } catch (const ScenarioError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(error("/dev/zero").find("/dev/zero: cannot read as a scenario file: it is not a regular file"),
            std::string::npos);
  EXPECT_NE(error("/dev/urandom").find("it is not a regular file"), std::string::npos);
  const fs::path dir = temp_dir();
  EXPECT_NE(error(dir.string()).find("it is a directory"), std::string::npos);
  { std::ofstream big(dir / "big.toml"); }
  fs::resize_file(dir / "big.toml", (std::uintmax_t{16} << 20) + 1);  // sparse
  EXPECT_NE(error((dir / "big.toml").string()).find("more than the 16 MiB"), std::string::npos);
  fs::remove_all(dir);
}

TEST(Ground, OverlappingBodiesAreAnErrorUnlessTheLaterWins) {
  const fs::path dir = temp_dir();
  const std::string two = kHead + R"(
[[body]]
name = "left"
material = "sand"
shape = "rectangle"
min = [0, 0]
max = [10, 4]
[[body]]
name = "right"
material = "clay"
shape = "rectangle"
min = [8, 0]
max = [20, 4]
)";
  const fs::path toml = dir / "s.toml";
  const std::string e = error_of(two, toml);
  EXPECT_NE(e.find("key 'body[1].shape': body \"right\" overlaps body \"left\""), std::string::npos) << e;
  EXPECT_NE(e.find("over about 8 m^2"), std::string::npos) << e;
  // Sharing an edge is no overlap.
  std::string touching = two;
  touching.replace(touching.find("min = [8, 0]"), 12, "min = [10, 0]");
  EXPECT_EQ(error_of(touching, toml), "");
  // The later body wins: the points of the overlap are its only, and the mass is that of
  // the union.
  write(toml, "body_overlap = \"later-wins\"\n" + two);
  const Scenario s = load_scenario(toml.string());
  const Particles<2> p = build_particles(s);
  EXPECT_NEAR(mass_of_body(p, 0), 1900 * 8 * 4, 1e-6);
  EXPECT_NEAR(mass_of_body(p, 1), 1800 * 12 * 4, 1e-6);
  fs::remove_all(dir);
}
