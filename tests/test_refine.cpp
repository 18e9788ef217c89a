// `skred refine` (run/refine.hpp): a scenario at h and h/2 per velocity transfer, checked on
// reference R4's thrown block, whose sliding distance v0^2 / (2 mu g) does not depend on the cell.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "run/refine.hpp"
#include "scenario/scenario.hpp"
#include "support.hpp"
#include "temp_dir.hpp"

using namespace skred;
namespace fs = std::filesystem;

namespace {

constexpr double g = 9.81, v0 = 1.0, mu = 0.466;

// R4's horizontal variant: an elastic block (c = 70.7 m/s) thrown at v0 along a base of
// friction mu, at rest after v0^2 / (2 mu g) = 0.1094 m and v0 / (mu g) = 0.219 s. A fixed
// time step (c dt / h = 0.18 at 10 mm), which refine halves with the cell.
std::string block_text() {
  return R"(title = "thrown block"
[grid]
size = [0.25, 0.06]
cell_size = 0.01
[[material]]
name = "block"
model = "linear-elastic"
density = 2000.0
young = 1.0e7
poisson = 0.0
[[body]]
name = "block"
material = "block"
particles_per_cell = 2
shape = "rectangle"
min = [0.02, 0.0]
max = [0.1, 0.04]
velocity = [1.0, 0.0]
[initial_stress]
k0 = "poisson"
[gravity]
acceleration = [0.0, -9.81]
[boundary]
y_min = { type = "friction", friction = 0.466 }
[solver]
time_step = 2.5e-5
[[stage]]
name = "throw"
duration = 0.28
[output]
interval = 0.28
)";
}

