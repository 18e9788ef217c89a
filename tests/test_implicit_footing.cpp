// A rigid strip footing pressed into weightless Tresca soil (Prandtl 1920; examples/
// footing_prandtl.toml): the limit pressure of a smooth footing is (2 + pi) s_u. The implicit
// integrator drives the footing's nodes with [[prescribed_velocity]] and reads their force; the
// cell-averaged volumetric strain (B-bar) keeps the isochoric plastic flow from locking. Half
// the footing (B/2 = 0.5 m) on a roller axis of symmetry, soil 2.5 m wide and 1.5 m deep.
#include <fmt/core.h>
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <iterator>
#include <map>
#include <numbers>
#include <string>
#include <vector>

#include "run/simulation.hpp"
#include "scenario/scenario.hpp"
#include "support.hpp"
#include "temp_dir.hpp"

using namespace skred;

namespace {

constexpr double kCohesion = 1e4, kHalfWidth = 0.5;
const double kPrandtl = 2.0 + std::numbers::pi;

// examples/footing_prandtl.toml on cells of h, `steps` load steps to the settlement
// 2.5 mm x `end`, with solver.volumetric_strain = `volumetric`.
AnyScenario footing(double h, int steps, double end, const std::string& volumetric) {
  const std::string path = std::string(SKRED_SOURCE_DIR) + "/examples/footing_prandtl.toml";
  return parse_any_scenario(read_scenario_text(path), path,
                            {{"grid.cell_size", h}, {"implicit.load_steps", steps}, {"solver.end_time", end}},
                            {{"solver.volumetric_strain", volumetric}});
}

struct FootingRun {
  test::TempDir dir;
  RunResult result;
  std::vector<std::map<std::string, double>> rows;
  explicit FootingRun(const AnyScenario& s) {
    RunOptions opt;
    opt.progress = false;
    opt.threads = 2;
    result = run_simulation(s, dir.path(), opt);
    rows = test::series_rows(dir / "series.csv");
  }
  // The footing pressure over s_u at row k: the nodes' force on the soil over the half width.
  double q(std::size_t k) const { return -rows[k].at("force_footing_y") / kHalfWidth / kCohesion; }
};

}  // namespace

// On h = B/32 the pressure rises to a plateau within 3 % of (2 + pi) s_u (measured +1.5 % at
// its peak, +1.3 % at the end; B/16 gives +3.3 %, the error halving with h: docs/studies/
// 2026-12-02-prandtl-footing.md); Newton converges every step; the footing's work is the stored
// and dissipated energy (load_work = strain energy + plastic dissipation).
TEST(ImplicitFooting, PrandtlLimitPressureWithinThreePercent) {
  FootingRun run(footing(0.03125, 10, 1.0, "cell-average"));
  ASSERT_TRUE(run.result.completed) << run.result.message;
  ASSERT_EQ(run.rows.size(), 11u);
  double peak = 0.0;
  for (std::size_t k = 0; k < run.rows.size(); ++k) peak = std::max(peak, run.q(k));
  const double last = run.q(run.rows.size() - 1);
  EXPECT_NEAR(peak, kPrandtl, 0.03 * kPrandtl);
  EXPECT_NEAR(last, kPrandtl, 0.03 * kPrandtl);
  EXPECT_GT(run.q(5), 0.95 * kPrandtl);  // the plateau, not a value passed on the way
  EXPECT_LT(std::abs(last - run.q(8)), 0.01 * kPrandtl);
  // The footing does all the work: it is stored or dissipated (the trapezoid of its force).
  const auto& end = run.rows.back();
  const double stored = end.at("strain_energy") + end.at("plastic_dissipation");
  EXPECT_NEAR(end.at("load_work"), stored, 0.005 * stored);
  EXPECT_GT(end.at("plastic_dissipation"), 0.5 * stored);
  // A smooth footing: no horizontal force.
  EXPECT_EQ(end.at("force_footing_x"), 0.0);
  std::ifstream in(run.dir / "summary.json");
  const std::string summary((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string forces = fmt::format("\"forces\": {{\"footing\": [0, {}]}}", end.at("force_footing_y"));
  EXPECT_NE(summary.find(forces), std::string::npos) << summary;
}

// Without the cell average the plastic flow locks: each point's own volumetric strain must
// vanish, and the pressure overshoots (2 + pi) s_u by far (measured +27 % at h = B/16 and
// still rising) where the cell average stays within 4 %.
TEST(ImplicitFooting, PointIntegrationLocksTheCellAverageDoesNot) {
  FootingRun locked(footing(0.0625, 8, 4.0, "point"));
  FootingRun averaged(footing(0.0625, 8, 4.0, "cell-average"));
  ASSERT_TRUE(locked.result.completed) << locked.result.message;
  ASSERT_TRUE(averaged.result.completed) << averaged.result.message;
  const std::size_t last = locked.rows.size() - 1;
  EXPECT_GT(locked.q(last), 1.15 * kPrandtl);
  EXPECT_GT(locked.q(last), locked.q(last - 2));  // still rising: no plateau
  EXPECT_NEAR(averaged.q(last), kPrandtl, 0.04 * kPrandtl);
}
