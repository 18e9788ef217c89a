// Initial stress (K0, Thesis eq. 5.6-5.7, Post eq. 51), staged analysis and parameter sweeps,
// checked against closed forms: the overburden stress rho g d, and the strain energy of a
// column under its own weight, U = w rho^2 g^2 H^3 / (6 M).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "run/simulation.hpp"
#include "run/sweep.hpp"
#include "scenario/build.hpp"
#include "scenario/initial_stress.hpp"
#include "support.hpp"
#include "temp_dir.hpp"
#include "text_run.hpp"

namespace fs = std::filesystem;
using namespace skred;
using skred::test::last_series_row;

namespace {

// A column of width w and height H on a fixed base between rollers; `extra` is appended.
std::string column_text(const std::string& extra, double young = 1e6, double poisson = 0.0) {
  std::ostringstream t;
  t << R"(
[grid]
size = [0.02, 0.12]
cell_size = 0.005
[[material]]
name = "soil"
model = "linear-elastic"
density = 1800.0
young = )"
    << young << "\npoisson = " << poisson << R"(
[[body]]
name = "column"
material = "soil"
shape = "rectangle"
min = [0.0, 0.0]
max = [0.02, 0.1]
[gravity]
acceleration = [0.0, -9.81]
[boundary]
x_min = "roller"
x_max = "roller"
y_min = "fixed"
[solver]
cfl = 0.3
)" << extra;
  return t.str();
}

fs::path temp_dir(const std::string& name) { return skred::test::fresh_temp_dir(name); }

// One equilibrium stage: gravity over a 0.05 s ramp (three periods of the column), then held
// until the mean speed stays below 1e-4 m/s for 0.02 s, with local damping alpha (0: off).
std::string fmt_stage(double alpha) {
  std::ostringstream t;
  t << "[[stage]]\nname = \"equilibrium\"\nduration = 1.0\ngravity_ramp_time = 0.05\nelastic = true\n"
       "rest_speed = 1e-4\nrest_time = 0.02\nlocal_damping = "
    << alpha << "\n[output]\ninterval = 1.0\nseries_interval = 0.002\n";
  return t.str();
}

std::string read(const fs::path& f) {
  std::ifstream in(f);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace

TEST(InitialStress, K0FromOverburdenMatchesRhoGDepth) {
  for (const char* rule : {"\"poisson\"", "0.7"}) {
    const Scenario s = parse_scenario(
        column_text(std::string("end_time = 0.1\n[initial_stress]\nk0 = ") + rule + "\n", 1e6, 0.3),
        "k0.toml");
    Particles<2> P = build_particles(s);
    EXPECT_TRUE(P.Fe.empty());  // Fe and its reference stress only when the frames ask for them
    P.track_elastic_F();
    EXPECT_TRUE(P.stress_ref.empty());  // no reference stress stored until one is set
    EXPECT_EQ(P.reference_stress(0), PointStress<2>::Zero());
    apply_initial_stress(s, P);
    const double k0 = std::string(rule) == "0.7" ? 0.7 : 0.3 / 0.7;  // Thesis eq. 5.7
    for (std::size_t p = 0; p < P.size(); ++p) {
      const double depth = 0.1 - P.x[p][1];
      const double syy = -1800.0 * 9.81 * depth;  // Thesis eq. 5.6
      EXPECT_NEAR(P.stress[p][1], syy, 1e-9 * std::abs(syy)) << rule << " p " << p;
      EXPECT_NEAR(P.stress[p][0], k0 * syy, 1e-9 * std::abs(syy));
      EXPECT_NEAR(P.stress[p][2], k0 * syy, 1e-9 * std::abs(syy));
      EXPECT_EQ(P.stress[p][3], 0.0);
      EXPECT_EQ(P.reference_stress(p), P.stress[p]);  // Fe's reference state (Post eq. 77)
    }
    // A point added later (e.g. by splitting) starts from a zero reference stress.
    P.add(Vec<2>(0.01, 0.01), Vec<2>::Zero(), 1.0, 1e-4, Vec<2>(0.005, 0.005), 0, 0);
    ASSERT_EQ(P.stress_ref.size(), P.size());
    EXPECT_EQ(P.reference_stress(P.size() - 1), PointStress<2>::Zero());
  }
}

TEST(InitialStress, LayeredBodiesAndJakyRule) {
  // A heavy Mohr-Coulomb layer (phi = 30 deg) over a light elastic one; different point
  // spacings. Overburden: rho_top g t_top + rho_bottom g (d - t_top).
  const std::string text = R"(
[grid]
size = [1.0, 2.0]
cell_size = 0.1
[[material]]
name = "light"
model = "linear-elastic"
density = 1000.0
young = 1e7
poisson = 0.25
[[material]]
name = "sand"
model = "mohr-coulomb"
density = 2000.0
young = 1e7
poisson = 0.3
friction = 30.0
cohesion = 0.0
[[body]]
material = "light"
particles_per_cell = 2
shape = "rectangle"
min = [0.0, 0.0]
max = [1.0, 1.0]
[[body]]
material = "sand"
particles_per_cell = 4
shape = "rectangle"
min = [0.0, 1.0]
max = [1.0, 1.5]
[gravity]
acceleration = [0.0, -10.0]
[initial_stress]
k0 = "jaky"
[solver]
end_time = 0.1
)";
  const Scenario s = parse_scenario(text, "layers.toml");
  Particles<2> P = build_particles(s);
  apply_initial_stress(s, P);
  for (std::size_t p = 0; p < P.size(); ++p) {
    const double y = P.x[p][1];
    const double syy =
        y >= 1.0 ? -2000.0 * 10.0 * (1.5 - y) : -(2000.0 * 10.0 * 0.5 + 1000.0 * 10.0 * (1.0 - y));
    const double k0 = y >= 1.0 ? 1.0 - std::sin(M_PI / 6) : 0.25 / 0.75;  // Post eq. 51 / Thesis eq. 5.7
    EXPECT_NEAR(P.stress[p][1], syy, 1e-9 * std::abs(syy)) << "y = " << y;
    EXPECT_NEAR(P.stress[p][0], k0 * syy, 1e-9 * std::abs(syy)) << "y = " << y;
  }
}

