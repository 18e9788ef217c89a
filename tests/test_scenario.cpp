// Scenario parser (scenario/parser.cpp): valid files and one-defect malformed files.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "scenario/build.hpp"
#include "scenario/scenario.hpp"

using namespace skred;

namespace {

const std::string kData = std::string(SKRED_SOURCE_DIR) + "/tests/data/";

// A valid scenario; every malformed case below is this text with one defect.
constexpr const char* kBase = R"(title = "t"
[grid]
origin = [0, 0]
size = [4.0, 2.0]
cell_size = 0.5

[[material]]
name = "sand"
model = "linear-elastic"
density = 2000.0
young = 1e7
poisson = 0.3

[[body]]
name = "block"
material = "sand"
particles_per_cell = 2
shape = "rectangle"
min = [0.0, 0.0]
max = [1.0, 1.0]

[gravity]
acceleration = [0, -9.81]

[boundary]
x_min = "fixed"
y_min = { type = "friction", friction = 0.5 }

[solver]
interpolation = "gimp"
scheme = "averaged"
end_time = 1.0
cfl = 0.3

[output]
interval = 0.1
)";

using Edits = std::vector<std::pair<std::string, std::string>>;

struct BadCase {
  const char* name;
  Edits edits;      // (text in kBase, replacement); the line the error must point at
                    // carries the marker "# <--"
  std::string key;  // key the message must name ("" for syntax errors)
};

std::string apply(const Edits& edits) {
  std::string text = kBase;
  for (const auto& [from, to] : edits) {
    const auto pos = text.find(from);
    EXPECT_NE(pos, std::string::npos) << from;
    EXPECT_EQ(text.find(from, pos + 1), std::string::npos) << "ambiguous edit: " << from;
    if (pos != std::string::npos) text.replace(pos, from.size(), to);
  }
  return text;
}

int marker_line(const std::string& text) {
  int line = 1;
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text.compare(i, 5, "# <--") == 0) return line;
    if (text[i] == '\n') ++line;
  }
  return -1;
}

