// The rest test on the speed the material moves with (Stage::rest_measure,
// ExplicitSolver::material_mean_speed; docs/method.md, "The rest test"). A FLIP point's v_p
// carries velocities the grid cannot see (FLIP's null space); the point moves with
// sum_i N_ip v_i (Thesis eq. 2.55), so a deposit can stand still while eq. 5.12's mean speed of
// the points does not fall.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "run/simulation.hpp"
#include "scenario/build.hpp"
#include "scenario/scenario.hpp"
#include "support.hpp"
#include "temp_dir.hpp"

namespace fs = std::filesystem;
using namespace skred;
using namespace skred::test;

namespace {

struct ColumnRun {
  RunResult result;
  std::vector<std::map<std::string, double>> series;
};

std::string read(const fs::path& f) {
  std::ifstream in(f, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// examples/soil_column.toml (h = 0.5 m, 1800 points) under pure FLIP, its stage's rest test on
// `measure` ("" leaves the key out: "auto").
std::string flip_column_text(const std::string& measure) {
  std::string text =
      with_transfer(read_scenario_text(std::string(SKRED_SOURCE_DIR) + "/examples/soil_column.toml"),
                    "velocity_transfer = \"flip\"");
  const std::string rest = "rest_speed = 0.005\n";
  const auto at = text.find(rest);
  if (at == std::string::npos) throw std::runtime_error("the example's rest_speed line is not in it");
  if (!measure.empty()) text.insert(at + rest.size(), "rest_measure = \"" + measure + "\"\n");
  return text;
}

ColumnRun flip_column(const std::string& measure) {
  const std::string text = flip_column_text(measure);
  const fs::path out = fresh_temp_dir();
  RunOptions opt;
  opt.progress = false;
  opt.threads = 1;
  ColumnRun r{run_simulation(parse_scenario(text, "column.toml"), out, opt), {}};
  r.series = series_rows(out / "series.csv");
  fs::remove_all(out);
  return r;
}

}  // namespace

TEST(RestMeasure, MaterialSpeedOfAUniformTranslationIsItsSpeed) {
  // p_i = sum N_ip m_p v0 = m_i v0 at every node the block reaches, and sum_i N_ip = 1: every
  // kernel's material speed is |v0|, to round-off, as the points' own.
  for (Interpolation k : {Interpolation::Linear, Interpolation::Gimp, Interpolation::Bspline}) {
    Particles<2> P;
    const Vec<2> v0(0.3, -0.4);
    const Material m = elastic(1000.0, 1.0e4, 0.3);
    fill_rectangle(P, m, 0.1, 2, 0.6, 0.6, 1.4, 1.4, v0);
    SolverSettings<2> st;
    st.interpolation = k;
    st.dt = 1e-4;
    ExplicitSolver<2> solver(grid2(0.1, 20, 20), P, {m}, st, 2);
    EXPECT_NEAR(solver.material_mean_speed(), 0.5, 1e-14) << to_string(k);  // before any step
    ASSERT_TRUE(solver.step().ok);
    EXPECT_NEAR(solver.material_mean_speed(), 0.5, 1e-12) << to_string(k);
    EXPECT_NEAR(solver.totals().mean_speed, 0.5, 1e-12) << to_string(k);
  }
}

TEST(RestMeasure, FlipColumnRestsOnTheMaterialsSpeedWhereItsPointsNeverDo) {
  // The Thesis §5.1 column of examples/soil_column.toml under pure FLIP. On the points' own speed
  // (eq. 5.12) its stage runs its whole 6 s: the points keep a mean speed of about 0.05 m/s,
  // ten times the rest speed of 0.005 m/s. On the material's ("auto" under FLIP) it ends at rest.
  const ColumnRun points = flip_column("points");
  const ColumnRun material = flip_column("");
  const ColumnRun moved = flip_column("displacement");
  ASSERT_TRUE(points.result.completed && material.result.completed);
  const StageMeasures& p = points.result.stages.back();
  const StageMeasures& m = material.result.stages.back();
  EXPECT_EQ(p.rest_measure, "points");
  EXPECT_EQ(m.rest_measure, "material");
  EXPECT_EQ(p.ended_by, "duration");
  EXPECT_EQ(m.ended_by, "rest");
  EXPECT_GT(p.final_mean_speed, 5 * 0.005);  // the points still carry their null-space speed
  ASSERT_FALSE(points.series.back().contains("material_speed"));  // a column only where it is read
  const auto& last = material.series.back();
  std::printf(
      "FLIP column: on the points' speed %s at %.2f s, runout %.4f m, mean speed %.4f m/s; on the "
      "material's %s at %.2f s, runout %.4f m, points' speed %.4f m/s, material's %.5f m/s\n",
      p.ended_by.c_str(), p.end_time, p.runout, p.final_mean_speed, m.ended_by.c_str(), m.end_time, m.runout,
      last.at("mean_speed"), last.at("material_speed"));
  EXPECT_LT(last.at("material_speed"), 0.005);
  EXPECT_GT(last.at("mean_speed"), 5 * 0.005);
  // Computing the measure changes nothing: both runs' rows are the same to the bit up to the rest.
  ASSERT_LE(material.series.size(), points.series.size());
  for (std::size_t i = 0; i < material.series.size(); ++i)
    for (const char* key : {"kinetic_energy", "gravity_work", "runout", "mean_speed"})
      ASSERT_EQ(material.series[i].at(key), points.series[i].at(key)) << key << " at row " << i;
  // The deposit had stopped: over the 3.4 s the points' run goes on, its front moves by less
  // than material moving at the rest speed would, (6 s - the rest's end) x 0.005 m/s.
  const double on = p.end_time - m.end_time;
  EXPECT_GT(on, 2.0);
  EXPECT_LT(std::abs(p.runout - m.runout), 0.005 * on);
  // On the displacement over windows of rest_time (0.3 s) it rests too, at the end of the first
  // window in which the points moved on average slower than the rest speed; the rows up to then
  // are again the points' run's, and its front moves on as little.
  ASSERT_TRUE(moved.result.completed);
  const StageMeasures& d = moved.result.stages.back();
  std::printf("on the displacement: %s at %.2f s, runout %.4f m, stop time %.2f s\n", d.ended_by.c_str(),
              d.end_time, d.runout, d.stop_time.value_or(NAN));
  EXPECT_EQ(d.rest_measure, "displacement");
  EXPECT_EQ(d.ended_by, "rest");
  ASSERT_TRUE(d.stop_time.has_value());
  EXPECT_NEAR(d.end_time - (d.start_time + *d.stop_time), 0.3, 1e-6);  // the quiet window
  for (std::size_t i = 0; i < moved.series.size(); ++i)
    ASSERT_EQ(moved.series[i].at("runout"), points.series[i].at("runout")) << "row " << i;
  EXPECT_LT(std::abs(p.runout - d.runout), 0.005 * (p.end_time - d.end_time));
}

TEST(RestMeasure, ScenarioKeyAndWhatAutoPicks) {
  const std::string base = read_scenario_text(std::string(SKRED_SOURCE_DIR) + "/examples/soil_column.toml");
  const auto with = [&](const std::string& transfer, const std::string& measure = "") {
    std::string text = with_transfer(base, transfer);
    if (!measure.empty()) text.replace(text.find("rest_speed = "), 0, "rest_measure = " + measure + "\n");
    const Scenario s = parse_scenario(text, "column.toml");
    return std::string(to_string(rest_measure_of(s, s.stages.back())));
  };
  EXPECT_EQ(with("velocity_transfer = \"flip\""), "material");
  EXPECT_EQ(with("velocity_transfer = \"aflip\""), "material");
  EXPECT_EQ(with("velocity_transfer = \"flip\"\npic_fraction = 0.05"), "points");  // a PIC share damps it
  EXPECT_EQ(with("velocity_transfer = \"xpic\""), "points");
  EXPECT_EQ(with("velocity_transfer = \"apic\""), "points");
  EXPECT_EQ(with(""), "points");  // the slide's default, XPIC once per 2 h/c
  EXPECT_EQ(with("velocity_transfer = \"xpic\"", "\"material\""), "material");
  EXPECT_EQ(with("velocity_transfer = \"flip\"", "\"points\""), "points");
  EXPECT_EQ(with("velocity_transfer = \"apic\"", "\"displacement\""), "displacement");
  // skred check says which
  const auto check = [&](const std::string& transfer, const std::string& measure = "") {
    std::string text = with_transfer(base, transfer);
    if (!measure.empty()) text.replace(text.find("rest_speed = "), 0, "rest_measure = " + measure + "\n");
    return describe(parse_scenario(text, "column.toml"));
  };
  EXPECT_NE(check("velocity_transfer = \"flip\"").find("the material's mean speed stays below 0.005 m/s"),
            std::string::npos);
  EXPECT_NE(check("").find("the points' mean speed stays below 0.005 m/s"), std::string::npos);
  EXPECT_NE(check("", "\"displacement\"").find("the points move on average slower than 0.005 m/s over 0.3 s"),
            std::string::npos);
  try {
    (void)with("", "\"grid\"");
    ADD_FAILURE() << "rest_measure = \"grid\" was accepted";
  } catch (const ScenarioError& e) {
    EXPECT_NE(std::string(e.what()).find("rest_measure"), std::string::npos) << e.what();
  }
}

TEST(RestMeasure, ARestartInsideADisplacementWindowEndsTheStageAsTheUninterruptedRun) {
  // The window's start and the points' positions then (x_rest) are in the checkpoint: stopped at
  // step 2500, inside the window of 2.4-2.7 s that ends the stage, the restarted run ends where
  // the uninterrupted one does, with the same series to the bit.
  const Scenario s = parse_scenario(flip_column_text("displacement"), "column.toml");
  const fs::path dir = fresh_temp_dir();
  RunOptions opt;
  opt.progress = false;
  opt.threads = 1;
  opt.checkpoint_every = 1000000;  // only the final one
  const RunResult a = run_simulation(s, dir / "a", opt);
  ASSERT_TRUE(a.completed) << a.message;
  RunOptions stop = opt;
  stop.stop_at_step = 2500;
  ASSERT_TRUE(run_simulation(s, dir / "b", stop).interrupted);
  RunOptions again = opt;
  again.restart = dir / "b" / "checkpoint.skc";
  const RunResult c = run_simulation(s, dir / "b", again);
  ASSERT_TRUE(c.completed) << c.message;
  ASSERT_EQ(a.stages.back().ended_by, "rest");
  EXPECT_GT(a.steps, 2500);
  EXPECT_EQ(c.steps, a.steps);
  EXPECT_EQ(c.stages.back().ended_by, "rest");
  EXPECT_EQ(c.stages.back().stop_time, a.stages.back().stop_time);
  EXPECT_EQ(c.stages.back().runout, a.stages.back().runout);
  EXPECT_EQ(read(dir / "a" / "series.csv"), read(dir / "b" / "series.csv"));
  fs::remove_all(dir);
}

TEST(RestMeasure, ThreeDimensionalSlabRestsOnTheMaterialsSpeedAndOnItsDisplacement) {
  // The Mohr-Coulomb slab of Column3D (1152 points between roller z walls) under pure FLIP: its
  // points keep a mean speed near 0.1 m/s to the stage's 5 s, twenty times the rest speed; on
  // the material's speed and on the displacement the stage rests, and the front of the run that
  // goes on moves less than material at the rest speed would.
  const auto run = [](const std::string& measure) {
    const std::string text = R"(
[grid]
size = [7.5, 3.5, 0.5]
cell_size = 0.25
[[material]]
name = "soil"
model = "mohr-coulomb"
density = 1800.0
young = 10e6
poisson = 0.3
friction = 30.0
cohesion = 500.0
[[body]]
material = "soil"
particles_per_cell = 2
shape = "box"
min = [0.0, 0.0, 0.0]
max = [1.5, 3.0, 0.5]
[initial_stress]
k0 = "poisson"
[gravity]
acceleration = [0.0, -9.81, 0.0]
[boundary]
x_min = "roller"
x_max = "roller"
y_min = "fixed"
z_min = "roller"
z_max = "roller"
[solver]
scheme = "usf"
cfl = 0.4
velocity_transfer = "flip"
[[stage]]
name = "collapse"
duration = 5.0
rest_speed = 0.005
rest_time = 0.3
rest_measure = ")" + measure +
                             R"("
[output]
interval = 5.0
series_interval = 0.05
)";
    const fs::path out = fresh_temp_dir();
    RunOptions opt;
    opt.progress = false;
    opt.threads = 2;
    const RunResult r = run_simulation(std::get<Scenario3>(parse_any_scenario(text, "slab.toml")), out, opt);
    fs::remove_all(out);
    EXPECT_TRUE(r.completed) << measure << ": " << r.message;
    return r.stages.back();
  };
  const StageMeasures p = run("points"), m = run("material"), d = run("displacement");
  std::printf(
      "FLIP slab (3D): on the points' speed %s at %.2f s, runout %.4f m, mean speed %.3f m/s; on the "
      "material's %s at %.2f s, %.4f m; on the displacement %s at %.2f s, %.4f m\n",
      p.ended_by.c_str(), p.end_time, p.runout, p.final_mean_speed, m.ended_by.c_str(), m.end_time, m.runout,
      d.ended_by.c_str(), d.end_time, d.runout);
  EXPECT_EQ(p.ended_by, "duration");
  EXPECT_GT(p.final_mean_speed, 5 * 0.005);
  for (const StageMeasures* s : {&m, &d}) {
    EXPECT_EQ(s->ended_by, "rest") << s->rest_measure;
    EXPECT_LT(std::abs(p.runout - s->runout), 0.005 * (p.end_time - s->end_time)) << s->rest_measure;
  }
}