TEST(Stages, MaterialsOfAStageApplyOverridesReductionAndElasticHold) {
  const std::string text = R"(
[grid]
size = [1.0, 1.0]
cell_size = 0.1
[[material]]
name = "sand"
model = "mohr-coulomb"
density = 2000.0
young = 1e7
poisson = 0.3
friction = 30.0
cohesion = 5000.0
dilation = 10.0
[[body]]
material = "sand"
shape = "rectangle"
min = [0.0, 0.0]
max = [1.0, 0.5]
[[stage]]
name = "equilibrium"
duration = 0.1
elastic = true
[[stage]]
name = "trigger"
duration = 0.2
[[stage.material]]
name = "sand"
cohesion = 0.0
[[stage]]
name = "srf"
duration = 0.1
strength_reduction = 1.5
)";
  const Scenario s = parse_scenario(text, "stages.toml");
  ASSERT_EQ(s.stages.size(), 3u);
  EXPECT_DOUBLE_EQ(s.end_time, 0.4);
  EXPECT_EQ(stage_materials(s, s.stages[0])[0].model, Model::LinearElastic);
  const Material trig = stage_materials(s, s.stages[1])[0];
  EXPECT_EQ(trig.model, Model::MohrCoulomb);
  EXPECT_EQ(trig.mohr_coulomb.cohesion, 0.0);
  EXPECT_DOUBLE_EQ(trig.mohr_coulomb.friction, M_PI / 6);
  const Material srf = stage_materials(s, s.stages[2])[0];
  EXPECT_NEAR(srf.mohr_coulomb.cohesion, 5000.0 / 1.5, 1e-9);
  EXPECT_NEAR(std::tan(srf.mohr_coulomb.friction), std::tan(M_PI / 6) / 1.5, 1e-12);
  EXPECT_NEAR(std::tan(srf.mohr_coulomb.dilation), std::tan(M_PI / 18) / 1.5, 1e-12);
}

