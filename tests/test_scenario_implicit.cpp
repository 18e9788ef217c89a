// The implicit integrator's part of a scenario file (scenario/parser_implicit.cpp):
// solver.integrator and the stages' `integrator`, [implicit] and [stage.implicit], grid.geometry
// (axisymmetric masses per radian), [[pressure]], what the implicit integrator refuses, and what
// `skred check` says about it. Every error names file, line and key.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "scenario/build.hpp"
#include "scenario/estimate.hpp"
#include "scenario/initial_stress.hpp"
#include "scenario/scenario.hpp"
#include "scenario/schema.hpp"
#include "scenario_error.hpp"

using namespace skred;

namespace {

// A column on a 4 x 2 m grid of 0.5 m cells; [solver] last, so keys appended go there.
constexpr const char* kHead = R"(title = "t"
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
shape = "rectangle"
min = [0.0, 0.0]
max = [1.0, 1.0]

[gravity]
acceleration = [0, -9.81]

[boundary]
x_min = "roller"
y_min = "fixed"
)";

// kHead with an implicit [solver]; `extra` follows it (more [solver] keys, then other tables).
std::string implicit_text(const std::string& extra = "") {
  return std::string(kHead) + "\n[solver]\nend_time = 1.0\nintegrator = \"implicit\"\n" + extra;
}
std::string explicit_text(const std::string& extra = "") {
  return std::string(kHead) + "\n[solver]\nend_time = 1.0\n" + extra;
}
// kHead with [[stage]] tables (and no [solver]).
std::string staged_text(const std::string& stages) { return std::string(kHead) + "\n" + stages; }

// `text` with its one occurrence of `from` replaced by `to`.
std::string edit(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  EXPECT_EQ(text.find(from, at + 1), std::string::npos) << "ambiguous edit: " << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

Scenario parse(const std::string& text) { return parse_scenario(text, "t.toml"); }

using skred::test::error_of;

}  // namespace

TEST(ImplicitScenario, DefaultsAreExplicitPlaneStrainWithoutPressures) {
  const Scenario s = parse(explicit_text());
  EXPECT_EQ(s.integrator, IntegratorKind::Explicit);
  ASSERT_EQ(s.stages.size(), 1u);
  EXPECT_EQ(s.stages[0].integrator, IntegratorKind::Explicit);
  EXPECT_FALSE(s.any_implicit());
  EXPECT_EQ(s.geometry, Geometry::PlaneStrain);
  EXPECT_TRUE(s.pressures.empty());
  // [implicit]'s defaults are the schema's (docs/scenario.md) and ImplicitSettings'.
  const ImplicitSettings d;
  const schema::Section& sec = schema::section("implicit");
  EXPECT_EQ(sec.at("time_step").def.value, d.time_step);
  EXPECT_EQ(sec.at("load_steps").def.value, d.load_steps);
  EXPECT_EQ(sec.at("residual_tolerance").def.value, d.residual_tolerance);
  EXPECT_EQ(sec.at("displacement_tolerance").def.value, d.displacement_tolerance);
  EXPECT_EQ(sec.at("max_iterations").def.value, d.max_iterations);
  EXPECT_EQ(sec.at("max_cuts").def.value, d.max_cuts);
  EXPECT_EQ(std::string(sec.at("analysis").def.text), std::string("\"") + to_string(d.analysis) + "\"");
  EXPECT_EQ(std::string(sec.at("iteration").def.text), std::string("\"") + to_string(d.iteration) + "\"");
  EXPECT_EQ(std::string(sec.at("linear_solver").def.text),
            std::string("\"") + to_string(d.linear_solver) + "\"");
  EXPECT_EQ(std::string(sec.at("line_search").def.text), d.line_search ? "true" : "false");
  // An implicit file without [implicit] gets them.
  const Scenario i = parse(implicit_text());
  EXPECT_EQ(i.integrator, IntegratorKind::Implicit);
  ASSERT_EQ(i.stages.size(), 1u);
  EXPECT_EQ(i.stages[0].integrator, IntegratorKind::Implicit);
  EXPECT_TRUE(i.any_implicit());
  EXPECT_EQ(i.stages[0].implicit.analysis, d.analysis);
  EXPECT_EQ(i.stages[0].implicit.load_steps, d.load_steps);
  EXPECT_EQ(i.stages[0].implicit.residual_tolerance, d.residual_tolerance);
  EXPECT_EQ(i.stages[0].implicit.linear_solver, d.linear_solver);
  EXPECT_EQ(i.stages[0].implicit.petsc_options, "");
}