std::string read(const fs::path& f) {
  std::ifstream in(f);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace

TEST(Refine, HalvesTheCellAndTheStepAndTheBlockSlidesAsR4Says) {
  const fs::path dir = test::fresh_temp_dir("refine");
  fs::create_directories(dir);
  const fs::path file = dir / "block.toml";
  std::ofstream(file) << block_text();
  RefineOptions o;
  o.levels = 2;
  o.transfers = {"xpic", "apic"};
  o.progress = false;
  const auto rows = run_refine(file.string(), dir / "out", o);
  ASSERT_EQ(rows.size(), 4u);
  const double stop = v0 * v0 / (2 * mu * g);
  for (const RefineRow& r : rows) {
    std::printf("%s h %.3f m, dt %.3g s: %ld points, runout %.5f m, largest displacement %.5f m (R4: %.5f)\n",
                r.transfer.c_str(), r.cell_size, r.time_step, r.particles, r.last.runout,
                r.last.max_displacement, stop);
    EXPECT_EQ(r.status, "completed");
    EXPECT_NEAR(r.last.max_displacement, stop, 0.02 * stop);  // R4, within the issue's 2 %
    EXPECT_NEAR(r.last.runout, stop, 0.02 * stop);            // the slide measure sees the same
  }
  for (int k : {0, 2}) {
    EXPECT_EQ(rows[k].cell_size, 0.01);
    EXPECT_EQ(rows[k + 1].cell_size, 0.005);
    EXPECT_EQ(rows[k + 1].time_step, 1.25e-5);                // halved with the cell
    EXPECT_EQ(rows[k + 1].particles, 4 * rows[k].particles);  // the same points per cell
    EXPECT_EQ(rows[k + 1].level, 1);
  }
  EXPECT_EQ(rows[2].transfer, "apic");
  const std::string table = read(dir / "out" / "refine.csv");
  EXPECT_EQ(table.rfind("transfer,level,cell_size,time_step,particles,status,folder,", 0), 0u) << table;
  EXPECT_NE(table.find("\nxpic,0,0.01,2.5e-05,"), std::string::npos) << table;
  EXPECT_NE(table.find("\napic,1,0.005,1.25e-05,"), std::string::npos) << table;
  EXPECT_TRUE(fs::exists(dir / "out" / "run_003" / "summary.json"));
  // Two levels extrapolate nothing: extrapolation.csv holds its header alone.
  EXPECT_EQ(read(dir / "out" / "extrapolation.csv"), extrapolation_table({}));
  // runout_change: the relative change from the level before, of the same transfer.
  std::istringstream lines(table);
  std::string line;
  std::getline(lines, line);
  for (int k = 0; std::getline(lines, line); ++k) {
    std::vector<std::string> f;
    std::stringstream cells(line);
    for (std::string c; std::getline(cells, c, ',');) f.push_back(c);
    ASSERT_GE(f.size(), 12u);
    if (k % 2 == 0) {
      EXPECT_EQ(f[11], "nan");
    } else {
      const double expected = (rows[k].last.runout - rows[k - 1].last.runout) / rows[k - 1].last.runout;
      EXPECT_NEAR(std::stod(f[11]), expected, 1e-9 * std::abs(expected) + 1e-15) << line;
    }
  }
  const std::string verdict = refine_verdict(rows);
  std::printf("%s", verdict.c_str());
  EXPECT_NE(verdict.find("xpic: the last halving (h = 0.01 to 0.005 m)"), std::string::npos) << verdict;
  EXPECT_NE(verdict.find("the transfers' runouts lie within"), std::string::npos) << verdict;
  fs::remove_all(dir);
}

// Bad options are refused before any run, and a transfer that is not one is named with its key.
TEST(Refine, BadOptionsAndTransfersAreRefusedBeforeAnyRun) {
  RefineOptions o;
  o.levels = 1;
  EXPECT_THROW(check_refine_options(o), std::invalid_argument);
  o.levels = 6;
  EXPECT_THROW(check_refine_options(o), std::invalid_argument);
  o.levels = 2;
  o.transfers = {"apic", "apic"};
  EXPECT_THROW(check_refine_options(o), std::invalid_argument);
  const fs::path dir = test::fresh_temp_dir("refine_bad");
  fs::create_directories(dir);
  const fs::path file = dir / "block.toml";
  std::ofstream(file) << block_text();
  o.transfers = {"apic", "pic"};
  o.progress = false;
  try {
    run_refine(file.string(), dir / "out", o);
    ADD_FAILURE() << "no error for velocity_transfer = \"pic\"";
  } catch (const ScenarioError& e) {
    EXPECT_NE(std::string(e.what()).find("velocity_transfer"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(dir / "out" / "run_000"));
  RefineRow coarse;  // a slide that did not move at h: no change to report, and no crash
  coarse.transfer = "xpic";
  coarse.cell_size = 1.0;
  coarse.status = "completed";
  RefineRow fine = coarse;
  fine.level = 1;
  fine.cell_size = 0.5;
  fine.last.runout = 0.3;
  EXPECT_NE(refine_verdict({coarse, fine}).find("xpic: no change of the runout to report"),
            std::string::npos);
  EXPECT_NE(refine_verdict({fine}).find("no change of the runout to report"), std::string::npos);
  EXPECT_TRUE(std::isnan(relative_change(0.0, 1.0)));
  EXPECT_DOUBLE_EQ(relative_change(2.0, 2.5), 0.25);
  fs::remove_all(dir);
}

// A transfer given from outside comes with its own defaults: the shipped soil column sets
// xpic_period, which would refuse "apic"; the override removes it with the transfer, and adds
// [solver] to a scenario that has none.
TEST(Refine, ATransferFromOutsideReplacesTheScenariosTransferKeys) {
  const std::string text = read(fs::path(SKRED_SOURCE_DIR) / "examples" / "soil_column.toml");
  const auto transfer = [&](const std::string& text, const std::string& t) {
    return std::get<Scenario>(
        parse_any_scenario(text, "scenario.toml", {}, {{"solver.velocity_transfer", t}}));
  };
  EXPECT_EQ(std::get<Scenario>(parse_any_scenario(text, "soil_column.toml")).xpic_period, 2.0);
  const Scenario apic = transfer(text, "apic");
  EXPECT_EQ(apic.velocity_transfer, VelocityTransfer::Apic);
  EXPECT_EQ(apic.xpic_period, 0.0);
  EXPECT_EQ(transfer(text, "xpic").xpic_period, 0.0);  // XPIC's own default: every step
  const Scenario by_default = transfer(text, "auto");  // a slide's default: XPIC once per 2 h/c
  EXPECT_EQ(by_default.velocity_transfer, VelocityTransfer::Xpic);
  EXPECT_GT(by_default.xpic_period, 0.0);
  std::string bare = block_text();
  bare.erase(bare.find("[solver]"), std::string("[solver]\ntime_step = 2.5e-5\n").size());
  ASSERT_EQ(bare.find("[solver]"), std::string::npos);
  EXPECT_EQ(transfer(bare, "apic").velocity_transfer, VelocityTransfer::Apic);
}

// A splitting cap given in the scenario grows with the points (4 x per halving in 2D; without
// one the cap is 10 x each run's own initial points), and every level's scenario passes the
// check (`skred refine`: the memory estimate) before the first run starts.
TEST(Refine, ASplittingCapGrowsWithThePointsAndEveryLevelIsCheckedFirst) {
  const fs::path dir = test::fresh_temp_dir("refine_cap");
  fs::create_directories(dir);
  std::string text = block_text();
  text.insert(text.find("shape = \"rectangle\""), "split = true\n");
  text += "[splitting]\nmax_points = 1000\n";
  const fs::path file = dir / "block.toml";
  std::ofstream(file) << text;
  RefineOptions o;
  o.levels = 3;
  o.progress = false;
  std::vector<long> caps;
  std::vector<double> cells;
  o.check = [&](const AnyScenario& s) {
    caps.push_back(std::get<Scenario>(s).splitting.max_points);
    cells.push_back(std::get<Scenario>(s).cell_size);
    if (caps.size() == 3) throw std::runtime_error("refused");
  };
  EXPECT_THROW(run_refine(file.string(), dir / "out", o), std::runtime_error);
  EXPECT_EQ(caps, (std::vector<long>{1000, 4000, 16000}));
  EXPECT_EQ(cells, (std::vector<double>{0.01, 0.005, 0.0025}));
  EXPECT_FALSE(fs::exists(dir / "out" / "run_000"));
  fs::remove_all(dir);
}

// Richardson's extrapolation of the last three sizes, on rows with the soil column's figures of
// docs/studies/2026-11-26-filter-per-unit-time.md ( the default 3.753 / 4.123 / 4.238 m at h = 0.5 /
// 0.25 / 0.125 m) and the 10 m slope's (0.869 / 2.324 / 3.988 m, whose change grows).
TEST(Refine, RichardsonsExtrapolationOfTheLastThreeSizes) {
  const auto series = [](const std::string& transfer, double h, std::vector<double> runout,
                         std::vector<double> work) {
    std::vector<RefineRow> rows;
    for (std::size_t k = 0; k < runout.size(); ++k) {
      RefineRow r;
      r.transfer = transfer;
      r.level = static_cast<int>(k);
      r.cell_size = std::ldexp(h, -static_cast<int>(k));
      r.status = "completed";
      r.last.ended_by = "rest";
      r.last.runout = runout[k];
      r.last.gravity_work = work[k];
      rows.push_back(r);
    }
    return rows;
  };
  std::vector<RefineRow> rows = series("auto", 0.5, {3.753, 4.123, 4.238}, {337.1e3, 357.2e3, 361.7e3});
  const std::vector<RefineRow> slope = series("apic", 1.0, {0.869, 2.324, 3.988}, {1283e3, 1735e3, 1954e3});
  rows.insert(rows.end(), slope.begin(), slope.end());

  const std::vector<RefineExtrapolation> ex = refine_extrapolations(rows);
  ASSERT_EQ(ex.size(), 4u);  // runout and gravity work per transfer
  EXPECT_EQ(ex[0].quantity, "runout");
  EXPECT_DOUBLE_EQ(ex[0].cell_size, 0.125);
  EXPECT_EQ(ex[0].estimate.kind, ConvergenceKind::monotone);
  const double p = std::log(0.370 / 0.115) / std::log(2.0);  // step 3 with r = 2
  EXPECT_NEAR(ex[0].estimate.order, p, 1e-9);
  EXPECT_NEAR(ex[0].estimate.extrapolated, 4.238 + 0.115 / (std::pow(2.0, p) - 1.0), 1e-9);  // step 4
  EXPECT_EQ(ex[1].quantity, "gravity_work");
  EXPECT_EQ(ex[1].estimate.kind, ConvergenceKind::monotone);
  EXPECT_EQ(ex[2].estimate.kind, ConvergenceKind::diverging);  // the slope's runout: +1.455, then +1.664 m
  EXPECT_EQ(ex[3].estimate.kind, ConvergenceKind::monotone);   // its gravity work: +452, then +219 kJ/m

  const std::string verdict = refine_verdict(rows);
  EXPECT_NE(verdict.find("auto: runout over h = 0.5, 0.25, 0.125 m: converges monotonically with apparent "
                         "order p = 1.69 towards 4.28986 m as h -> 0; GCI of the finest 1.53 %"),
            std::string::npos)
      << verdict;
  EXPECT_NE(
      verdict.find("apic: runout over h = 1, 0.5, 0.25 m: the last halving moved it by +1.664 m, the one "
                   "before by +1.455 m (R = 1.14): the changes do not shrink"),
      std::string::npos)
      << verdict;
  // Only one transfer's runout extrapolates, so no line compares them as h -> 0.
  EXPECT_EQ(verdict.find("extrapolated runouts lie within"), std::string::npos) << verdict;

  const std::string table = extrapolation_table(ex);
  EXPECT_EQ(table.substr(0, table.find('\n')),
            "transfer,quantity,cell_size,fine,medium,coarse,kind,ratio,order,extrapolated,approximate_error,"
            "extrapolated_error,gci_fine,next_change");
  EXPECT_NE(table.find("\napic,runout,0.25,3.988,2.324,0.869,diverging,"), std::string::npos) << table;
  EXPECT_EQ(std::count(table.begin(), table.end(), '\n'), 5);

  // A run that did not complete, or two levels only, give no extrapolation.
  rows[1].status = "unstable";
  EXPECT_EQ(refine_extrapolations(rows).size(), 2u);
  EXPECT_TRUE(refine_extrapolations(series("auto", 1.0, {1.0, 2.0}, {1.0, 2.0})).empty());
}