TEST(Stages, GravityStageStoresTheClosedFormEnergyAndRestEndsTheNextStage) {
  // Stage 1 ramps gravity in (Thesis eq. 4.13); at equilibrium the stored strain energy is
  // U = w rho^2 g^2 H^3 / (6 E) (nu = 0) and, for a slow ramp, equals the work of gravity.
  // Stage 2 holds the column; its mean speed is already below the rest speed, so it ends by
  // the rest criterion after rest_time instead of running its full duration.
  const Scenario s = parse_scenario(column_text(R"(
[[stage]]
name = "gravity"
duration = 0.34
gravity_ramp_time = 0.34
[[stage]]
name = "hold"
duration = 1.0
rest_speed = 1e-4
rest_time = 0.02
[output]
interval = 0.1
)"),
                                    "staged.toml");
  const fs::path out = temp_dir("column");
  RunOptions opt;
  opt.progress = false;
  opt.threads = 1;
  const RunResult r = run_simulation(s, out, opt);
  ASSERT_TRUE(r.completed) << r.message;
  ASSERT_EQ(r.stages.size(), 2u);
  const double U = 0.02 * std::pow(1800.0 * 9.81, 2) * std::pow(0.1, 3) / (6 * 1e6);
  const StageMeasures& g = r.stages[0];
  std::printf("gravity stage: U = %.6g (exact %.6g), W_g = %.6g, final mean speed %.3g\n", g.strain_energy, U,
              g.gravity_work, g.final_mean_speed);
  EXPECT_NEAR(g.strain_energy, U, 0.01 * U);
  EXPECT_NEAR(g.gravity_work, g.strain_energy, 0.002 * U);
  EXPECT_EQ(g.ended_by, "duration");
  const StageMeasures& h = r.stages[1];
  EXPECT_EQ(h.ended_by, "rest");
  EXPECT_LT(h.end_time - h.start_time, 0.1);
  EXPECT_GE(h.end_time - h.start_time, 0.02);
  ASSERT_TRUE(h.stop_time.has_value());
  EXPECT_LT(std::abs(h.gravity_work), 0.01 * U);  // measured from the stage start
  EXPECT_NEAR(h.runout, 0.0, 1e-4);
  EXPECT_NEAR(h.height_end, 0.1 - 0.5 * 1800 * 9.81 * 0.01 / 1e6, 2e-5);  // settlement rho g H^2 / 2E
  const std::string summary = read(out / "summary.json");
  EXPECT_NE(summary.find("\"ended_by\": \"rest\""), std::string::npos);
  EXPECT_NE(read(out / "series.csv").find(",1,"), std::string::npos);  // stage column
  fs::remove_all(out);
}

TEST(Stages, ADensityTriggerLoadsTheColumnAsTheHeavierSoilWould) {
  // Paper III's rainfall trigger on the R2 column: after gravity is in, a stage makes the
  // soil 1.5 times heavier over 0.34 s. The masses follow exactly; the column settles to the
  // heavier soil's static answer, rho g H^2 / (2E) with rho = 2700, and stores
  // U = w rho^2 g^2 H^3 / (6E), 2.25 times the first stage's (nu = 0).
  const Scenario s = parse_scenario(column_text(R"(
[[stage]]
name = "gravity"
duration = 0.34
gravity_ramp_time = 0.34
[[stage]]
name = "rain"
duration = 0.45
[[stage.material]]
name = "soil"
density = 2700
density_ramp_time = 0.34
[output]
interval = 0.1
)"),
                                    "rain.toml");
  const fs::path out = temp_dir("rain");
  RunOptions opt;
  opt.progress = false;
  opt.threads = 1;
  const RunResult r = run_simulation(s, out, opt);
  ASSERT_TRUE(r.completed) << r.message;
  ASSERT_EQ(r.stages.size(), 2u);
  const auto U = [](double rho) { return 0.02 * std::pow(rho * 9.81, 2) * std::pow(0.1, 3) / (6 * 1e6); };
  const StageMeasures& rain = r.stages[1];
  const double stored = r.stages[0].strain_energy + rain.strain_energy;
  std::printf("rain stage: U = %.6g (exact %.6g), height %.7g (exact %.7g)\n", stored, U(2700),
              rain.height_end, 0.1 - 0.5 * 2700 * 9.81 * 0.01 / 1e6);
  EXPECT_NEAR(stored, U(2700), 0.03 * U(2700));
  EXPECT_NEAR(rain.height_end, 0.1 - 0.5 * 2700 * 9.81 * 0.01 / 1e6, 2e-5);
  EXPECT_NEAR(density_at_stage_start(s, 2, 0), 2700.0, 0.0);
  EXPECT_EQ(stage_materials(s, s.stages[1])[0].density, 2700.0);
  // A stable step for every density a stage reaches; a ramp longer than its stage refused.
  EXPECT_THROW(parse_scenario(column_text(R"(
[[stage]]
duration = 0.1
[[stage.material]]
name = "soil"
density = 2700
density_ramp_time = 0.2
)"),
                              "bad.toml"),
               ScenarioError);
  fs::remove_all(out);
}