const std::vector<BadCase>& bad_cases() {
  static const std::vector<BadCase> cases = {
      {"unknown top-level key",
       {{R"(title = "t")", R"(title = "t"
colour = "red"  # <--)"}},
       "colour"},
      {"unknown key in grid", {{"cell_size = 0.5", "cell_size = 0.5\nspacing = 1  # <--"}}, "grid.spacing"},
      {"unknown key in material", {{"poisson = 0.3", "poisson = 0.3\nphi = 30  # <--"}}, "material[0].phi"},
      {"unknown key in body (radius on a rectangle)",
       {{"max = [1.0, 1.0]", "max = [1.0, 1.0]\nradius = 0.5  # <--"}},
       "body[0].radius"},
      {"unknown key in inline boundary table",
       {{"friction = 0.5 }", "friction = 0.5, mu = 1 }  # <--"}},
       "boundary.y_min.mu"},
      {"missing grid.cell_size", {{"[grid]", "[grid]  # <--"}, {"cell_size = 0.5\n", ""}}, "grid.cell_size"},
      {"missing solver.end_time",
       {{"[solver]", "[solver]  # <--"}, {"end_time = 1.0\n", ""}},
       "solver.end_time"},
      {"missing material.density",
       {{"[[material]]", "[[material]]  # <--"}, {"density = 2000.0\n", ""}},
       "material[0].density"},
      {"missing [grid] table",
       {{R"(title = "t")", R"(title = "t"  # <--)"},
        {"[grid]\norigin = [0, 0]\nsize = [4.0, 2.0]\ncell_size = 0.5\n", ""}},
       "grid"},
      {"missing body shape",
       {{"[[body]]", "[[body]]  # <--"}, {"shape = \"rectangle\"\nmin = [0.0, 0.0]\nmax = [1.0, 1.0]\n", ""}},
       "body[0].shape"},
      {"cell_size is a string", {{"cell_size = 0.5", R"(cell_size = "a"  # <--)"}}, "grid.cell_size"},
      {"particles_per_cell is a float",
       {{"particles_per_cell = 2", "particles_per_cell = 2.5  # <--"}},
       "body[0].particles_per_cell"},
      {"end_time is a boolean", {{"end_time = 1.0", "end_time = true  # <--"}}, "solver.end_time"},
      // Shorter than one time step (1.8e-3 s here): fuzzing found such runs "completed" with no
      // step, and stages of 1e-4 s each taking a whole step.
      {"end_time of 1e-30 s", {{"end_time = 1.0", "end_time = 1e-30  # <--"}}, "solver.end_time"},
      {"end_time below one step", {{"end_time = 1.0", "end_time = 0.001  # <--"}}, "solver.end_time"},
      {"a stage below one step",
       {{"end_time = 1.0\n", ""},
        {"[output]", "[[stage]]\nduration = 1.0\n[[stage]]\nduration = 1e-4  # <--\n\n[output]"}},
       "stage[1].duration"},
      {"material is a plain table", {{"[[material]]", "[material]  # <--"}}, "material"},
      {"velocity has three components",
       {{"max = [1.0, 1.0]", "max = [1.0, 1.0]\nvelocity = [1, 0, 0]  # <--"}},
       "body[0].velocity"},
      {"poisson = 0.5", {{"poisson = 0.3", "poisson = 0.5  # <--"}}, "material[0].poisson"},
      {"cfl = 0", {{"cfl = 0.3", "cfl = 0  # <--"}}, "solver.cfl"},
      {"cfl > 1", {{"cfl = 0.3", "cfl = 1.5  # <--"}}, "solver.cfl"},
      {"negative density", {{"density = 2000.0", "density = -2000.0  # <--"}}, "material[0].density"},
      {"particles_per_cell = 0",
       {{"particles_per_cell = 2", "particles_per_cell = 0  # <--"}},
       "body[0].particles_per_cell"},
      {"particles_per_cell = 9",
       {{"particles_per_cell = 2", "particles_per_cell = 9  # <--"}},
       "body[0].particles_per_cell"},
      {"negative friction", {{"friction = 0.5 }", "friction = -0.1 }  # <--"}}, "boundary.y_min.friction"},
      {"friction coefficient with a fixed side",
       {{R"(type = "friction", friction = 0.5 })", R"(type = "fixed", friction = 0.5 }  # <--)"}},
       "boundary.y_min.friction"},
      {"zero output interval", {{"interval = 0.1", "interval = 0.0  # <--"}}, "output.interval"},
      {"negative time step", {{"cfl = 0.3", "cfl = 0.3\ntime_step = -1e-4  # <--"}}, "solver.time_step"},
      {"quadrature_points = 4",
       {{"cfl = 0.3", "cfl = 0.3\nquadrature_points = 4  # <--"}},
       "solver.quadrature_points"},
      {"non-finite young", {{"young = 1e7", "young = inf  # <--"}}, "material[0].young"},
      {"non-finite gravity",
       {{"acceleration = [0, -9.81]", "acceleration = [0, nan]  # <--"}},
       "gravity.acceleration"},
      {"unknown interpolation",
       {{R"(interpolation = "gimp")", R"(interpolation = "cubic"  # <--)"}},
       "solver.interpolation"},
      {"unknown scheme", {{R"(scheme = "averaged")", R"(scheme = "mls"  # <--)"}}, "solver.scheme"},
      {"unknown boundary kind", {{R"(x_min = "fixed")", R"(x_min = "sticky"  # <--)"}}, "boundary.x_min"},
      {"unknown boundary type in table",
       {{R"(y_min = { type = "friction", friction = 0.5 })", R"(y_min = { type = "glue" }  # <--)"}},
       "boundary.y_min.type"},
      {"bare friction", {{R"(x_min = "fixed")", R"(x_min = "friction"  # <--)"}}, "boundary.x_min"},
      {"boundary is a number", {{R"(x_min = "fixed")", R"(x_min = 1  # <--)"}}, "boundary.x_min"},
      {"unknown model",
       {{R"(model = "linear-elastic")", R"(model = "cam-clay"  # <--)"}},
       "material[0].model"},
      {"unknown material reference",
       {{R"(material = "sand")", R"(material = "clay"  # <--)"}},
       "body[0].material"},
      {"duplicate material names",
       {{"poisson = 0.3", R"(poisson = 0.3
[[material]]
name = "sand"  # <--
model = "linear-elastic"
density = 1800.0
young = 5e6
poisson = 0.35)"}},
       "material[1].name"},
      {"grid size not a multiple of cell_size",
       {{"size = [4.0, 2.0]", "size = [4.0, 2.2]  # <--"}},
       "grid.size"},
      {"too many cells", {{"cell_size = 0.5", "cell_size = 1e-5  # <--"}}, "grid.cell_size"},
      {"non-positive grid size", {{"size = [4.0, 2.0]", "size = [0.0, 2.0]  # <--"}}, "grid.size"},
      {"rectangle outside the grid", {{"max = [1.0, 1.0]", "max = [4.5, 1.0]  # <--"}}, "body[0].max"},
      {"rectangle with max < min", {{"max = [1.0, 1.0]", "max = [1.0, -1.0]  # <--"}}, "body[0].max"},
      {"disc outside the grid",
       {{"shape = \"rectangle\"\nmin = [0.0, 0.0]\nmax = [1.0, 1.0]",
         "shape = \"disc\"\ncenter = [1.0, 1.0]\nradius = 1.5  # <--"}},
       "body[0].radius"},
      {"polygon with 2 vertices",
       {{"shape = \"rectangle\"\nmin = [0.0, 0.0]\nmax = [1.0, 1.0]",
         "shape = \"polygon\"\nvertices = [[0, 0], [1, 1]]  # <--"}},
       "body[0].vertices"},
      {"polygon with zero area",
       {{"shape = \"rectangle\"\nmin = [0.0, 0.0]\nmax = [1.0, 1.0]",
         "shape = \"polygon\"\nvertices = [[0, 0], [1, 1], [2, 2]]  # <--"}},
       "body[0].vertices"},
      {"polygon vertex outside the grid",
       {{"shape = \"rectangle\"\nmin = [0.0, 0.0]\nmax = [1.0, 1.0]",
         "shape = \"polygon\"\nvertices = [[0, 0], [1, 0],\n  [1, 9]]  # <--"}},
       "body[0].vertices[2]"},
      {"body too small to hold a point",
       {{"shape = \"rectangle\"\nmin = [0.0, 0.0]\nmax = [1.0, 1.0]",
         "shape = \"disc\"  # <--\ncenter = [1.0, 1.0]\nradius = 0.01"}},
       "body[0].shape"},
      {"TOML syntax error", {{"cell_size = 0.5", "cell_size = = 0.5  # <--"}}, ""},
  };
  return cases;
}

}  // namespace

TEST(Scenario, FullExampleParsesIntoExpectedValues) {
  const Scenario s = load_scenario(kData + "full.toml");
  EXPECT_EQ(s.source, kData + "full.toml");
  EXPECT_EQ(s.title, "Column collapse on a rough floor");
  EXPECT_EQ(s.origin, Vec<2>(-1.0, 0.0));
  EXPECT_EQ(s.cells[0], 48);
  EXPECT_EQ(s.cells[1], 16);
  EXPECT_DOUBLE_EQ(s.cell_size, 0.25);

  ASSERT_EQ(s.materials.size(), 2u);
  EXPECT_EQ(s.materials[0].name, "sand");
  EXPECT_EQ(s.materials[0].model, Model::LinearElastic);
  EXPECT_DOUBLE_EQ(s.materials[0].density, 2000.0);
  EXPECT_DOUBLE_EQ(s.materials[0].elastic.young, 1e7);
  EXPECT_DOUBLE_EQ(s.materials[0].elastic.poisson, 0.3);
  EXPECT_EQ(s.materials[1].name, "clay");
  EXPECT_DOUBLE_EQ(s.materials[1].density, 1800.0);  // written as an integer

  ASSERT_EQ(s.bodies.size(), 3u);
  const Body& column = s.bodies[0];
  EXPECT_EQ(column.name, "column");
  EXPECT_EQ(column.material, 0);
  EXPECT_EQ(column.particles_per_cell, 3);
  EXPECT_EQ(column.velocity, Vec<2>(0.5, 0.0));
  ASSERT_TRUE(std::holds_alternative<Rectangle>(column.shape));
  EXPECT_EQ(std::get<Rectangle>(column.shape).min, Vec<2>(0.0, 0.0));
  EXPECT_EQ(std::get<Rectangle>(column.shape).max, Vec<2>(2.0, 3.0));

  const Body& wedge = s.bodies[1];
  EXPECT_EQ(wedge.name, "body-1");
  EXPECT_EQ(wedge.material, 1);
  EXPECT_EQ(wedge.particles_per_cell, 2);
  EXPECT_EQ(wedge.velocity, Vec<2>::Zero());
  ASSERT_TRUE(std::holds_alternative<Polygon>(wedge.shape));
  ASSERT_EQ(std::get<Polygon>(wedge.shape).vertices.size(), 3u);
  EXPECT_EQ(std::get<Polygon>(wedge.shape).vertices[2], Vec<2>(3.0, 1.5));

  ASSERT_TRUE(std::holds_alternative<Disc>(s.bodies[2].shape));
  EXPECT_EQ(std::get<Disc>(s.bodies[2].shape).center, Vec<2>(8.0, 1.0));
  EXPECT_DOUBLE_EQ(std::get<Disc>(s.bodies[2].shape).radius, 0.5);

  EXPECT_EQ(s.gravity, Vec<2>(0.0, -9.81));
  EXPECT_DOUBLE_EQ(s.gravity_ramp_time, 0.5);
  EXPECT_EQ(s.boundaries[0].kind, BoundaryKind::Fixed);
  EXPECT_EQ(s.boundaries[1].kind, BoundaryKind::Roller);
  EXPECT_EQ(s.boundaries[2].kind, BoundaryKind::Friction);
  EXPECT_DOUBLE_EQ(s.boundaries[2].friction, 0.6);
  EXPECT_EQ(s.boundaries[3].kind, BoundaryKind::Free);

  EXPECT_EQ(s.interpolation, Interpolation::GimpQuadrature);
  EXPECT_EQ(s.quadrature_points, 3);
  EXPECT_EQ(s.scheme, StressScheme::USL);
  EXPECT_DOUBLE_EQ(s.end_time, 2.0);
  EXPECT_DOUBLE_EQ(s.time_step, 1e-4);
  EXPECT_DOUBLE_EQ(s.cfl, 0.5);
  EXPECT_DOUBLE_EQ(s.output_interval, 0.05);
  EXPECT_DOUBLE_EQ(s.series_interval, 0.001);
}

TEST(Scenario, MinimalExampleGetsDefaults) {
  const Scenario s = load_scenario(kData + "minimal.toml");
  EXPECT_EQ(s.title, "");
  EXPECT_EQ(s.origin, Vec<2>::Zero());
  EXPECT_EQ(s.cells[0], 8);
  EXPECT_EQ(s.cells[1], 4);
  ASSERT_EQ(s.bodies.size(), 1u);
  EXPECT_EQ(s.bodies[0].name, "body-0");
  EXPECT_EQ(s.bodies[0].particles_per_cell, 2);
  EXPECT_EQ(s.gravity, Vec<2>::Zero());
  EXPECT_EQ(s.gravity_ramp_time, 0.0);
  for (const auto& b : s.boundaries) EXPECT_EQ(b.kind, BoundaryKind::Free);
  EXPECT_EQ(s.interpolation, Interpolation::Gimp);
  EXPECT_EQ(s.quadrature_points, 2);
  EXPECT_EQ(s.scheme, StressScheme::Averaged);
  EXPECT_EQ(s.time_step, 0.0);
  EXPECT_DOUBLE_EQ(s.cfl, 0.3);
  EXPECT_DOUBLE_EQ(s.output_interval, 1.0 / 20.0);
  EXPECT_DOUBLE_EQ(s.series_interval, 1.0 / 200.0);
}

TEST(Scenario, EveryDataFileIsValid) {
  int n = 0;
  for (const auto& e : std::filesystem::directory_iterator(kData)) {
    if (e.path().extension() != ".toml") continue;
    EXPECT_NO_THROW(build_particles(load_scenario(e.path().string()))) << e.path();
    ++n;
  }
  EXPECT_GE(n, 2);
}

TEST(Scenario, BaseTextOfTheMalformedCasesIsValid) {
  const Scenario s = parse_scenario(kBase, "test.toml");
  EXPECT_EQ(s.boundaries[2].kind, BoundaryKind::Friction);
  EXPECT_DOUBLE_EQ(s.boundaries[2].friction, 0.5);
}

TEST(Scenario, MalformedInputNamesFileLineAndKey) {
  ASSERT_GE(bad_cases().size(), 20u);
  for (const auto& c : bad_cases()) {
    SCOPED_TRACE(c.name);
    const std::string text = apply(c.edits);
    const int line = marker_line(text);
    ASSERT_GT(line, 0) << "test case without a '# <--' marker";
    try {
      parse_scenario(text, "test.toml");
      ADD_FAILURE() << "accepted:\n" << text;
    } catch (const ScenarioError& e) {
      const std::string what = e.what();
      const std::string prefix = "test.toml:" + std::to_string(line) + ":";
      EXPECT_EQ(what.rfind(prefix, 0), 0u) << what;
      if (c.key.empty()) {
        EXPECT_NE(what.find(": syntax error: "), std::string::npos) << what;
      } else {
        EXPECT_NE(what.find(": key '" + c.key + "': "), std::string::npos) << what;
      }
    }
  }
}

TEST(Scenario, MessagesHaveTheDocumentedForm) {
  auto message = [](const Edits& edits) {
    try {
      parse_scenario(apply(edits), "s.toml");
    } catch (const ScenarioError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message({{"cell_size = 0.5", R"(cell_size = "a")"}}),
            "s.toml:5:13: key 'grid.cell_size': expected a number, got a string");
  EXPECT_EQ(message({{"poisson = 0.3", "poisson = 0.5"}}),
            "s.toml:12:11: key 'material[0].poisson': must be >= 0 and < 0.5, got 0.5");
  const std::string interp = message({{R"(interpolation = "gimp")", R"(interpolation = "cubic")"}});
  for (const char* v : {"\"linear\"", "\"gimp\"", "\"gimp-quadrature\"", "\"bspline\""})
    EXPECT_NE(interp.find(v), std::string::npos) << interp;
  const std::string scheme = message({{R"(scheme = "averaged")", R"(scheme = "x")"}});
  for (const char* v : {"\"usf\"", "\"usl\"", "\"averaged\""})
    EXPECT_NE(scheme.find(v), std::string::npos) << scheme;
  EXPECT_NE(message({{"[grid]", "[grid]\nfoo = 1"}}).find("allowed keys here: origin, size, cell_size"),
            std::string::npos);
}

TEST(Scenario, LoadReportsUnreadableFile) {
  try {
    load_scenario("/nonexistent/skred.toml");
    FAIL() << "no exception";
  } catch (const ScenarioError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/skred.toml"), std::string::npos);
  }
}

TEST(Scenario, EnumNamesRoundTrip) {
  EXPECT_STREQ(to_string(Interpolation::GimpQuadrature), "gimp-quadrature");
  EXPECT_STREQ(to_string(StressScheme::USF), "usf");
  EXPECT_STREQ(to_string(BoundaryKind::Roller), "roller");
}