TEST(ImplicitScenario, EveryImplicitKeyIsParsed) {
  const Scenario s = parse(implicit_text(R"(
[implicit]
analysis = "dynamic"
time_step = 0.01
iteration = "elastic"
residual_tolerance = 1e-6
displacement_tolerance = 1e-7
max_iterations = 40
line_search = false
max_cuts = 3
linear_solver = "iterative"
petsc_options = "-ksp_type gmres -pc_type gamg"
)"));
  for (const ImplicitSettings* im : {&s.implicit, &s.stages[0].implicit}) {
    EXPECT_EQ(im->analysis, ImplicitAnalysis::Dynamic);
    EXPECT_EQ(im->time_step, 0.01);
    EXPECT_EQ(im->load_steps, 1);
    EXPECT_EQ(im->iteration, ImplicitIteration::Elastic);
    EXPECT_EQ(im->residual_tolerance, 1e-6);
    EXPECT_EQ(im->displacement_tolerance, 1e-7);
    EXPECT_EQ(im->max_iterations, 40);
    EXPECT_FALSE(im->line_search);
    EXPECT_EQ(im->max_cuts, 3);
    EXPECT_EQ(im->linear_solver, LinearSolverKind::Iterative);
    EXPECT_EQ(im->petsc_options, "-ksp_type gmres -pc_type gamg");
  }
  const Scenario q = parse(implicit_text("[implicit]\nload_steps = 20\n"));
  EXPECT_EQ(q.stages[0].implicit.analysis, ImplicitAnalysis::QuasiStatic);
  EXPECT_EQ(q.stages[0].implicit.load_steps, 20);
}

TEST(ImplicitScenario, StagesTakeTheSolversIntegratorAndOverrideImplicitKeys) {
  const Scenario s = parse(staged_text(R"(
[solver]
integrator = "implicit"

[implicit]
load_steps = 10
max_iterations = 30

[[stage]]
name = "gravity"
duration = 1.0

[[stage]]
name = "load"
duration = 2.0

[stage.implicit]
analysis = "dynamic"
time_step = 0.05
linear_solver = "iterative"

[[stage]]
name = "more"
duration = 1.0
implicit = { load_steps = 4, iteration = "elastic" }
)"));
  ASSERT_EQ(s.stages.size(), 3u);
  for (const Stage& st : s.stages) {
    EXPECT_EQ(st.integrator, IntegratorKind::Implicit) << st.name;
    EXPECT_EQ(st.implicit.max_iterations, 30) << st.name;  // [implicit]'s, never overridden
  }
  EXPECT_EQ(s.stages[0].implicit.analysis, ImplicitAnalysis::QuasiStatic);
  EXPECT_EQ(s.stages[0].implicit.load_steps, 10);
  EXPECT_EQ(s.stages[0].implicit.linear_solver, LinearSolverKind::Direct);
  EXPECT_EQ(s.stages[1].implicit.analysis, ImplicitAnalysis::Dynamic);
  EXPECT_EQ(s.stages[1].implicit.time_step, 0.05);
  EXPECT_EQ(s.stages[1].implicit.linear_solver, LinearSolverKind::Iterative);
  EXPECT_EQ(s.stages[2].implicit.load_steps, 4);
  EXPECT_EQ(s.stages[2].implicit.iteration, ImplicitIteration::Elastic);
  EXPECT_EQ(s.stages[2].implicit.linear_solver, LinearSolverKind::Direct);
  EXPECT_EQ(s.implicit.load_steps, 10);  // the common settings are not changed by a stage

  // A stage sets its own integrator: an explicit equilibrium stage, then an implicit one.
  const Scenario m = parse(staged_text(R"(
[[stage]]
duration = 1.0

[[stage]]
duration = 1.0
integrator = "implicit"
)"));
  EXPECT_EQ(m.integrator, IntegratorKind::Explicit);
  EXPECT_EQ(m.stages[0].integrator, IntegratorKind::Explicit);
  EXPECT_EQ(m.stages[1].integrator, IntegratorKind::Implicit);
  EXPECT_TRUE(m.any_implicit());
}

TEST(ImplicitScenario, PrescribedVelocitiesAreParsed) {
  const Scenario s = parse(implicit_text(R"(
[[prescribed_velocity]]
min = [0, 1]
max = [0.5, 1]
velocity = [0, -0.01]

[[prescribed_velocity]]
name = "plate"
min = [1.0, 0.0]
max = [1.0, 1.0]
velocity = [0.002, 0]
components = "x"
)"));
  ASSERT_EQ(s.prescribed.size(), 2u);
  EXPECT_EQ(s.prescribed[0].name, "prescribed0");
  EXPECT_EQ(s.prescribed[0].components, 0b11);  // "all"
  EXPECT_EQ(s.prescribed[0].velocity[1], -0.01);
  EXPECT_EQ(s.prescribed[0].max[0], 0.5);
  EXPECT_EQ(s.prescribed[1].name, "plate");
  EXPECT_EQ(s.prescribed[1].components, 0b01);
  EXPECT_NE(
      describe(s).find("prescribed velocity \"plate\": the nodes in [1, 0] to [1, 1] driven at [0.002, 0] "
                       "m/s (x held)"),
      std::string::npos)
      << describe(s);
}

TEST(ImplicitScenario, PressuresAreParsed) {
  const Scenario s = parse(implicit_text(R"(
[[pressure]]
body = "block"
side = "x_max"
value = 1e5
ramp_time = 0.5

[[pressure]]
body = "block"
side = "y_max"
value = -2000
)"));
  ASSERT_EQ(s.pressures.size(), 2u);
  EXPECT_EQ(s.pressures[0].body, 0);
  EXPECT_EQ(s.pressures[0].side, 1);  // 2 axis + 1 for _max
  EXPECT_EQ(s.pressures[0].pressure, 1e5);
  EXPECT_EQ(s.pressures[0].ramp_time, 0.5);
  EXPECT_EQ(s.pressures[1].side, 3);
  EXPECT_EQ(s.pressures[1].pressure, -2000.0);
  EXPECT_EQ(s.pressures[1].ramp_time, 0.0);
  // In 3D the z faces too.
  const std::string three = R"(
[grid]
size = [2.0, 2.0, 2.0]
cell_size = 0.5
[[material]]
name = "sand"
model = "linear-elastic"
density = 2000.0
young = 1e7
poisson = 0.3
[[body]]
name = "cube"
material = "sand"
shape = "box"
min = [0.0, 0.0, 0.0]
max = [1.0, 1.0, 1.0]
[solver]
end_time = 1.0
integrator = "implicit"
[[pressure]]
body = "cube"
side = "z_min"
value = 10
)";
  const AnyScenario a = parse_any_scenario(three, "t.toml");
  ASSERT_TRUE(std::holds_alternative<Scenario3>(a));
  ASSERT_EQ(std::get<Scenario3>(a).pressures.size(), 1u);
  EXPECT_EQ(std::get<Scenario3>(a).pressures[0].side, 4);
}

// Each defect gives an error naming its key (and where it is: "t.toml:LINE:").
TEST(ImplicitScenario, EveryErrorNamesItsKey) {
  const std::string axisymmetric =
      edit(std::string(kHead), "cell_size = 0.5", "cell_size = 0.5\ngeometry = \"axisymmetric\"");
  const std::string dilating = edit(std::string(kHead), "model = \"linear-elastic\"",
                                    "model = \"mohr-coulomb\"\nfriction = 30\ncohesion = "
                                    "0\ninitial_void_ratio = 0.6\nmax_void_ratio = 0.9");
  struct Case {
    const char* name;
    std::string text;
    std::string key;
  };
  const std::vector<Case> cases = {
      {"unknown integrator", explicit_text("integrator = \"semi\"\n"), "solver.integrator"},
      {"unknown stage integrator", staged_text("[[stage]]\nduration = 1.0\nintegrator = \"fast\"\n"),
       "stage[0].integrator"},
      {"unknown analysis", implicit_text("[implicit]\nanalysis = \"static\"\n"), "implicit.analysis"},
      {"negative time step", implicit_text("[implicit]\nanalysis = \"dynamic\"\ntime_step = -1\n"),
       "implicit.time_step"},
      {"zero load steps", implicit_text("[implicit]\nload_steps = 0\n"), "implicit.load_steps"},
      {"too many load steps", implicit_text("[implicit]\nload_steps = 2000000\n"), "implicit.load_steps"},
      {"fractional load steps", implicit_text("[implicit]\nload_steps = 2.5\n"), "implicit.load_steps"},
      {"unknown iteration", implicit_text("[implicit]\niteration = \"picard\"\n"), "implicit.iteration"},
      {"residual tolerance 1", implicit_text("[implicit]\nresidual_tolerance = 1\n"),
       "implicit.residual_tolerance"},
      {"residual tolerance 0", implicit_text("[implicit]\nresidual_tolerance = 0\n"),
       "implicit.residual_tolerance"},
      {"displacement tolerance 0", implicit_text("[implicit]\ndisplacement_tolerance = 0.0\n"),
       "implicit.displacement_tolerance"},
      {"max_iterations 0", implicit_text("[implicit]\nmax_iterations = 0\n"), "implicit.max_iterations"},
      {"max_iterations 1001", implicit_text("[implicit]\nmax_iterations = 1001\n"),
       "implicit.max_iterations"},
      {"max_cuts 31", implicit_text("[implicit]\nmax_cuts = 31\n"), "implicit.max_cuts"},
      {"line_search a number", implicit_text("[implicit]\nline_search = 1\n"), "implicit.line_search"},
      {"unknown linear solver", implicit_text("[implicit]\nlinear_solver = \"lu\"\n"),
       "implicit.linear_solver"},
      {"petsc_options a number", implicit_text("[implicit]\npetsc_options = 3\n"), "implicit.petsc_options"},
      {"unknown implicit key", implicit_text("[implicit]\ntolerance = 1e-6\n"), "implicit.tolerance"},
      {"[implicit] with only explicit stages", explicit_text("[implicit]\nload_steps = 2\n"), "implicit"},
      {"[stage.implicit] on an explicit stage",
       staged_text("[solver]\nintegrator = \"implicit\"\n[[stage]]\nduration = 1.0\n[[stage]]\nduration = "
                   "1.0\nintegrator = \"explicit\"\n[stage.implicit]\nload_steps = 2\n"),
       "stage[1].implicit"},
      {"bad key in [stage.implicit]",
       staged_text(
           "[solver]\nintegrator = \"implicit\"\n[[stage]]\nduration = 1.0\n[stage.implicit]\nmax_cuts "
           "= -1\n"),
       "stage[0].implicit.max_cuts"},
      {"unknown key in [stage.implicit]",
       staged_text(
           "[solver]\nintegrator = \"implicit\"\n[[stage]]\nduration = 1.0\n[stage.implicit]\nsteps = "
           "2\n"),
       "stage[0].implicit.steps"},
      {"time_step of a quasi-static analysis", implicit_text("[implicit]\ntime_step = 0.1\n"),
       "implicit.time_step"},
      {"load_steps of a dynamic stage",
       staged_text(
           "[solver]\nintegrator = \"implicit\"\n[implicit]\nanalysis = \"dynamic\"\n[[stage]]\nduration "
           "= 1.0\n[stage.implicit]\nload_steps = 5\n"),
       "stage[0].implicit.load_steps"},
      {"a dynamic stage of 1e12 steps",
       implicit_text("[implicit]\nanalysis = \"dynamic\"\ntime_step = 1e-12\n"), "implicit.time_step"},
      {"solver.time_step with every stage implicit", implicit_text("time_step = 1e-4\n"), "solver.time_step"},
      {"unknown geometry",
       edit(explicit_text(), "cell_size = 0.5", "cell_size = 0.5\ngeometry = \"spherical\""),
       "grid.geometry"},
      {"axisymmetric grid at x < 0",
       edit(axisymmetric, "origin = [0, 0]", "origin = [-1, 0]") +
           "[solver]\nend_time = 1.0\nintegrator = \"implicit\"\n",
       "grid.origin"},
      {"axisymmetric axis held fixed",
       edit(axisymmetric, "x_min = \"roller\"", "x_min = \"fixed\"") + "[solver]\nend_time = 1.0\n",
       "boundary.x_min"},
      {"axisymmetric with splitting",
       edit(axisymmetric, "shape = \"rectangle\"", "split = true\nshape = \"rectangle\"") +
           "[solver]\nend_time = 1.0\n",
       "body[0].split"},
      {"axisymmetric with cell-centre shear",
       axisymmetric + "[solver]\nend_time = 1.0\nscheme = \"usf\"\nshear_strain = \"cell-centre\"\n",
       "solver.shear_strain"},
      {"geometry in 3D",
       "[grid]\nsize = [2.0, 2.0, 2.0]\ncell_size = 0.5\ngeometry = \"plane-strain\"\n[[material]]\nname = "
       "\"s\"\nmodel = \"linear-elastic\"\ndensity = 2000.0\nyoung = 1e7\npoisson = 0.3\n[[body]]\nmaterial "
       "= "
       "\"s\"\nshape = \"box\"\nmin = [0, 0, 0]\nmax = [1, 1, 1]\n[solver]\nend_time = 1.0\n",
       "grid.geometry"},
      {"prescribed velocity with the explicit integrator",
       explicit_text("[[prescribed_velocity]]\nmin = [0, 1]\nmax = [0.5, 1]\nvelocity = [0, -1]\n"),
       "prescribed_velocity"},
      {"prescribed velocity with the B-spline",
       implicit_text("interpolation = \"bspline\"\n[[prescribed_velocity]]\nmin = [0, 1]\nmax = [0.5, "
                     "1]\nvelocity = [0, -1]\n"),
       "prescribed_velocity"},
      {"prescribed velocity between nodes",
       implicit_text("[[prescribed_velocity]]\nmin = [0, 1.1]\nmax = [0.5, 1.2]\nvelocity = [0, -1]\n"),
       "prescribed_velocity[0].min"},
      {"prescribed velocity outside the grid",
       implicit_text("[[prescribed_velocity]]\nmin = [0, 3]\nmax = [0.5, 4]\nvelocity = [0, -1]\n"),
       "prescribed_velocity[0].min"},
      {"prescribed velocity box upside down",
       implicit_text("[[prescribed_velocity]]\nmin = [0, 1]\nmax = [0.5, 0.5]\nvelocity = [0, -1]\n"),
       "prescribed_velocity[0].max"},
      {"prescribed velocity without velocity",
       implicit_text("[[prescribed_velocity]]\nmin = [0, 1]\nmax = [0.5, 1]\n"),
       "prescribed_velocity[0].velocity"},
      {"prescribed velocity of z in 2D",
       implicit_text(
           "[[prescribed_velocity]]\nmin = [0, 1]\nmax = [0.5, 1]\nvelocity = [0, -1]\ncomponents = "
           "\"z\"\n"),
       "prescribed_velocity[0].components"},
      {"prescribed velocities of one name",
       implicit_text(
           "[[prescribed_velocity]]\nname = \"f\"\nmin = [0, 1]\nmax = [0.5, 1]\nvelocity = [0, "
           "-1]\n[[prescribed_velocity]]\nname = \"f\"\nmin = [1, 1]\nmax = [1.5, 1]\nvelocity = [0, "
           "-1]\n"),
       "prescribed_velocity[1].name"},
      {"prescribed velocity name with a comma",
       implicit_text("[[prescribed_velocity]]\nname = \"a,b\"\nmin = [0, 1]\nmax = [0.5, 1]\nvelocity = [0, "
                     "-1]\n"),
       "prescribed_velocity[0].name"},
      {"pressure with the explicit integrator",
       explicit_text("[[pressure]]\nbody = \"block\"\nside = \"x_max\"\nvalue = 1e5\n"), "pressure"},
      {"pressure on an unknown body",
       implicit_text("[[pressure]]\nbody = \"tube\"\nside = \"x_max\"\nvalue = 1\n"), "pressure[0].body"},
      {"pressure without a body", implicit_text("[[pressure]]\nside = \"x_max\"\nvalue = 1\n"),
       "pressure[0].body"},
      {"pressure on a z face in 2D",
       implicit_text("[[pressure]]\nbody = \"block\"\nside = \"z_min\"\nvalue = 1\n"), "pressure[0].side"},
      {"pressure on an unknown side",
       implicit_text("[[pressure]]\nbody = \"block\"\nside = \"left\"\nvalue = 1\n"), "pressure[0].side"},
      {"pressure without a value", implicit_text("[[pressure]]\nbody = \"block\"\nside = \"x_max\"\n"),
       "pressure[0].value"},
      {"pressure not finite",
       implicit_text("[[pressure]]\nbody = \"block\"\nside = \"x_max\"\nvalue = inf\n"), "pressure[0].value"},
      {"negative pressure ramp",
       implicit_text("[[pressure]]\nbody = \"block\"\nside = \"x_max\"\nvalue = 1\nramp_time = -1\n"),
       "pressure[0].ramp_time"},
      {"unknown pressure key",
       implicit_text("[[pressure]]\nbody = \"block\"\nside = \"x_max\"\nvalue = 1\nface = 2\n"),
       "pressure[0].face"},
      {"two pressures on one face",
       implicit_text("[[pressure]]\nbody = \"block\"\nside = \"x_max\"\nvalue = 1\n[[pressure]]\nbody = "
                     "\"block\"\nside = \"x_max\"\nvalue = 2\n"),
       "pressure[1].side"},
      {"contact with the implicit integrator",
       implicit_text(
           "[[body]]\nname = \"top\"\nmaterial = \"sand\"\nshape = \"rectangle\"\nmin = [0.0, 1.0]\nmax "
           "= [1.0, 1.5]\n[[contact]]\nbodies = [\"block\", \"top\"]\nfriction = 0.3\n"),
       "contact"},
      {"rigid body with the implicit integrator",
       implicit_text(
           "[[body]]\nname = \"plate\"\nmaterial = \"sand\"\nrigid = true\nshape = \"rectangle\"\nmin = "
           "[0.0, 1.0]\nmax = [1.0, 1.5]\n"),
       "body[1].rigid"},
      {"frictional wall with the implicit integrator",
       edit(std::string(kHead), "y_min = \"fixed\"", "y_min = { type = \"friction\", friction = 0.5 }") +
           "[solver]\nend_time = 1.0\nintegrator = \"implicit\"\n",
       "boundary.y_min"},
      {"splitting with the implicit integrator",
       edit(std::string(kHead), "shape = \"rectangle\"", "split = true\nshape = \"rectangle\"") +
           "[solver]\nend_time = 1.0\nintegrator = \"implicit\"\n",
       "body[0].split"},
      {"dilated continuum with the implicit integrator",
       edit(dilating, "shape = \"rectangle\"", "dilation_continuum = true\nshape = \"rectangle\"") +
           "[solver]\nend_time = 1.0\nintegrator = \"implicit\"\n",
       "body[0].dilation_continuum"},
      {"local damping on an implicit stage",
       staged_text("[[stage]]\nduration = 1.0\nlocal_damping = 0.5\n[[stage]]\nduration = 1.0\nintegrator = "
                   "\"implicit\"\nlocal_damping = 0.5\n"),
       "stage[1].local_damping"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const std::string e = error_of(c.text);
    ASSERT_NE(e, "") << c.text;
    EXPECT_EQ(e.rfind("t.toml:", 0), 0u) << e;
    EXPECT_NE(e.find("key '" + c.key + "':"), std::string::npos) << e;
  }
  // The messages say why.
  const auto message = [&](const std::string& name) {
    for (const Case& c : cases)
      if (c.name == name) return error_of(c.text);
    ADD_FAILURE() << "no case " << name;
    return std::string();
  };
  EXPECT_NE(message("[implicit] with only explicit stages").find("no stage runs the implicit integrator"),
            std::string::npos);
  EXPECT_NE(message("[stage.implicit] on an explicit stage")
                .find("runs the explicit integrator; set integrator = \"implicit\""),
            std::string::npos);
  EXPECT_NE(message("axisymmetric axis held fixed").find("the axis r = 0, a symmetry line"),
            std::string::npos);
  EXPECT_NE(message("axisymmetric with splitting").find("not available in axisymmetric geometry"),
            std::string::npos);
  EXPECT_NE(message("pressure with the explicit integrator")
                .find("pressures are applied by the implicit integrator only"),
            std::string::npos);
  for (const char* name :
       {"contact with the implicit integrator", "rigid body with the implicit integrator",
        "frictional wall with the implicit integrator", "splitting with the implicit integrator",
        "dilated continuum with the implicit integrator", "local damping on an implicit stage"})
    EXPECT_NE(message(name).find("is not available with integrator = \"implicit\""), std::string::npos)
        << name << ": " << message(name);
  // The same scenarios are valid with the explicit integrator (but for the pressure).
  EXPECT_EQ(error_of(edit(std::string(kHead), "y_min = \"fixed\"",
                          "y_min = { type = \"friction\", friction = 0.5 }") +
                     "[solver]\nend_time = 1.0\n"),
            "");
  EXPECT_EQ(error_of(staged_text("[[stage]]\nduration = 1.0\nlocal_damping = 0.5\n")), "");
}

// Axisymmetric: each point's mass and volume are per radian, the plane-strain ones times its
// radius x_p (measured from x = 0, not from the grid's origin).
TEST(ImplicitScenario, AxisymmetricPointsWeighTheirRadius) {
  std::string plane = implicit_text();
  plane = edit(plane, "origin = [0, 0]", "origin = [0.5, 0]");
  plane = edit(plane, "min = [0.0, 0.0]", "min = [1.0, 0.0]");
  plane = edit(plane, "max = [1.0, 1.0]", "max = [2.5, 1.0]");
  std::string axi = plane;
  axi = edit(axi, "cell_size = 0.5", "cell_size = 0.5\ngeometry = \"axisymmetric\"");
  const Scenario sp = parse(plane), sa = parse(axi);
  EXPECT_EQ(sp.geometry, Geometry::PlaneStrain);
  EXPECT_EQ(sa.geometry, Geometry::Axisymmetric);
  const Particles<2> pp = build_particles(sp), pa = build_particles(sa);
  ASSERT_EQ(pp.size(), pa.size());
  ASSERT_EQ(pp.size(), 24u);  // 3 x 2 cells of 2 x 2 points
  const double area = 0.25 * 0.25, rho = 2000.0;
  for (std::size_t p = 0; p < pa.size(); ++p) {
    EXPECT_EQ(pa.x[p], pp.x[p]);
    EXPECT_NEAR(pa.mass[p] / pp.mass[p], pa.x[p][0], 1e-12);
    EXPECT_NEAR(pa.volume0[p] / pp.volume0[p], pa.x[p][0], 1e-12);
    EXPECT_NEAR(pa.mass[p], rho * area * pa.x[p][0], 1e-9);
    EXPECT_NEAR(pp.mass[p], rho * area, 1e-12);
  }
  // K0 initial stress is that of plane strain: the weight per radian over the radius.
  for (std::string* text : {&plane, &axi})
    *text = edit(*text, "[solver]", "[initial_stress]\nk0 = 0.5\n[solver]");
  const Scenario ip = parse(plane), ia = parse(axi);
  Particles<2> qp = build_particles(ip), qa = build_particles(ia);
  apply_initial_stress(ip, qp);
  apply_initial_stress(ia, qa);
  for (std::size_t p = 0; p < qa.size(); ++p)
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(qa.stress[p][c], qp.stress[p][c], 1e-9 * std::abs(qp.stress[p][1]));
  EXPECT_LT(qa.stress[0][1], 0.0);
  // `skred check` says so.
  EXPECT_NE(describe(sa).find("geometry: axisymmetric"), std::string::npos) << describe(sa);
  EXPECT_EQ(describe(sp).find("geometry: axisymmetric"), std::string::npos);
}

TEST(ImplicitScenario, CheckSaysEachStagesIntegratorAndTheSystemsSize) {
  const Scenario s = parse(staged_text(R"(
[implicit]
load_steps = 10

[[stage]]
name = "settle"
duration = 1.0

[[stage]]
name = "quake"
duration = 2.0
integrator = "implicit"
[stage.implicit]
analysis = "dynamic"
time_step = 0.01

[[stage]]
name = "static"
duration = 1.0
integrator = "implicit"
implicit = { iteration = "elastic", linear_solver = "iterative" }

[[stage]]
name = "auto"
duration = 1.0
integrator = "implicit"
implicit = { analysis = "dynamic" }
)"));
  const std::string d = describe(s);
  for (const std::string& part :
       {std::string("settle: 1 s, explicit integrator"),
        std::string(
            "quake: 2 s, implicit integrator (dynamic, time step 0.01 s, newton iteration, direct linear "
            "solver)"),
        std::string(
            "static: 1 s, implicit integrator (quasi-static in 10 load steps, elastic iteration, iterative "
            "linear solver)"),
        fmt::format(
            "auto: 1 s, implicit integrator (dynamic, time step {:.4g} s (10 x the stable explicit step)",
            10 * stable_time_step(s)),
        // The 1 x 1 m block covers 2 x 2 cells: 3 x 3 nodes, 18 unknowns; MUMPS' fit
        // 230 B x 18 log2 18 = 17.3 kB.
        std::string("implicit system: about 18 unknowns"),
        std::string(
            "direct solver: about 17.3 kB for the factorisation (an estimate: MUMPS' measured 230 B x "
            "N log2 N")})
    EXPECT_NE(d.find(part), std::string::npos) << part << " missing in:\n" << d;
  EXPECT_EQ(parse(explicit_text()).stages.size(), 1u);
  EXPECT_EQ(describe(parse(explicit_text())).find("implicit system"), std::string::npos);

  // Pressures (every stage implicit).
  const std::string p = describe(parse(implicit_text(R"(
[implicit]
linear_solver = "iterative"
[[pressure]]
body = "block"
side = "y_max"
value = 5e4
ramp_time = 0.5
)")));
  EXPECT_NE(p.find("pressure: 50000 Pa on the y_max face of body block, ramped over 0.5 s"),
            std::string::npos)
      << p;
  EXPECT_NE(p.find("implicit system"), std::string::npos) << p;
  EXPECT_EQ(p.find("direct solver"), std::string::npos) << p;  // no stage factorises
}

// The system's size: the union of the bodies' node boxes, and its direct solver's memory.
TEST(ImplicitScenario, SystemEstimateCountsTheNodesOfTheBodiesBoundingBoxesOnce) {
  // Two 1 x 1 m blocks side by side share a column of nodes: 3 x 3 + 3 x 3 - 3 = 15 nodes.
  const Scenario s =
      parse(implicit_text("[[body]]\nname = \"next\"\nmaterial = \"sand\"\nshape = \"rectangle\"\nmin = "
                          "[1.0, 0.0]\nmax = [2.0, 1.0]\n"));
  const ImplicitSystemSize z = estimate_implicit_system(s);
  EXPECT_EQ(z.nodes, 15.0);
  EXPECT_EQ(z.unknowns, 30.0);
  EXPECT_EQ(z.row_nodes, 5.0);
  EXPECT_EQ(z.bandwidth, 20.0);
  EXPECT_NEAR(z.direct_bytes, 230.0 * 30.0 * std::log2(30.0), 1e-9);
  // 3D: a 1 m cube on 0.5 m cells, 27 nodes, 81 unknowns; MUMPS' fit 1000 B x 81^(4/3).
  const AnyScenario a = parse_any_scenario(R"(
[grid]
size = [2.0, 2.0, 2.0]
cell_size = 0.5
[[material]]
name = "sand"
model = "linear-elastic"
density = 2000.0
young = 1e7
poisson = 0.3
[[body]]
material = "sand"
shape = "box"
min = [0.0, 0.0, 0.0]
max = [1.0, 1.0, 1.0]
[solver]
end_time = 1.0
integrator = "implicit"
)",
                                           "t.toml");
  const ImplicitSystemSize z3 = estimate_implicit_system(std::get<Scenario3>(a));
  EXPECT_EQ(z3.nodes, 27.0);
  EXPECT_EQ(z3.unknowns, 81.0);
  EXPECT_NEAR(z3.direct_bytes, 1000.0 * std::pow(81.0, 4.0 / 3.0), 1e-6);
  EXPECT_NE(describe(std::get<Scenario3>(a)).find("N^(4/3)"), std::string::npos);
}