namespace {

// Runs the scenario `text` on one thread into a scratch folder: the first stage's measures
// and the last series.csv row.
std::pair<StageMeasures, std::map<std::string, double>> run_stage(const std::string& text,
                                                                  const std::string& name) {
  const Scenario s = parse_scenario(text, name + ".toml");
  const fs::path out = temp_dir(name);
  RunOptions opt;
  opt.progress = false;
  opt.threads = 1;
  const RunResult r = run_simulation(s, out, opt);
  EXPECT_TRUE(r.completed) << r.message;
  auto row = last_series_row(out / "series.csv");
  fs::remove_all(out);
  return {r.stages.at(0), row};
}

}  // namespace

TEST(Stages, LocalDampingBringsAnEquilibriumStageToRestInFewerSteps) {
  // Cundall-type local damping (grid_update): gravity applied to the R2 column over a short
  // sine ramp (Thesis eq. 4.13) leaves it ringing at its period 4H/c_p; undamped, the averaged
  // scheme keeps that energy. The stage ends once the mean speed stays below rest_speed. With
  // damping it must end at rest sooner, at the static answer (settlement rho g H^2 / 2E,
  // stored energy U = w rho^2 g^2 H^3 / (6E), nu = 0), with the work of gravity accounted for:
  // W_g = KE + U + damping_work (series.csv) within 1 %.
  const auto run = [](double alpha, const std::string& name) {
    return run_stage(column_text(fmt_stage(alpha)), name);
  };
  const auto [undamped, row0] = run(0.0, "undamped");
  const auto [damped, row1] = run(0.7, "damped");
  const double U = 0.02 * std::pow(1800.0 * 9.81, 2) * std::pow(0.1, 3) / (6 * 1e6);
  const double height = 0.1 - 0.5 * 1800 * 9.81 * 0.01 / 1e6;
  std::printf(
      "equilibrium stage to rest (mean speed < 1e-4 m/s for 0.02 s): %ld steps undamped (%s, %.3g s), "
      "%ld steps with local damping 0.7 (%s, %.3g s)\n",
      undamped.steps, undamped.ended_by.c_str(), undamped.end_time, damped.steps, damped.ended_by.c_str(),
      damped.end_time);
  std::printf(
      "damped: U = %.6g (exact %.6g), W_g = %.6g, damping work %.6g, KE %.3g, height %.7g (exact %.7g)\n",
      row1.at("strain_energy"), U, row1.at("gravity_work"), row1.at("damping_work"),
      row1.at("kinetic_energy"), damped.height_end, height);
  EXPECT_EQ(damped.ended_by, "rest");
  EXPECT_LT(damped.steps, undamped.steps);
  EXPECT_EQ(row0.count("damping_work"), 0u);  // the column exists only when a stage is damped
  EXPECT_GT(row1.at("damping_work"), 0.0);
  EXPECT_NEAR(row1.at("strain_energy"), U, 0.01 * U);
  EXPECT_NEAR(damped.height_end, height, 2e-5);
  const double balance = row1.at("kinetic_energy") + row1.at("strain_energy") + row1.at("damping_work");
  EXPECT_NEAR(balance, row1.at("gravity_work"), 0.01 * row1.at("gravity_work"));
  EXPECT_NEAR(row1.at("total_energy"), 0.0, 0.01 * row1.at("gravity_work"));
}

// The same with contact (Paper III §C.2.7): the column and a lid on it as two bodies in
// frictional contact, each damped on its own nodes (not at the interface, where the contact
// phase changes the velocities afterwards). Damped, the stage ends at rest in fewer steps and
// the damping does positive work. The energy balance is printed, not asserted: with the lid
// ringing on the column the contact's bookkeeping misses (undamped +24 % of the gravity work
// after 1 s, damped -4.0 %; docs/studies/2026-11-25-contact-and-damping-energy-defect.md), an open defect of
// the contact work. The damping's work is what the points lose to it (damping_work_at_points: sum_p m_p dt
// d_p . (v_p + dt/2 a_p) at the points). Booked at the nodes, with the lumped mass of the nodes that a GIMP
// domain barely reaches (where d_i ~ f_i / m_i), the Thesis fig. 4.7 cantilever's balance missed by +89 %
// (FLIP) and -51 % (XPIC) of the gravity work; measured now 3.5e-6 and 8.2e-4.
TEST(Stages, LocalDampingWorkIsWhatThePointsLoseWithGimp) {
  for (const char* transfer : {"flip", "xpic"}) {
    const auto r = skred::test::run_text(
        skred::test::thesis_cantilever(
            std::string("interpolation = \"gimp\"\nvelocity_transfer = \"") + transfer + "\"",
            "local_damping = 0.3"),
        1, "cantilever.toml");
    std::printf("damped GIMP cantilever, %s: damping work %.4f J/m of W_g %.4f J/m, balance %+.2e\n",
                transfer, r.row.at("damping_work"), r.row.at("gravity_work"), r.balance());
    EXPECT_TRUE(r.result.completed) << transfer;
    EXPECT_GT(r.row.at("damping_work"), 0.0) << transfer;
    EXPECT_LT(std::abs(r.balance()), 0.01) << transfer;
  }
}

TEST(Stages, LocalDampingWithContactBringsTheStageToRestSooner) {
  const auto run = [](double alpha, const std::string& name) {
    return run_stage(column_text(fmt_stage(alpha) + R"(
[[body]]
name = "lid"
material = "soil"
shape = "rectangle"
min = [0.0, 0.1]
max = [0.02, 0.11]
[[contact]]
bodies = ["column", "lid"]
friction = 0.3
)"),
                     name);
  };
  const auto [undamped, row0] = run(0.0, "contact_undamped");
  const auto [damped, row1] = run(0.7, "contact_damped");
  std::printf(
      "column + lid in contact, to rest: %ld steps undamped (%s, %.3g s), %ld with local damping 0.7 (%s, "
      "%.3g s); undamped: W_g %.6g, total %.3g; damped: W_g %.6g, U %.6g, damping work %.6g, contact work "
      "%.3g, "
      "total %.3g\n",
      undamped.steps, undamped.ended_by.c_str(), undamped.end_time, damped.steps, damped.ended_by.c_str(),
      damped.end_time, row0.at("gravity_work"), row0.at("total_energy"), row1.at("gravity_work"),
      row1.at("strain_energy"), row1.at("damping_work"), row1.at("contact_work"), row1.at("total_energy"));
  EXPECT_EQ(damped.ended_by, "rest");
  EXPECT_LT(damped.steps, undamped.steps);
  EXPECT_GT(row1.at("damping_work"), 0.0);
}

TEST(Sweep, OneRowPerValueAndBadKeysNamed) {
  const fs::path dir = temp_dir("sweep");
  fs::create_directories(dir);
  const fs::path file = dir / "column.toml";
  std::ofstream(file) << column_text("end_time = 0.01\n[output]\ninterval = 0.01\n");
  SweepOptions o;
  o.axes = {{"material[soil].young", {1e6, 4e6}}};
  o.progress = false;
  const auto rows = run_sweep(file.string(), dir / "out", o);
  ASSERT_EQ(rows.size(), 2u);
  const std::string table = read(dir / "out" / "sweep.csv");
  EXPECT_EQ(table.rfind("material[soil].young,status,folder,steps,", 0), 0u) << table;
  EXPECT_NE(table.find("\n1000000,completed,run_000,"), std::string::npos) << table;
  EXPECT_NE(table.find("\n4000000,completed,run_001,"), std::string::npos) << table;
  EXPECT_TRUE(fs::exists(dir / "out" / "run_001" / "summary.json"));
  // The stiffer column's time step is shorter: more steps for the same end time.
  EXPECT_GT(rows[1].steps, rows[0].steps);
  o.axes[0].key = "material[clay].young";
  try {
    run_sweep(file.string(), dir / "out2", o);
    ADD_FAILURE() << "no error for an unknown material";
  } catch (const ScenarioError& e) {
    EXPECT_NE(std::string(e.what()).find("material[clay].young"), std::string::npos) << e.what();
  }
  o.axes[0] = {"material[0].young", {1e6, -1.0}};  // validated before any run starts
  EXPECT_THROW(run_sweep(file.string(), dir / "out3", o), ScenarioError);
  EXPECT_FALSE(fs::exists(dir / "out3" / "run_000"));
  fs::remove_all(dir);
}

// The values of --set: lists and ranges, without the rounding noise of FROM + k STEP, and a
// grid of several keys (the first slowest); malformed input named.
TEST(Sweep, SetValuesAndGrid) {
  const SweepAxis a = parse_sweep_axis("material[sand].friction=0.1:0.3:0.1,0.7");
  EXPECT_EQ(a.key, "material[sand].friction");
  ASSERT_EQ(a.values.size(), 4u);
  EXPECT_EQ(a.values[2], 0.3);  // 0.1 + 2 * 0.1 is 0.30000000000000004
  EXPECT_EQ(a.values[3], 0.7);
  const auto grid = sweep_grid({{"a", {1, 2}}, {"b", {10, 20, 30}}});
  ASSERT_EQ(grid.size(), 6u);
  EXPECT_EQ(grid[1], (std::vector<double>{1, 20}));
  EXPECT_EQ(grid[3], (std::vector<double>{2, 10}));
  for (const char* bad : {"friction", "=1,2", "k=", "k=1:2", "k=1:2:", "k=2:1:0.5", "k=1:2:0", "k=abc",
                          "k=1,,2", "k=0:1e9:1", "k=nan"})
    EXPECT_THROW(parse_sweep_axis(bad), std::invalid_argument) << bad;
  EXPECT_THROW(sweep_grid({{"a", {1}}, {"a", {2}}}), std::invalid_argument);
  EXPECT_THROW(sweep_grid({}), std::invalid_argument);
  SweepRow r;
  r.values = {0.3, 2};
  r.status = "completed";
  r.folder = "run_000";
  r.last.name = "slide, dry";
  r.last.runout = 1.0 / 3.0;
  const std::string table = sweep_table({{"a", {}}, {"b", {}}}, {r});
  EXPECT_NE(table.find("\n0.3,2,completed,run_000,0,0,0,\"slide, dry\",,0.333333333333,"), std::string::npos)
      << table;
  EXPECT_NE(table.find(",stop_time,"), std::string::npos);
  EXPECT_NE(table.find(",nan,"), std::string::npos) << table;  // no stop time
}

TEST(Walls, ClosedWallsAreImpenetrableFreeSidesAreNot) {
  // A block thrown at 5 m/s against the x_max wall: a roller wall stops it at the wall (no
  // point passes it); with a free side the run stops as unstable, naming the point that left.
  for (const char* side : {"\"roller\"", "\"free\""}) {
    std::ostringstream t;
    t << R"(
[grid]
size = [1.0, 1.0]
cell_size = 0.05
[[material]]
name = "soil"
model = "tresca"
density = 2000.0
young = 1e6
poisson = 0.3
cohesion = 2000.0
[[body]]
material = "soil"
shape = "rectangle"
min = [0.6, 0.0]
max = [0.9, 0.2]
velocity = [5.0, 0.0]
[boundary]
y_min = "roller"
y_max = "roller"
x_max = )"
      << side << R"(
[solver]
end_time = 0.1
scheme = "usf"
[output]
interval = 0.1
)";
    const Scenario s = parse_scenario(t.str(), "wall.toml");
    const fs::path out = temp_dir("wall");
    RunOptions opt;
    opt.progress = false;
    double x_max = -1.0;  // the largest point position seen before every step
    double vx = 0.0;      // the block's mean x velocity, the last time seen
    opt.edit_points = [&](Particles<2>& P, const ExplicitSolver<2>&) {
      double mv = 0.0, m = 0.0;
      for (std::size_t p = 0; p < P.size(); ++p) {
        x_max = std::max(x_max, P.x[p][0]);
        mv += P.mass[p] * P.v[p][0], m += P.mass[p];
      }
      vx = mv / m;
      return false;
    };
    const RunResult r = run_simulation(s, out, opt);
    if (std::string(side) == "\"roller\"") {
      ASSERT_TRUE(r.completed) << r.message;
      const std::string vtu = read(out / "particles_000001.vtu");
      EXPECT_FALSE(vtu.empty());
      // Thrown at 5 m/s, 0.1 m from the wall at x = 1, the block reached it within 0.02 s and
      // the wall stopped it: its momentum into the wall is gone, not only its points' positions
      // held at the wall (which move_point does for any point a wall node let through).
      std::printf("block at the roller wall: mean vx %.4f m/s at the end (thrown at 5)\n", vx);
      EXPECT_GT(x_max, 1.0 - 0.05);
      EXPECT_LT(std::abs(vx), 0.05 * 5.0);
    } else {
      EXPECT_FALSE(r.completed);
      EXPECT_TRUE(r.left_grid) << r.message;  // a sound point, not an instability
      EXPECT_NE(r.message.find("left the grid (its state is sound"), std::string::npos) << r.message;
      EXPECT_NE(read(out / "summary.json").find("\"status\": \"left_grid\""), std::string::npos);
    }
    fs::remove_all(out);
  }
}
